# The firmware's timing, as its monitor measured it on its microsecond clock (TIM2): every
# pulse's main phase, gap and balancing phase, and the period from one pulse's start to the
# next, equal the configured stimulus within one timer tick (1 us).  Under QEMU's -icount
# (scripts/firmware-emu).  Also: the balancing phase in whole DAC codes, and the charge
# each channel keeps because of that rounding, as the monitor reports it.
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
[[ ${TP_DEVICE:-} == firmware ]] || fail "pty-timing checks the firmware's monitor: run with TP_DEVICE=firmware"
summary() {  # summary FILE: the ranges of the measured periods and phases
  jq -sc '{ periods: (map(.start_us) | [range(1; length) as $i | .[$i] - .[$i - 1]] | [min, max]),
            widths: (map(.width_us) | [min, max]), gaps: (map(.interphase_us) | [min, max]),
            balance: (map(.balance_width_us) | [min, max]) }' "$1"
}
check_timing() {  # check_timing NAME PERIOD_US WIDTH GAP BALANCE COUNT
  local name=$1 period=$2 w=$3 g=$4 b=$5 count=$6
  [[ $(lines "$name.jsonl") -eq $count ]] || fail "$name: $(lines "$name.jsonl") pulses, expected $count"
  jq -se --argjson p "$period" --argjson w "$w" --argjson g "$g" --argjson b "$b" '
    def within1(x; y): ((x - y) | fabs) <= 1;
    (map(.start_us) | [range(1; length) as $i | .[$i] - .[$i - 1]]) as $periods
    | ($periods | all(within1(.; $p)))
      and all(.[]; within1(.width_us; $w) and within1(.interphase_us; $g) and within1(.balance_width_us; $b))
    ' "$name.jsonl" > /dev/null || fail "$name: timing off by more than one tick: $(summary "$name.jsonl")"
  echo "ok: $name: $count pulses, period $period us, phases $w/$g/$b us, each within 1 us: $(summary "$name.jsonl")"
}
# 1. The paper's pulse: 200 Hz, 200 + 200 us.
make_stimulus a.json --frequency 200 --count 100
start_emu --record a.jsonl
stimctl --port "$PORT" < a.json 2> a.err || fail "a: $(cat a.err)"
sleep 0.2
stop_emu
check_timing a 5000 200 0 200 100
check_record a.jsonl "$EXPECTED"
# 2. A gap and a long, low balancing phase, at 500 Hz.
make_stimulus b.json --frequency 500 --width 100 --interphase 50 --balance-width 400 --count 200
start_emu --record b.jsonl
stimctl --port "$PORT" < b.json 2> b.err || fail "b: $(cat b.err)"
sleep 0.2
stop_emu
check_timing b 2000 100 50 400 200
# The balancing codes are whole: -code x 100/400, summing to zero; the charge kept per
# channel is what that rounding leaves, at most one code x 400 us (0.39 nC).
jq -se 'all(.[]; (.net_charge_nC | map(fabs) | max) <= 0.000977 * 400 + 1e-9)' b.jsonl > /dev/null \
  || fail "b: net charge beyond one code of the balancing phase"
# 3. The fastest rate, 1000 Hz, with the emulated board's shortest phase, 50 us (the real
# board's is 20 us: QEMU's core is slower), twice.
make_stimulus c.json --frequency 1000 --width 50 --count 100
start_emu --record c.jsonl
stimctl --port "$PORT" < c.json 2> c.err || fail "c: $(cat c.err)"
sleep 0.2
stop_emu
check_timing c 1000 50 0 50 100
