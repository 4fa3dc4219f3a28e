# Long work shows progress on stderr when it is a terminal (issue 38, finding 11): a line
# rewritten in place ("\rPROGRAM: TEXT, S s\e[K"), counted by the library's own loop, erased
# before the one-line summary; when stderr is not a terminal, not a byte more than the
# summary.  Through a real pseudo-terminal: script(1) runs the program with stderr on one,
# stdout to a file.
command -v script > /dev/null || fail "script(1) is not installed (util-linux)"

# on_terminal NAME COMMAND...: runs COMMAND with stderr on a pty (stdout to NAME.out); what
# the terminal showed goes to NAME.tty, carriage returns as newlines.
on_terminal() {
  local name=$1; shift
  local cmd; printf -v cmd '%q ' "$@"
  script -qefc "$cmd > $name.out" /dev/null < /dev/null > "$name.raw" 2>&1 || fail "$* on a terminal: $(cat "$name.raw")"
  tr '\r' '\n' < "$name.raw" > "$name.tty"
}
# progress NAME PATTERN SUMMARY: the terminal showed at least one progress line matching
# PATTERN (an ERE, the seconds after it), the line erased, then SUMMARY's line; and the
# program without a terminal wrote the same stdout, and on stderr nothing but the summary.
progress() {
  local name=$1 pattern=$2 summary=$3 esc=$'\e'
  grep -qE "^$pattern, [0-9]+\.[0-9] s$esc\[K\$" "$name.tty" || fail "$name: no progress line matching '$pattern': $(cat -v "$name.raw")"
  grep -qE "^$esc\[K$summary" "$name.tty" || fail "$name: the progress line not erased before the summary: $(cat -v "$name.raw")"
  echo "ok: $name on a terminal: $(grep -cE "^$pattern" "$name.tty") progress lines, e.g. $(grep -E "^$pattern" "$name.tty" | tail -1 | cat -v)"
}
# quiet NAME COMMAND...: without a terminal, stdout as on the terminal and stderr the summary only.
quiet() {
  local name=$1; shift
  "$@" > "$name.pipe.out" 2> "$name.err" || fail "$*: $(cat "$name.err")"
  cmp -s "$name.out" "$name.pipe.out" || fail "$name: stdout differs on a terminal"
  if [[ $(wc -l < "$name.err") -ne 1 ]] || grep -q $'[\r\e]' "$name.err"; then
    fail "$name without a terminal: $(cat -v "$name.err")"
  fi
  echo "ok: $name without a terminal: $(cat "$name.err")"
}

bank=(optimize-weights --bank --grid 3x3 --pitch 2 --pad 1x1 --neighbourhood 3 --threads 2)
on_terminal bank "${bank[@]}"
progress bank "optimize-weights: bank [0-9]+ of 12 problems" "optimize-weights: bank of 9 pixels x 3 modes"
grep -qE "^optimize-weights: bank [0-9]+ of 27 patterns judged" bank.tty || fail "bank: no line judging patterns: $(cat -v bank.raw)"
quiet bank "${bank[@]}"

optimize-weights --mode SAI > sai.json 2> /dev/null || fail "optimize-weights"
population=(fiber-threshold --config sai.json --population 2 --threads 2)
on_terminal population "${population[@]}"
progress population "fiber-threshold: population [0-9] of 6 afferents" "fiber-threshold: mrg, 200 us biphasic"
quiet population "${population[@]}"

sd=(fiber-threshold --config sai.json --strength-duration --widths '100,200')
on_terminal sd "${sd[@]}"
progress sd "fiber-threshold: strength-duration 100 us, width 1 of 2" "fiber-threshold: mrg, biphasic"
grep -qE "^fiber-threshold: strength-duration 200 us, width 2 of 2" sd.tty || fail "sd: no second width: $(cat -v sd.raw)"

threshold=(optimize-weights --mode SAI --electrodes 4 --objective threshold --max-evaluations 10)
on_terminal threshold "${threshold[@]}"
progress threshold "optimize-weights: threshold search 1 of at most 10 whole searches" "optimize-weights: SAI threshold ratio"
