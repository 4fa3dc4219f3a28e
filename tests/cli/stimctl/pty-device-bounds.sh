# The host refuses a device it cannot drive safely (exit 2 before configuring, nothing
# delivered): a watchdog longer than its 300 ms safety bound, or shorter than two
# keep-alive periods.  A 16-bit DAC (the emulator's documented maximum) works.
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
make_stimulus stim.json --frequency 200 --duration 0.5
for wd in 1000 301 60 99; do
  start_emu --record "wd$wd.jsonl" --watchdog-ms "$wd"
  rc=0
  stimctl --port "$PORT" < stim.json > out.txt 2> "wd$wd.err" || rc=$?
  sleep 0.1
  stop_emu
  [[ $rc -eq 2 ]] || fail "watchdog $wd ms: exit $rc, expected 2: $(cat "wd$wd.err")"
  [[ ! -s out.txt ]] || fail "watchdog $wd ms: wrote to stdout"
  [[ $(lines "wd$wd.jsonl") -eq 0 ]] || fail "watchdog $wd ms: pulses delivered"
  bound=$([[ $wd -gt 300 ]] && echo 300 || echo 100)
  grep -q "$wd ms" "wd$wd.err" && grep -q "$bound ms" "wd$wd.err" \
    || fail "watchdog $wd ms: the message must name both values: $(cat "wd$wd.err")"
  echo "ok: $(cat "wd$wd.err")"
done
for wd in 100 300; do
  start_emu --record "ok$wd.jsonl" --watchdog-ms "$wd"
  stimctl --port "$PORT" < stim.json 2> "ok$wd.err" || fail "watchdog $wd ms refused: $(cat "ok$wd.err")"
  stop_emu
  [[ $(lines "ok$wd.jsonl") -eq 100 ]] || fail "watchdog $wd ms: $(lines "ok$wd.jsonl") pulses"
done
start_emu --record dac16.jsonl --dac-bits 16
stimctl --port "$PORT" < stim.json 2> dac16.err || fail "16-bit DAC: $(cat dac16.err)"
stop_emu
[[ $(lines dac16.jsonl) -eq 100 ]] || fail "16-bit DAC: $(lines dac16.jsonl) pulses"
check_record dac16.jsonl "$EXPECTED"
echo "ok: 16-bit DAC: $(cat dac16.err)"
