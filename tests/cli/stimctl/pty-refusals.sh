# Refusals leave no pulse in the record: amplitude above the device's limit, zero-sum
# violated, malformed JSON, more channels than the device has.
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
expect_refusal() {  # expect_refusal NAME STIMULUS_FILE [emu options]
  local name=$1 stim=$2; shift 2
  start_emu --record "$name.jsonl" "$@"
  local rc=0
  stimctl --port "$PORT" < "$stim" > out.txt 2> err.txt || rc=$?
  sleep 0.1
  stop_emu
  [[ $rc -eq 2 ]] || fail "$name: exit $rc, expected 2: $(cat err.txt)"
  [[ ! -s out.txt ]] || fail "$name: wrote to stdout"
  [[ $(lines "$name.jsonl") -eq 0 ]] || fail "$name: $(lines "$name.jsonl") pulses delivered"
  echo "ok: $name: $(cat err.txt)"
}
make_stimulus ok.json --frequency 200 --duration 1
AMP=1.5 make_stimulus strong.json --frequency 200 --duration 1
expect_refusal over-device-limit strong.json --max-current 1
expect_refusal too-many-channels ok.json --channels 4
expect_refusal unbalanced "$TP_INPUTS/stimulus-unbalanced.json"
expect_refusal over-host-limit "$TP_INPUTS/stimulus-over-limit.json"
expect_refusal malformed "$TP_INPUTS/malformed.json"
