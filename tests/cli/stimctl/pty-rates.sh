# High rates: every configuration the device accepts is delivered on time, and the rest
# is refused before anything is sent.  A gap, and the off time between one pulse's end
# and the next one's start, must each be at least the device's shortest phase (its
# min_width_us: 10 us on stim-emu, 50 us on the emulated firmware), in which it loads the
# next phase's codes.  The host refuses what breaks that (exit 2, one line, nothing
# delivered); the device refuses it too (raw-frames).  What is accepted is delivered, and
# the pulse count reported is the count delivered.  Against the firmware the monitor's
# measured timing is checked too: every period and phase within one tick (1 us).
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
min=10
[[ ${TP_DEVICE:-} == firmware ]] && min=50
start_emu --record rec.jsonl
# 1. Refused by the host: 300 + 100 + 599 us at 1000 Hz leaves 1 us between pulses; an
# off time one below the shortest phase; a gap below it.
refuse() {  # refuse NAME EXPECTED_MESSAGE MAKE-PULSE-OPTIONS...
  local name=$1 msg=$2; shift 2
  make_stimulus "$name.json" "$@"
  local rc=0
  stimctl --port "$PORT" < "$name.json" > "$name.out" 2> "$name.err" || rc=$?
  [[ $rc -eq 2 ]] || fail "$name: exit $rc: $(cat "$name.err")"
  [[ $(wc -l < "$name.err") -eq 1 && ! -s $name.out ]] || fail "$name: not one line: $(cat "$name.err" "$name.out")"
  grep -q "$msg" "$name.err" || fail "$name: $(cat "$name.err")"
  echo "ok: $name refused: $(cat "$name.err")"
}
refuse off-1us "off time of 1 us between pulses" \
  --frequency 1000 --width 300 --interphase 100 --balance-width 599 --count 50
refuse off-short "off time of $((min - 1)) us" \
  --frequency 1000 --width 300 --interphase 100 --balance-width $((600 - min + 1)) --count 50
refuse gap-short "interphase gap of $((min - 1)) us" \
  --frequency 1000 --width 300 --interphase $((min - 1)) --balance-width 400 --count 50
# 2. Refused by the device as well, whatever the host: configure with 1 us between pulses.
rate_config() {  # rate_config PERIOD WIDTH GAP BALANCE: 8 channels, 50 pulses
  echo "$(le32 $((0x7A7E0001)))$(le32 "$1")$(le16 "$2")$(le16 "$3")$(le16 "$4")08$(le32 50)"
}
{ echo "send 1 2 $(rate_config 1000 300 100 599)"
  echo "send 2 2 $(rate_config 1000 300 $((min - 1)) 400)"
  echo "send 3 2 $(rate_config 1000 300 100 $((600 - min)))"
  echo "send 4 5 $(le32 $((0x7A7E0001)))"; } | raw-frames "$PORT" > acks.txt || fail "raw-frames: $(cat acks.txt)"
result() { awk -v s="$1" '$1 == s { r = $2 } END { print r }' acks.txt; }
[[ $(result 1) == 3 && $(result 2) == 3 ]] || fail "the device accepted a short off time or gap: $(cat acks.txt)"
[[ $(result 3) == 0 ]] || fail "the device refused an off time of its shortest phase: $(cat acks.txt)"
echo "ok: the device refuses 1 us between pulses and a $((min - 1)) us gap (out_of_range), accepts $min us"
# 3. Accepted at the edge: 1000 Hz, 300 + 100 + (600 - min) us: min us between pulses,
# 300 pulses: the count of issue 20's case (300/100/500 us), with less time between
# pulses than it leaves.
# Delivered, every pulse counted, none lost, and the host's keep-alives answered
# throughout (stimctl fails on 6 unanswered attempts, or when the stimulus has not ended
# 1 s after its duration): under QEMU the firmware's monitor line for every pulse must not
# slow the emulated board (firmware/README.md, "The board and QEMU").
n=300
make_stimulus edge.json --frequency 1000 --width 300 --interphase 100 --balance-width $((600 - min)) --count $n
stimctl --port "$PORT" < edge.json 2> edge.err || fail "edge: $(cat edge.err)"
sleep 0.2
stop_emu
[[ $(lines rec.jsonl) -eq $n ]] || fail "edge: $(lines rec.jsonl) pulses delivered, expected $n"
grep -q ": $n of $n pulses on 8 channels" edge.err || fail "edge: reported $(cat edge.err)"
jq -se 'map(.t_s) | . as $t | [range(1; length) | $t[.] - $t[. - 1]] | all(fabs - 0.001 | fabs < 1e-9)' rec.jsonl > /dev/null \
  || fail "edge: slots not 1 ms apart"
if [[ ${TP_DEVICE:-} == firmware ]]; then
  # The monitor's measurements: every pulse 500 us after its slot (the engine's delay),
  # periods 1000 us, phases as configured, each within one tick.
  jq -se --argjson b $((600 - min)) '
    def within1(x; y): ((x - y) | fabs) <= 1;
    all(.[]; within1(.start_us - .t_s * 1e6; 500) and within1(.width_us; 300)
             and within1(.interphase_us; 100) and within1(.balance_width_us; $b))
    and (map(.start_us) | . as $s | [range(1; length) | $s[.] - $s[. - 1]] | all(within1(.; 1000)))
    ' rec.jsonl > /dev/null \
    || fail "edge: late or off by more than a tick: $(jq -sc 'map(.start_us - .t_s * 1e6) | [min, max]' rec.jsonl)"
  echo "ok: 1000 Hz, 300/100/$((600 - min)) us: $n pulses, each on time within 1 us"
fi
echo "ok: $(tail -1 edge.err)"
