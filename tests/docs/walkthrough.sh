# The README's walk-through as a new user runs it (issue 38): its code blocks, in order, as
# written, from a clone into a folder of the user's own outside it, and their outputs
# checked.  The quick start's block runs in a stand-in for the clone (its build, data and
# scripts) with a HOME of its own, less the two lines that build (this build is the one
# under test); every block after it runs where the quick start leaves the user, with only
# the PATH and PYTHONPATH it exports.  Changed, each said when made: calibrate's person is
# a scripted observer (--responses -, with short trials); the install block is left to the
# install tests; and no block may use a path into the clone (data/images/, scripts/).  Sourced by tests/cli/check (fail, $work).
: "${TP_BUILD:?}" "${TP_SOURCE:?}"
here=$TP_SOURCE/tests/docs
t=$work/t  # the test's own files
mkdir -p "$t"
python3 "$here/blocks.py" "$TP_SOURCE/README.md" "$t/blocks" > "$t/blocks.txt" || fail "README.md: $(cat "$t/blocks.txt")"
root=$work/clone home=$work/home
mkdir -p "$root" "$home"
ln -s "$TP_BUILD" "$root/build"
ln -s "$TP_SOURCE/data" "$root/data"
ln -s "$TP_SOURCE/scripts" "$root/scripts"
lines_of() { grep -c '' "$1"; }

# The user's shell: no build on PATH until the quick start puts it there.
export PATH=/usr/local/bin:/usr/bin:/bin HOME=$home
unset PYTHONPATH
# calibrate's person: a scripted observer with hidden thresholds and comfort limits (mA).
observe() {
  rm -f "$t/prompts"
  mkfifo "$t/prompts"
  python3 "$here/observer.py" RA:0.2:0.5 SAI:0.15:0.4 PC:0.25:0.6 < "$t/prompts" |
    "$@" --responses - --trial-duration 0.05 2> "$t/prompts"
}
export -f observe
export t here

quick=0 ran=0 previous_err=
while read -r n lang; do
  block=$t/blocks/$n.$lang
  case $lang in
    out)  # a program's output: the block before printed it (times aside)
      [[ -n $previous_err ]] || fail "README block $n: output with no command before it"
      mask() { sed -E 's/[0-9]+(\.[0-9]+)? s\b/T s/g' "$1"; }
      diff <(mask "$block") <(mask "$previous_err") > "$t/out.diff" ||
        fail "README block $n: the output differs from what the commands printed: $(cat "$t/out.diff")"
      echo "ok: block $n: the output shown is what the commands print"
      continue ;;
    python)
      if [[ ${TP_PYTHON_BUILT:-} != ON ]]; then echo "note: block $n (Python): the module is not built here"; continue; fi
      /usr/bin/python3 "$block" > "$t/py.$n.out" 2> "$t/py.$n.err" || fail "README block $n (Python): $(tail -3 "$t/py.$n.err")"
      head -1 "$t/py.$n.out" | grep -E '^0\.102[0-9]+ \(141, 1001\)$' > /dev/null || fail "README block $n printed $(head -1 "$t/py.$n.out")"
      sed -n 2p "$t/py.$n.out" | grep -F "'pulses': 200," | grep -F "'end': 'stimulus complete'" > /dev/null ||
        fail "README block $n: delivered $(sed -n 2p "$t/py.$n.out")"
      echo "ok: block $n (Python): $(head -1 "$t/py.$n.out")"
      ran=$((ran + 1)); continue ;;
    sh) ;;
    *) fail "README block $n: a block in $lang, which this test does not know" ;;
  esac
  if grep -q '^scripts/demo' "$block"; then  # the quick start, in the clone
    grep -q '^scripts/test' "$block" || fail "README block $n: the quick start without scripts/test"
    { grep -v -e '^scripts/demo' -e '^scripts/test' "$block" || true; } > "$t/quick.sh"
    cd "$root"
    # shellcheck disable=SC1091
    source "$t/quick.sh" || fail "README block $n: the quick start failed"
    [[ $PWD != "$TP_SOURCE"* && $PWD != "$root"* ]] || fail "the quick start leaves the user in the clone ($PWD)"
    [[ $(command -v calibrate) == "$root/build/tools/calibrate" ]] || fail "the quick start's PATH gives calibrate as $(command -v calibrate)"
    [[ $(command -v tp-plot-render) == "$root/build/tools/tp-plot-render" ]] || fail "no tp-plot-render on the quick start's PATH"
    if command -v man > /dev/null; then
      [[ $(man -w calibrate) == "$root/build/tools/man/man1/calibrate.1.gz" ]] || fail "man -w calibrate: $(man -w calibrate 2>&1)"
      [[ $(man -w 7 tactile-primaries) == "$root/build/tools/man/man7/tactile-primaries.7.gz" ]] || fail "man -w 7 tactile-primaries"
      MANWIDTH=100 man calibrate 2> /dev/null | grep -F -- "--responses" > /dev/null || fail "man calibrate lacks --responses"
      echo "ok: man calibrate from the build tree"
    fi
    [[ $(find "$root" -mindepth 1 | wc -l) -eq 3 ]] || fail "the quick start left in the clone: $(ls "$root")"
    echo "ok: block $n, the quick start: PATH, PYTHONPATH, the work folder $PWD"
    quick=1; continue
  fi
  [[ $quick == 1 ]] || fail "README block $n comes before the quick start"
  if grep -q '^cmake --install' "$block"; then echo "ok: block $n (installing) is the install tests'"; continue; fi
  sed -E 's/^calibrate /observe calibrate /' "$block" > "$t/run.sh"
  cmp -s "$block" "$t/run.sh" || echo "note: block $n: calibrate answered by a scripted observer"
  ! grep -q -e 'data/images/' -e '^scripts/' "$t/run.sh" ||
    fail "README block $n uses a path into the clone (data/images/, scripts/): $(cat "$block")"
  SECONDS=0
  bash -euo pipefail "$t/run.sh" > "$t/sh.$n.out" 2> "$t/sh.$n.err" ||
    fail "README block $n failed: $(cat "$block") -> $(tail -3 "$t/sh.$n.err")"
  previous_err=$t/sh.$n.err
  echo "ok: block $n ran in $SECONDS s: $(head -1 "$block")"
  ran=$((ran + 1))
done < "$t/blocks.txt"
[[ $quick == 1 && $ran -ge 4 ]] || fail "the README's walk-through: quick start $quick, $ran blocks run"

# What the blocks made, in the folder of the user's own: nothing else, and nothing anywhere in the clone.
[[ $(find "$root" -mindepth 1 | wc -l) -eq 3 ]] || fail "the walk-through left in the clone: $(ls "$root")"
# The mix: RA at 30 Hz and SAI at 200 Hz, delivered for 2 s; then RA faded by five frames.
jq -e '[.patterns[] | [.mode, .pulse.frequency_hz, .amplitude_mA]] == [["RA", 30, 0.8], ["SAI", 200, 1.2]]' \
  ra-sai-mix.json > /dev/null || fail "ra-sai-mix.json: $(head -c 300 ra-sai-mix.json)"
grep -F "460 of 460 pulses on 8 channels of 2 patterns" "$t"/sh.*.err > /dev/null || fail "the mix: $(cat "$t"/sh.*.err)"
grep -E "of 2 patterns, .*, 5 live frames, .*; end of input; output stopped" "$t"/sh.*.err > /dev/null ||
  fail "the fade: $(cat "$t"/sh.*.err)"
# The picture: the profile from the observer's hidden values, the delivered record, the plot.
for p in RA:0.2:0.5 SAI:0.15:0.4 PC:0.25:0.6; do
  IFS=: read -r name threshold comfort <<< "$p"
  jq -e --arg p "$name" --argjson t "$threshold" --argjson c "$comfort" '.primaries[$p] |
      (.threshold_mA / $t) > 0.85 and (.threshold_mA / $t) < 1.15 and
      (.comfort_mA / $c) > 0.85 and (.comfort_mA / $c) < 1.15' profile.json > /dev/null ||
    fail "profile.json's $name: $(jq -c --arg p "$name" '.primaries[$p]' profile.json), hidden $threshold and $comfort mA"
done
[[ $(lines_of trials.csv) -gt 30 ]] || fail "trials.csv: $(lines_of trials.csv) lines"
[[ $(lines_of face.jsonl) -gt 100 ]] || fail "face.jsonl: $(lines_of face.jsonl) pulses"
[[ $(head -c 4 face-delivered.png | tail -c 3) == PNG ]] || fail "face-delivered.png is not a PNG"
jq -e '.patterns | length > 10' bar.json > /dev/null || fail "bar.json: $(head -c 200 bar.json)"
echo "ok: the walk-through from $PWD: $(ls | tr '\n' ' ')"
# Had they been made at the clone's root instead, git would not see them (.gitignore).
if git -C "$TP_SOURCE" rev-parse --git-dir > /dev/null 2>&1; then
  for f in *; do
    git -C "$TP_SOURCE" check-ignore -q --no-index "$f" || fail "$f, made at the clone's root, is not in .gitignore"
  done
  echo "ok: .gitignore covers what the walk-through makes"
fi
