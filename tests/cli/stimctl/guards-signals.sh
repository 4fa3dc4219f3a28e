# Shutdown during the skin's modes (issue 41, "Shutdown"): SIGINT and SIGTERM stop the
# output first (exit 128 + signal, no pulse after stimctl exits), and SIGKILL leaves it to
# the device's watchdog (300 ms: at most ~60 pulses at 200 Hz, then none), while stimctl
# holds the sensation under a sweat ramp, and while a pattern is suspended on a lifted pad
# (--contact-loss suspend), on stim-emu's real pseudo-terminal with a skin.
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
make_stimulus stim.json --frequency 200 --duration 60
jq '.reference_impedance_kohm = [.currents_mA[] | if . == 0 then null else 7.24 end]' stim.json > held.json
skin() {  # FILE EVENTS
  printf '{"format": "tactile-primaries/skin/1", "electrode": {"rs_kohm": 1.0, "rp_kohm": 50.0, "cp_nf": 30.0}, "events": %s}\n' "$2" > "$1"
}
skin hold-skin.json '[{"t_s": 0, "channels": "all", "rp_kohm": 10, "ramp_s": 5}]'
skin suspend-skin.json '[{"t_s": 0.2, "channels": [2], "contact": 0}]'
for mode in hold suspend; do
  flags=(--hold-sensation) input=held.json
  [[ $mode == suspend ]] && flags=(--contact-loss suspend) input=stim.json
  for sig in INT TERM KILL; do
    start_emu --record "$mode-$sig.jsonl" --skin "$mode-skin.json"
    env --default-signal stimctl --port "$PORT" "${flags[@]}" < "$input" 2> "$mode-$sig.err" &
    host=$!
    sleep 0.5
    kill -s "$sig" "$host"
    rc=0
    wait "$host" 2> /dev/null || rc=$?
    at_exit=$(lines "$mode-$sig.jsonl")
    sleep 0.5
    later=$(lines "$mode-$sig.jsonl")
    sleep 0.3
    last=$(lines "$mode-$sig.jsonl")
    stop_emu
    [[ $rc -eq $((128 + $(kill -l "$sig"))) ]] || fail "$mode, SIG$sig: exit $rc: $(cat "$mode-$sig.err")"
    [[ $at_exit -gt 40 ]] || fail "$mode, SIG$sig: only $at_exit pulses before the signal"
    if [[ $sig == KILL ]]; then
      (( later - at_exit <= 70 && last == later )) \
        || fail "$mode, SIGKILL: $((later - at_exit)) pulses after the kill, then $((last - later)) more: the watchdog did not stop it"
    else
      [[ $at_exit -eq $later ]] || fail "$mode, SIG$sig: pulses continued after stimctl exited ($at_exit -> $later)"
      grep -q "output stopped" "$mode-$sig.err" || fail "$mode, SIG$sig: no summary: $(cat "$mode-$sig.err")"
    fi
    # Suspended: the pattern was at the probe when the signal came.
    if [[ $mode == suspend ]]; then
      jq -se '.[-1].currents_mA | map(fabs) | max <= 0.051' "$mode-$sig.jsonl" > /dev/null \
        || fail "suspend, SIG$sig: the last pulse was not a probe: $(tail -1 "$mode-$sig.jsonl")"
    fi
    echo "ok: $mode, SIG$sig -> exit $rc after $at_exit pulses, $((later - at_exit)) after"
  done
done
