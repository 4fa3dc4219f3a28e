# Records and logs written as they go (issue 38, finding 8): a full device is an error that
# stops the output, never ignored (stimctl --record and --latency-log, stim-emu's --record and
# --event-log on /dev/full: exit 1 naming the file), and a record killed mid-run by SIGKILL
# ends in a whole line (it was cut at a 4096-byte buffer's edge), every line JSON.
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
make_stimulus stim.json --frequency 200 --duration 1
make_stimulus long.json --frequency 200 --duration 60

# stimctl's in-process emulator: the record fails at the first pulse; the output stops.
refuses 1 --stdin stim.json \
  --says "stimctl: --record: cannot write '/dev/full': No space left on device; output stopped" \
  -- stimctl --port emu --record /dev/full
# The live latency log fails at the first frame.
echo '{"amplitudes": [0.5]}' > frames.jsonl
refuses 1 --stdin frames.jsonl --says "stimctl: --latency-log: cannot write '/dev/full': No space left on device" \
  -- stimctl --port emu --live --stimulus stim.json --latency-log /dev/full

# stim-emu on a pty: its record (at the first pulse) or its event log (at the start) cannot
# be written: it stops the output and exits 1 by itself, naming the file; the host finds
# the device gone.
for log in --record --event-log; do
  start_emu "$log" /dev/full
  rc=0
  stimctl --port "$PORT" < stim.json 2> host.err || rc=$?
  [[ $rc -eq 1 ]] || fail "stim-emu $log /dev/full: the host exited $rc: $(cat host.err)"
  for _ in $(seq 500); do kill -0 "$EMU_PID" 2> /dev/null || break; sleep 0.01; done
  kill -0 "$EMU_PID" 2> /dev/null && fail "stim-emu $log /dev/full: still running 5 s after the host: $(cat "$work/emu.err")"
  rc=0
  wait "$EMU_PID" || rc=$?
  [[ $rc -eq 1 ]] || fail "stim-emu $log /dev/full: exit $rc: $(cat "$work/emu.err")"
  grep -qxF "stim-emu: $log: cannot write '/dev/full': No space left on device" "$work/emu.err" \
    || fail "stim-emu $log /dev/full said: $(cat "$work/emu.err")"
  echo "ok: stim-emu $log /dev/full: exit 1, $(tail -1 "$work/emu.err"); the host: $(tail -1 host.err)"
done

# whole_lines FILE: at least 40 lines, the last ending in a newline, every one a JSON object.
whole_lines() {
  local n; n=$(lines "$1")
  [[ $n -ge 40 ]] || fail "$1: only $n lines"
  [[ $(tail -c 1 "$1" | od -An -c | tr -d ' ') == '\n' ]] || fail "$1: its last line is cut: $(tail -c 120 "$1")"
  jq -e 'type == "object"' "$1" > /dev/null 2> jq.err || fail "$1: not whole JSON lines: $(cat jq.err)"
  echo "ok: $1: $n whole lines, $(wc -c < "$1") bytes"
}
# wait_for_bytes FILE N: until FILE holds at least N bytes (at most 10 s).
wait_for_bytes() {
  for _ in $(seq 1000); do [[ -f $1 && $(wc -c < "$1") -ge $2 ]] && return; sleep 0.01; done
  fail "$1: fewer than $2 bytes after 10 s"
}

# stimctl --record killed mid-run by SIGKILL (0.13 s after 12 KiB, 3 buffers' worth).
stimctl --port emu --record killed.jsonl < long.json 2> /dev/null &
host=$!
wait_for_bytes killed.jsonl 12288
sleep 0.13
kill -KILL "$host"
wait "$host" 2> /dev/null || true
whole_lines killed.jsonl

# stim-emu's record, the emulator killed by SIGKILL mid-run.
start_emu --record emu-killed.jsonl
stimctl --port "$PORT" < long.json 2> /dev/null &
host=$!
wait_for_bytes emu-killed.jsonl 12288
sleep 0.13
kill -KILL "$EMU_PID"
wait "$host" 2> /dev/null || true
whole_lines emu-killed.jsonl
