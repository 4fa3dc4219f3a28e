# calibrate through a real terminal (tmux: send-keys and capture-pane), against stim-emu on
# a pty, with a scripted observer who reads each trial's delivered current from the
# emulator's record: "felt it?" yes above a hidden threshold, "too strong?" yes above a
# hidden comfort limit.  For three hidden pairs the profile's SAI threshold and comfort lie
# within the staircase's final step (a factor of sqrt(1.25)) of the hidden ones, and no
# pulse exceeds the ceiling.  Then q during a long trial stops the output within one pulse
# period (10 Hz: 100 ms) of the key, by the emulator's clock.  The terminal shows the
# session's length up front and each staircase as it starts; stderr ends with a summary.
# Esc, after a trial and during one, is named as the key that stopped it.
source "$TP_SOURCE/tests/cli/render-tactile/common.sh"
command -v tmux > /dev/null || skip TP_REQUIRE_TMUX "tmux is not installed (scripts/setup installs it)"
sock=tp-calibrate-$$
tmux_() { tmux -L "$sock" "$@"; }
trap 'tmux_ kill-server 2> /dev/null || true; cleanup' EXIT  # and the harness's own

# observe HIDDEN_THRESHOLD HIDDEN_COMFORT: answers every prompt until calibrate ends.
observe() {
  local thr=$1 comfort=$2 last=0 seen=0
  for ((turn = 0; turn < 20000; ++turn)); do
    [[ -e rc ]] && return 0
    local line
    line=$(tmux_ capture-pane -p -t cal | grep -E '^trial [0-9]+: .*(felt it|too strong)\? \[y/n\] *$' | tail -1 || true)
    if [[ -n $line ]]; then
      local n=${line#trial }; n=${n%%:*}
      if ((n > last)); then
        # This trial's pulses: the record's new lines (wait for stim-emu's flush).
        local total level
        for _ in $(seq 100); do total=$(lines rec.jsonl); ((total > seen)) && break; sleep 0.01; done
        sleep 0.02; total=$(lines rec.jsonl)
        level=$(tail -n +$((seen + 1)) rec.jsonl | jq -s 'map(.currents_mA | map(fabs) | max) | max')
        seen=$total
        local limit=$thr; [[ $line == *"too strong"* ]] && limit=$comfort
        ((n == 1)) && tmux_ capture-pane -p -S - -t cal > pane.txt
        if awk -v l="$level" -v h="$limit" 'BEGIN { exit !(l > h) }'; then tmux_ send-keys -t cal y; else tmux_ send-keys -t cal n; fi
        last=$n
      fi
    fi
    sleep 0.01
  done
  fail "the observer gave up (calibrate still running)"
}

cal=(calibrate --bank "$BANK" --log log.csv --primaries SAI --ceiling 1)
for pair in "0.13 0.3" "0.31 0.62" "0.55 0.9"; do
  read -r thr comfort <<< "$pair"
  rm -f rc rec.jsonl prof.json
  start_emu --channels "$CHANNELS" --record rec.jsonl
  tmux_ new-session -d -s cal -x 160 -y 40 \
    "${cal[*]} --trial-duration 0.05 --port $PORT > prof.json 2> err.txt; echo \$? > rc"
  observe "$thr" "$comfort"
  stop_emu
  [[ $(cat rc) == 0 ]] || fail "calibrate exited $(cat rc): $(cat err.txt)"
  jq -e --argjson t "$thr" --argjson c "$comfort" '.primaries.SAI as $r
      | ($r.threshold_mA / $t | log | fabs) <= (1.25 | sqrt | log) + 1e-9
      and ($r.comfort_mA / $c | log | fabs) <= (1.25 | sqrt | log) + 1e-9' prof.json > /dev/null \
    || fail "hidden $thr and $comfort mA: profile $(jq -c .primaries prof.json)"
  peak=$(jq -s 'map(.currents_mA | map(fabs) | max) | max' rec.jsonl)
  awk -v p="$peak" 'BEGIN { exit !(p <= 1 + 0.000977) }' || fail "a pulse of $peak mA, above the 1 mA ceiling"
  [[ $(($(lines log.csv) - 1)) == $(jq '.primaries.SAI.trials' prof.json) ]] || fail "log rows against the profile's trials"
  grep -qE "^calibrate: SAI at 1 pixel: 2 staircases, about [0-9]+ trials of 0.05 s, at most 160$" pane.txt \
    && grep -qF "calibrate: SAI, primary 1 of 1, at pixel (4, 4), 1 of 1: the threshold, felt it?" pane.txt \
    || fail "the terminal before trial 1: $(cat pane.txt)"
  summary=$(jq -r '.primaries.SAI | "calibrate: \(.trials) trials; SAI threshold \(.threshold_mA * 1e4 | round / 1e4) mA, comfort \(.comfort_mA * 1e4 | round / 1e4) mA"' prof.json)
  [[ $(tail -1 err.txt) == "$summary" ]] || fail "the summary: '$(tail -1 err.txt)', expected '$summary'"
  echo "ok: hidden $thr, $comfort mA -> $(jq -c .primaries.SAI prof.json); peak $peak mA; $(grep -oE 'about [0-9]+ trials' pane.txt) said; $(tail -1 err.txt)"
done

# Esc at the first question, then during a trial: named as Esc (before: "(q)").
rm -f rc
start_emu --channels "$CHANNELS"
tmux_ new-session -d -s cal -x 160 -y 40 \
  "${cal[*]} --trial-duration 0.05 --port $PORT > prof.json 2> err.txt; echo \$? > rc"
for _ in $(seq 500); do tmux_ capture-pane -p -t cal | grep -qF 'felt it? [y/n]' && break; sleep 0.01; done
tmux_ send-keys -t cal Escape
for _ in $(seq 500); do [[ -e rc ]] && break; sleep 0.01; done
[[ $(cat rc) == 1 ]] || fail "Esc: calibrate exited $(cat rc 2> /dev/null)"
[[ $(tail -1 err.txt) == "calibrate: stopped by the user (Esc) after trial 1; nothing running" ]] \
  || fail "Esc: $(cat err.txt)"
echo "ok: Esc at the question: $(tail -1 err.txt)"
rm -f rc events.txt
stop_emu
start_emu --channels "$CHANNELS" --event-log events.txt
tmux_ new-session -d -s cal -x 160 -y 40 \
  "${cal[*]} --trial-duration 10 --rates SAI:10 --port $PORT > prof.json 2> err.txt; echo \$? > rc"
for _ in $(seq 500); do grep -q '^start' events.txt 2> /dev/null && break; sleep 0.01; done
tmux_ send-keys -t cal Escape
for _ in $(seq 500); do [[ -e rc ]] && break; sleep 0.01; done
[[ $(cat rc) == 1 ]] || fail "Esc during a trial: calibrate exited $(cat rc 2> /dev/null)"
[[ $(tail -1 err.txt) == "calibrate: stopped by the user (Esc) during trial 1; output stopped" ]] \
  || fail "Esc during a trial: $(cat err.txt)"
grep -q '^stop' events.txt || fail "Esc during a trial: no stop in $(cat events.txt)"
stop_emu
echo "ok: Esc during a trial: $(tail -1 err.txt)"

# q during a 10 s trial at 10 Hz, 0.6 s in: from just before tmux sends the key (the
# shell's $EPOCHREALTIME, no process started in between) to the device's stop frame (the
# emulator's event log, CLOCK_REALTIME), within one pulse period, 100 ms.  That includes
# the tmux client's start and the key's way through the pty.
rm -f rc rec.jsonl
start_emu --channels "$CHANNELS" --record rec.jsonl --event-log events.txt
tmux_ new-session -d -s cal -x 160 -y 40 \
  "${cal[*]} --trial-duration 10 --rates SAI:10 --start 0.2 --port $PORT > prof.json 2> err.txt; echo \$? > rc"
for _ in $(seq 500); do grep -q '^start' events.txt 2> /dev/null && break; sleep 0.01; done
sleep 0.6
t_q=$EPOCHREALTIME
tmux_ send-keys -t cal q
for _ in $(seq 500); do [[ -e rc ]] && break; sleep 0.01; done
sleep 0.1
stop_emu
[[ $(cat rc) == 1 ]] || fail "q: calibrate exited $(cat rc 2> /dev/null)"
grep -q "stopped by the user (q) during trial 1" err.txt || fail "q: $(cat err.txt)"
[[ -s prof.json ]] && fail "q: a profile was written"
read -r t_start t_stop < <(awk '$1 == "start" { s = $3 } $1 == "stop" { e = $3 } END { print s, e }' events.txt)
last=$(jq -s 'map(.t_s) | max' rec.jsonl)
awk -v q="$t_q" -v e="$t_stop" -v s="$t_start" -v l="$last" 'BEGIN {
  stop = (e / 1e9 - q) * 1e3; tail = (s / 1e9 + l - q) * 1e3
  printf "q -> stop %.1f ms, the last pulse %.1f ms after q\n", stop, tail
  exit !(stop <= 100 && tail <= 100) }' > q.txt || fail "q: $(cat q.txt)"
echo "ok: $(cat q.txt); $(lines rec.jsonl) pulses of 100; $(cat err.txt)"
