# calibrate with answers from a pipe (--responses -): q stops after the first trial (one
# trial delivered, no profile); someone who never feels anything gets no profile and a log
# of every trial, none above the ceiling; someone who feels everything is stopped at the
# floor, and told so.  A program that answers (a coprocess reading the prompts) gets its
# hidden levels, the session's length up front, each staircase as it starts and a summary
# at the end; its log's answers, given again, give the same trials and profile.
source "$TP_SOURCE/tests/cli/render-tactile/common.sh"
cal=(calibrate --bank "$BANK" --primaries SAI --trial-duration 0.05 --responses - --port emu --emu-channels 64)
echo q | "${cal[@]}" --log q.csv --record q.jsonl > q.json 2> q.err && fail "q: exit 0"
grep -q "stopped by the user (q) after trial 1" q.err || fail "q: $(cat q.err)"
[[ ! -s q.json ]] || fail "q: a profile was written"
[[ $(lines q.csv) -eq 1 && $(lines q.jsonl) -eq 10 ]] || fail "q: $(lines q.csv) log lines, $(lines q.jsonl) pulses"
echo "ok: q after one trial of 10 pulses: $(tail -1 q.err)"
yes n | head -1000 | "${cal[@]}" --ceiling 0.5 --log none.csv --record none.jsonl > none.json 2> none.err && fail "never felt: exit 0"
grep -qF "SAI at pixel (4, 4): not felt up to the ceiling, 0.5 mA; no threshold" none.err || fail "never felt: $(cat none.err)"
[[ $(tail -1 none.err) == "calibrate: no primary found (said above): no profile; the log has every trial" ]] \
  || fail "never felt: $(tail -1 none.err)"
[[ ! -s none.json ]] || fail "never felt: a profile was written"
peak=$(jq -s 'map(.currents_mA | map(fabs) | max) | max' none.jsonl)
last=$(tail -1 none.csv | cut -d, -f7)
awk -v p="$peak" -v l="$last" 'BEGIN { exit !(p <= 0.5 + 0.000977 && l == 0.5) }' || fail "never felt: peak $peak mA, last level $last"
echo "ok: never felt: $(($(lines none.csv) - 1)) trials up to the 0.5 mA ceiling (peak $peak mA)"
# Felt every time: down to the floor, where three "yes" end it, said as such (before: 80
# trials, then "no threshold found up to the ceiling").
yes y | head -1000 | "${cal[@]}" --log all.csv > all.json 2> all.err && fail "always felt: exit 0"
grep -qF "SAI at pixel (4, 4): felt 3 times in a row at the floor, 0.001 mA" all.err || fail "always felt: $(cat all.err)"
grep -q "ceiling" all.err && fail "always felt: the ceiling named: $(grep ceiling all.err)"
[[ $(tail -3 all.csv | cut -d, -f7 | sort -u) == 0.001 && $(lines all.csv) -lt 60 ]] \
  || fail "always felt: $(($(lines all.csv) - 1)) trials, the last at $(tail -3 all.csv | cut -d, -f7 | tr '\n' ' ')"
echo "ok: always felt: $(($(lines all.csv) - 1)) trials, the last three at the floor"

# observe THRESHOLD COMFORT CALIBRATE...: calibrate (--responses -) as a coprocess, its
# prompts on stderr answered from the level each names: "felt it?" yes above THRESHOLD,
# "too strong?" yes above COMFORT.  Everything it said goes to said.txt.
observe() {
  local thr=$1 comfort=$2; shift 2
  coproc CAL { "$@" 2>&1; }
  local pid=$CAL_PID out=${CAL[0]} in=${CAL[1]} chunk="" level limit
  : > said.txt
  while IFS= read -r -d ']' -u "$out" chunk; do
    printf '%s]' "$chunk" >> said.txt
    [[ $chunk =~ ([0-9.]+)\ mA\ \.\.\.\ (felt\ it|too\ strong)\?\ \[y/n$ ]] || continue
    level=${BASH_REMATCH[1]} limit=$thr
    [[ ${BASH_REMATCH[2]} == "too strong" ]] && limit=$comfort
    if awk -v l="$level" -v h="$limit" 'BEGIN { exit !(l > h) }'; then echo y; else echo n; fi >&"$in"
  done
  printf '%s' "$chunk" >> said.txt
  wait "$pid"
}
observe 0.2 0.5 "${cal[@]}" --log seen.csv --output seen.json || fail "observed: $(tail -2 said.txt)"
jq -e '.primaries.SAI as $r | ($r.threshold_mA / 0.2 | log | fabs) <= (1.25 | sqrt | log) + 1e-9
    and ($r.comfort_mA / 0.5 | log | fabs) <= (1.25 | sqrt | log) + 1e-9' seen.json > /dev/null \
  || fail "observed 0.2 and 0.5 mA: $(jq -c .primaries seen.json)"
# The model's threshold beside the person's: fiber-threshold's for the SAI pattern at the
# centre pixel (pad 27 of the 8 x 8 bank), through its peak, at calibrate's pulse.
jq '.pixels[27].patterns.SAI as $p | .weights = $p.weights
    | .focus = {x_mm: $p.peak.x_mm, z_mm: $p.peak.z_mm} | del(.pixels, .bank)' "$BANK" > sai27.json
fiber-threshold --config sai27.json > th.json 2> th.err || fail "fiber-threshold: $(cat th.err)"
jq -e --slurpfile t th.json '(.primaries.SAI.model_threshold_mA / $t[0].thresholds.receptors.SAI.threshold_mA - 1
    | fabs) < 1e-9' seen.json > /dev/null \
  || fail "model_threshold_mA $(jq .primaries.SAI.model_threshold_mA seen.json), fiber-threshold's $(jq .thresholds.receptors.SAI.threshold_mA th.json)"
# Up front, from the procedure's own numbers; each staircase as it starts; the summary.
n=$(($(lines seen.csv) - 1))
grep -qE "^calibrate: SAI at 1 pixel: 2 staircases, about [0-9]+ trials of 0.05 s, at most 160$" said.txt \
  || fail "the session's length: $(head -1 said.txt)"
about=$(grep -oE 'about [0-9]+' said.txt | cut -d' ' -f2)
((about * 2 > n && about < n * 2)) || fail "about $about trials, $n taken"
grep -qF "calibrate: SAI, primary 1 of 1, at pixel (4, 4), 1 of 1: the threshold, felt it?" said.txt \
  && grep -qF "calibrate: SAI, primary 1 of 1, at pixel (4, 4), 1 of 1: the comfort limit, too strong?" said.txt \
  || fail "the stages: $(grep -v ^trial said.txt)"
summary=$(jq -r '.primaries.SAI | "calibrate: \(.trials) trials; SAI threshold \(.threshold_mA * 1e4 | round / 1e4) mA, comfort \(.comfort_mA * 1e4 | round / 1e4) mA"' seen.json)
[[ $(tail -1 said.txt) == "$summary" ]] || fail "the summary: '$(tail -1 said.txt)', expected '$summary'"
echo "ok: observed 0.2 and 0.5 mA: about $about trials said, $n taken; $(tail -1 said.txt)"
# The log's answers again (docs/calibration.md): the same trials, the same profile.
tail -n +2 seen.csv | cut -d, -f9 | "${cal[@]}" --log again.csv --output again.json 2> /dev/null \
  || fail "the log's answers again"
cmp -s seen.csv again.csv && cmp -s seen.json again.json || fail "the log's answers again: another session"
echo "ok: the log's answers again: the same $n trials and profile"
# With a bank that carries recruitment (here made by hand: 4 SAI-mode afferents a class at
# pad 27, reference 0.1 mA), the same answers give the same thresholds and each mode's
# colour at the person's comfort limit: the fractions at 0.1 x comfort / threshold mA.
jq '.recruitment = {population: 4, pulse: {width_us: 200, interphase_us: 0, balance_width_us: 200}, modes: {SAI: {pad: 27, reference_mA: 0.1,
      thresholds_mA: {RA: [0.05, 0.2, 0.3, null], SAI: [0.02, 0.1, 0.15, 0.4], PC: [0.3, 0.5, 0.9, null]}}}}' \
  "$BANK" > rbank.json
cal_r=("${cal[@]}"); cal_r[2]=rbank.json
tail -n +2 seen.csv | cut -d, -f9 | "${cal_r[@]}" --log colour.csv --output colour.json 2> colour.err \
  || fail "with recruitment: $(cat colour.err)"
jq -e --slurpfile b rbank.json '.primaries.SAI as $r | ($b[0].recruitment.modes.SAI) as $m
    | (0.1 * $r.comfort_mA / $r.threshold_mA) as $at
    | [$m.thresholds_mA.RA, $m.thresholds_mA.SAI, $m.thresholds_mA.PC]
    | map(map(select(. != null and . <= $at)) | length / 4) == $r.colour' colour.json > /dev/null \
  || fail "the SAI colour: $(jq -c .primaries.SAI colour.json)"
echo "ok: with recruitment, SAI's colour $(jq -c .primaries.SAI.colour colour.json)"
# On an emulator with a skin (issue 41, item 6): the same answers give the same profile,
# and each pad's impedance at the threshold's trials (the mean of their readings: Rp 50
# kOhm, 30 nF, so 1 + 50 (1 - e^(-w/1500)) kOhm at calibrate's 200 us, within 0.05: at 200
# Hz the interface, tau 1.5 ms, is not quite discharged between pulses), null where a pad
# carried nothing.  make-pulse --profile carries them into the stimulus, and stimctl
# --hold-sensation takes it; from a profile without them, it is refused.
printf '{"format": "tactile-primaries/skin/1", "electrode": {"rs_kohm": 1.0, "rp_kohm": 50.0, "cp_nf": 30.0}}\n' > skin.json
tail -n +2 seen.csv | cut -d, -f9 | "${cal[@]}" --emu-skin skin.json --log z.csv --output z.json 2> z.err \
  || fail "with a skin: $(cat z.err)"
jq -e --slurpfile s seen.json '.primaries.SAI.threshold_mA == $s[0].primaries.SAI.threshold_mA' z.json > /dev/null \
  || fail "with a skin: another threshold"
jq -e --slurpfile b "$BANK" '.primaries.SAI.impedance_kohm as $z | ($b[0].pixels[] | select(.pad == 36) | .patterns.SAI.weights) as $w
    | ($z | length) == 64
    and all(range(0; 64); if $w[.] == 0 then $z[.] == null
                          else (($z[.] - (1 + 50 * (1 - ((-200 / 1500) | exp)))) | fabs) < 0.05 end)' z.json > /dev/null \
  || fail "the profile's impedances: $(jq -c .primaries.SAI.impedance_kohm z.json)"
# The pattern at the pixel calibrated, (4, 4): pad 36.
jq '(.pixels[] | select(.pad == 36) | .patterns.SAI) as $p | .weights = $p.weights
    | .focus = {x_mm: $p.peak.x_mm, z_mm: $p.peak.z_mm} | .mode = "SAI" | del(.pixels, .bank)' "$BANK" > sai36.json
make-pulse --profile z.json --intensity 0.5 --frequency 20 --duration 0.5 < sai36.json > held.json 2> /dev/null || fail "make-pulse --profile"
jq -e --slurpfile z z.json '.reference_impedance_kohm == $z[0].primaries.SAI.impedance_kohm' held.json > /dev/null \
  || fail "make-pulse did not carry the impedances: $(jq -c .reference_impedance_kohm held.json)"
stimctl --port emu --emu-channels 64 --emu-skin skin.json --hold-sensation < held.json 2> held.err \
  || fail "--hold-sensation: $(cat held.err)"
grep -q "sensation held" held.err || fail "--hold-sensation: $(cat held.err)"
make-pulse --profile seen.json --intensity 0.5 --frequency 20 --duration 0.5 < sai36.json > noz.json 2> /dev/null || fail "make-pulse"
refuses 2 --stdin noz.json --says "--hold-sensation: the stimulus has no reference impedance for channel" \
  -- stimctl --port emu --emu-channels 64 --emu-skin skin.json --hold-sensation
echo "ok: with a skin, the profile's impedances: $(jq -c '[.primaries.SAI.impedance_kohm[] | select(. != null)]' z.json)"
# Bad input before anything is sent.
refuses 2 --says "calibrate: --ceiling: 2.5 mA outside (0, 2] mA" -- calibrate --bank "$BANK" --log x.csv --ceiling 2.5 --responses -
refuses 2 --says "calibrate: --start: 1.5 mA outside [0.001, 1] mA" -- calibrate --bank "$BANK" --log x.csv --start 1.5 --responses -
refuses 2 --says "--pixel" -- calibrate --bank "$BANK" --log x.csv --pixel 8,0 --responses -
refuses 2 --says "not a primary" -- calibrate --bank "$BANK" --log x.csv --primaries XY --responses -
refuses 2 --says "--responses" -- calibrate --bank "$BANK" --log x.csv --responses file.txt
refuses 2 --says "--record" -- calibrate --bank "$BANK" --log x.csv --port /dev/ttyS99 --record r.jsonl
refuses 2 --says "give one" -- calibrate --bank "$BANK" --log x.csv --pixel 1,1 --per-pixel --responses -
refuses 2 --says "not a bank" -- calibrate --bank "$TP_INPUTS/sai-weights.json" --log x.csv --responses -
refuses 2 --says "--log: cannot open '/nonexistent/dir/x.csv'" -- calibrate --bank "$BANK" --log /nonexistent/dir/x.csv --responses -
refuses 2 --says "--output: cannot write '/nonexistent/dir/p.json'" -- calibrate --bank "$BANK" --log x.csv --output /nonexistent/dir/p.json --responses -
refuses 2 --says "could not find" -- calibrate --bank "$BANK" --log x.csv --pixel 0,0 --primaries PC --responses -
refuses 2 --says "--trial-duration" -- calibrate --bank "$BANK" --log x.csv --trial-duration 20 --responses -
# The bank's own current limit bounds the ceiling (found by the review).
jq '.max_current_mA = 0.5' "$BANK" > low-bank.json
refuses 2 --says "above the bank's current limit" -- calibrate --bank low-bank.json --log x.csv --ceiling 1 --responses -
