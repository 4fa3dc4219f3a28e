# The gap between different patterns' pulses, as the firmware measures it (issue 38: two
# 1000 Hz patterns measured 98-99 us against 100): pattern B's slot is exactly pattern A's
# pulse and the gap after A's, so every B pulse is due the gap after A's measured end.  The
# monitor's start_us and phase widths are the edges as the engine measured them (1 us
# ticks); no measured gap may be below the table's.
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
[[ ${TP_DEVICE:-} == firmware ]] || fail "run with TP_DEVICE=firmware (the record's measured edges)"
make_stimulus a.json --frequency 100 --width 200 --balance-width 200 --duration 1
make_stimulus b.json --frequency 100 --width 200 --balance-width 200 --duration 1
mix-stimuli --gap 100 --phase 0,500 a.json b.json > ab.json 2> mix.err || fail "mix-stimuli: $(cat mix.err)"
start_emu --record gap.jsonl
stimctl --port "$PORT" < ab.json 2> gap.err || fail "stimctl: $(cat gap.err)"
sleep 0.2
stop_emu
[[ $(lines gap.jsonl) -eq 200 ]] || fail "$(lines gap.jsonl) pulses recorded, expected 200"
gaps=$(jq -sce '[range(1; length) as $k | .[$k - 1] as $a | .[$k] as $b | select($a.pattern != $b.pattern)
  | $b.start_us - ($a.start_us + $a.width_us + $a.interphase_us + $a.balance_width_us)]
  | [min, max, length]' gap.jsonl) || fail "record: $gaps"
jq -e '.[0] >= 100 and .[2] >= 199' <<< "$gaps" > /dev/null ||
  fail "measured gaps between patterns [min, max, count]: $gaps us, the table's is 100"
echo "ok: gaps between the patterns' pulses, measured [min, max, count]: $gaps us; $(cat gap.err)"
