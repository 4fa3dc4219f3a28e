# SIGINT and SIGTERM stop the output first, then stimctl exits 128 + signal.
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
make_stimulus stim.json --frequency 200 --duration 60
for sig in INT TERM; do
  start_emu --record "$sig.jsonl"
  stimctl --port "$PORT" < stim.json 2> "$sig.err" &
  host=$!
  sleep 0.5
  kill -"$sig" "$host"
  rc=0
  wait "$host" || rc=$?
  at_exit=$(lines "$sig.jsonl")
  sleep 0.5
  later=$(lines "$sig.jsonl")
  stop_emu
  want=$([[ $sig == INT ]] && echo 130 || echo 143)
  [[ $rc -eq $want ]] || fail "SIG$sig: exit $rc, expected $want: $(cat "$sig.err")"
  [[ $at_exit -eq $later ]] || fail "SIG$sig: pulses continued after stimctl exited ($at_exit -> $later)"
  grep -q "output stopped" "$sig.err" || fail "SIG$sig: no summary: $(cat "$sig.err")"
  echo "ok: SIG$sig -> exit $rc after $at_exit pulses; $(head -1 "$sig.err")"
done
