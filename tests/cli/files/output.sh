# --output FILE (issue 38, finding 8; docs/programs.md, "Files"): every program that writes
# one document writes to FILE exactly the bytes it writes on stdout, and nothing on stdout;
# on /dev/full it fails (exit 1, nothing on stdout, its last line naming the file); a FILE
# in a missing directory is refused (exit 2) before any work; a run that fails leaves a
# previous FILE as it was; and no temporary is ever left beside a FILE.

# writes_whole PROGRAM [--stdin FILE] -- COMMAND...: the four cases above for one command.
writes_whole() {
  local program=$1 stdin=/dev/null; shift
  [[ $1 == --stdin ]] && { stdin=$2; shift 2; }
  shift  # --
  "$@" < "$stdin" > want.out 2> /dev/null || fail "$*: exit $?"
  [[ -s want.out ]] || fail "$*: nothing on stdout"
  rm -f got.out
  "$@" --output got.out < "$stdin" > stdout.txt 2> err.txt || fail "$* --output: $(cat err.txt)"
  [[ ! -s stdout.txt ]] || fail "$* --output: wrote to stdout: $(head -c 200 stdout.txt)"
  cmp -s want.out got.out || fail "$* --output: other bytes than on stdout"
  local rc=0
  "$@" --output /dev/full < "$stdin" > stdout.txt 2> err.txt || rc=$?
  [[ $rc -eq 1 ]] || fail "$* --output /dev/full: exit $rc: $(cat err.txt)"
  [[ ! -s stdout.txt ]] || fail "$* --output /dev/full: wrote to stdout"
  [[ $(tail -1 err.txt) == "$program: --output: cannot write '/dev/full': No space left on device" ]] \
    || fail "$* --output /dev/full said: $(cat err.txt)"
  [[ $(grep -c "cannot write" err.txt) -eq 1 ]] || fail "$* --output /dev/full: $(cat err.txt)"
  # Refused at once: no output, and no work (the commands' work takes from 0.1 s to
  # seconds, fiber-threshold's below: minutes).
  refuses 2 --stdin "$stdin" --says "--output: cannot write 'missing/doc': No such file or directory" \
    -- "$@" --output missing/doc
  echo "ok: $program: --output: $(wc -c < got.out) bytes as on stdout; /dev/full: $(tail -1 err.txt)"
}

optimize-weights --mode SAI > sai.json 2> /dev/null || fail "optimize-weights"
make-pulse --amplitude 1 --input sai.json > sai-stim.json 2> /dev/null || fail "make-pulse"
make-pulse --amplitude 0.8 --frequency 30 --input sai.json > ra-stim.json 2> /dev/null || fail "make-pulse"
optimize-weights --bank --grid 2x2 --pitch 2 --pad 1x1 > bank.json 2> /dev/null || fail "optimize-weights --bank"
cat > profile.json << 'JSON'
{"format": "tactile-primaries/profile/1",
 "primaries": {"RA": {"threshold_mA": 0.4, "comfort_mA": 1.0},
               "SAI": {"threshold_mA": 0.3, "comfort_mA": 0.9},
               "PC": {"threshold_mA": 0.5, "comfort_mA": 1.2}}}
JSON
echo '{"rgb": [[255, 0, 0], [0, 200, 0], [0, 0, 0], [0, 0, 0]]}' > frames.jsonl

writes_whole af-field -- af-field --electrodes 4 --pitch 1 --x -1:1:0.5 --y 0.5:1:0.5
writes_whole af-field -- af-field --grid 2x2 --pitch 2 --pad 1x1 --plane-depth 0.9 --x -1:1:1 --z-grid -1:1:1
writes_whole af-field -- af-field --config sai.json --summary
writes_whole optimize-weights -- optimize-weights --mode SAI
writes_whole optimize-weights -- optimize-weights --mode RA,SAI --format csv
writes_whole optimize-weights -- optimize-weights --bank --grid 2x2 --pitch 2 --pad 1x1
writes_whole fiber-threshold -- fiber-threshold --config sai.json --population 1
writes_whole make-pulse -- make-pulse --amplitude 1 --input sai.json
writes_whole make-pulse -- make-pulse --amplitude 1 --input sai.json --format csv
writes_whole mix-stimuli -- mix-stimuli ra-stim.json sai-stim.json
writes_whole render-tactile --stdin frames.jsonl -- render-tactile --bank bank.json --profile profile.json --sequence -
writes_whole render-tactile --stdin frames.jsonl -- render-tactile --bank bank.json --profile profile.json --sequence - --plan
# The missing directory before minutes of work (6000 afferents): at once.
start=$SECONDS
refuses 2 --says "--output: cannot write 'missing/doc'" -- fiber-threshold --config sai.json --population 2000 --output missing/doc
[[ $((SECONDS - start)) -lt 20 ]] || fail "the missing directory was refused only after $((SECONDS - start)) s"

# Live frames go to stdout as they are due: no document to write whole.
render-tactile --bank bank.json --profile profile.json --sequence - < frames.jsonl > seq.json 2> /dev/null || fail "render-tactile --sequence"
refuses 2 --stdin frames.jsonl --says "--output: --frames writes live frames to stdout as they are due" \
  -- render-tactile --bank bank.json --profile profile.json --frames seq.json - --output frames.out
[[ ! -e frames.out ]] || fail "render-tactile --frames --output left frames.out"

# A run that fails (bad input found after the file was opened, a runtime failure) leaves a
# previous file as it was.
echo previous > kept.json
refuses 2 --says "--mode: required" -- optimize-weights --output kept.json
refuses 2 --says "--amplitude" -- make-pulse --amplitude 3 --input sai.json --output kept.json
rc=0
fiber-threshold --config sai.json --population 1 --recruitment /dev/full --output kept.json > stdout.txt 2> err.txt || rc=$?
[[ $rc -eq 1 && ! -s stdout.txt ]] || fail "--recruitment /dev/full: exit $rc: $(cat err.txt)"
[[ $(tail -1 err.txt) == "fiber-threshold: --recruitment: cannot write '/dev/full': No space left on device" ]] \
  || fail "--recruitment /dev/full said: $(cat err.txt)"
[[ $(cat kept.json) == previous ]] || fail "a failed run changed kept.json: $(head -c 200 kept.json)"

# No temporary left anywhere, whatever ended each run.
left=$(find . -maxdepth 1 -name '.?*' -printf '%f ')
[[ -z $left ]] || fail "temporaries left: $left"
echo "ok: a failed run kept the previous file; no temporary left"
