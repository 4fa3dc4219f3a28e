# A message quotes user text with its control characters (C0, DEL, C1) and any byte that is
# not UTF-8 escaped as \xNN (\n, \r, \t as such): a terminal shown the message does nothing
# but print it, and the line is UTF-8 (Python's exceptions need it).  Valid UTF-8 is kept.
clean() {
  LC_ALL=C grep -q $'[\x01-\x09\x0b-\x1f\x7f]' "$work/err" &&
    fail "raw control bytes in: $(od -c "$work/err" | head -5)"
  [[ $(tr -cd '\000' < "$work/err" | wc -c) -eq 0 ]] || fail "a NUL in: $(od -c "$work/err" | head -5)"
  iconv -f UTF-8 -t UTF-8 "$work/err" > /dev/null 2>&1 || fail "not UTF-8: $(od -c "$work/err" | head -5)"
  LC_ALL=C grep -q $'\xc2[\x80-\x9f]' "$work/err" && fail "a C1 control in: $(od -c "$work/err" | head -5)"
  return 0
}
# argv, in tp's own messages: an escape sequence, a control byte, a byte that is not UTF-8
refuses 2 --says "--model: unknown conductor model 'x\x1B[31m\x01\xFF'" -- af-field --model $'x\e[31m\x01\xff'
clean
refuses 2 --says "--model: unknown conductor model 'a\nb\tc\r'" -- af-field --model $'a\nb\tc\r'
clean
refuses 2 --says "--model: unknown conductor model 'C1 \xC2\x9B, kept: é µ'" -- af-field --model $'C1 \xc2\x9b, kept: é µ'
clean
refuses 2 --says "--config: cannot open '/nonexistent/\xFF\xFE.json'" -- af-field --config $'/nonexistent/\xff\xfe.json'
clean
# ... in CLI11's
refuses 2 --says "The following argument was not expected: --bo\x01gus" -- af-field $'--bo\x01gus'
clean
# ... and from a file: a NUL and a terminal's clear-screen in a JSON key (\u0000\u001b)
refuses 2 --stdin "$TP_INPUTS/document-nul-key.json" --says "array: unknown key 'pitch\x00\x1B[2J'" -- af-field --config - --summary
clean
# ... in another program's path, and a number's text
refuses 2 --says "--recruitment: cannot write '/nonexistent/\x1B]0;title\x07'" -- \
  fiber-threshold --config "$TP_INPUTS/sai-weights.json" --population 1 --recruitment $'/nonexistent/\e]0;title\a'
clean
refuses 2 --says "--pitch: not a number '1\x7F'" -- optimize-weights --mode SAI --pitch $'1\x7f'
clean
echo "ok: every message escaped, one line of UTF-8"
