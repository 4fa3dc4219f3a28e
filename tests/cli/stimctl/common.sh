# Shared by the stimctl scripts: a stimulus from the SAI weights, and record checks.
AMP=1.0
make_stimulus() {  # make_stimulus FILE [make-pulse options]
  local f=$1; shift
  make-pulse --amplitude "$AMP" "$@" < "$TP_INPUTS/sai-weights.json" > "$f" 2> /dev/null || fail "make-pulse"
}
# check_record FILE EXPECTED_JSON_ARRAY: every pulse's currents equal the expected ones
# within 1.5 DAC steps (12-bit over +-2 mA: 0.977 uA a step), sum to zero, balance charge.
check_record() {
  local rec=$1 expected=$2
  jq -se --argjson exp "$expected" '
    (map(.currents_mA as $c | [range(0; $exp | length)] | map(($c[.] - $exp[.]) | fabs) | max) | max) as $dev
    | (map(.currents_mA | add | fabs) | max) as $sum
    | (map(.net_charge_nC | map(fabs) | max) | max) as $q
    | if $dev <= 0.0015 and $sum <= 1e-9 and $q <= 1e-9 then true
      else error("deviation \($dev) mA, sum \($sum) mA, net charge \($q) nC") end' "$rec" > /dev/null \
    || fail "record $rec: $(jq -se --argjson exp "$expected" 'map(.currents_mA) | .[0]' "$rec" 2>&1 | tr -d '\n ')"
}
EXPECTED='[0, 0, -0.5, 1, -0.5, 0, 0, 0]'

# Raw protocol fields, as hex for raw-frames: le16 N and le32 N (little-endian), codes C...
# (a set_weights body: the count, then each code), config TOKEN CHANNELS (a configure
# body: 200 Hz, 200 us + 200 us, no pulse limit).
le16() { printf '%02x%02x' $(($1 & 255)) $((($1 >> 8) & 255)); }
le32() { printf '%02x%02x%02x%02x' $(($1 & 255)) $((($1 >> 8) & 255)) $((($1 >> 16) & 255)) $((($1 >> 24) & 255)); }
codes() { local n=$#; printf '%02x' "$n"; for c in "$@"; do le16 $((c & 0xFFFF)); done; }
config() {
  echo "$(le32 "$1")$(le32 5000)$(le16 200)$(le16 0)$(le16 200)$(printf '%02x' "$2")$(le32 0)"
}

# A mix of RA at 30 Hz and SAI at 200 Hz (mix-stimuli), 2 s: make_mix FILE [mix-stimuli options]
make_mix() {
  local f=$1; shift
  make-pulse --amplitude 0.8 --frequency 30 --duration 2 < "$TP_INPUTS/ra-weights.json" > ra.json 2> /dev/null || fail "make-pulse RA"
  make-pulse --amplitude 1.2 --frequency 200 --duration 2 < "$TP_INPUTS/sai-weights.json" > sai.json 2> /dev/null || fail "make-pulse SAI"
  mix-stimuli ra.json sai.json "$@" > "$f" 2> mix.err || fail "mix-stimuli: $(cat mix.err)"
}
# check_mix_record REC MIX COUNTS: the schedule from the record alone.  COUNTS is a JSON
# list of [least, most] pulses per pattern.  Each pulse: its pattern's currents within one
# DAC step (0.977 uA) and summing to zero; its slot (t_s - slip) on its pattern's phase +
# k x period; slip at most 1 ms; no two pulses overlapping, different patterns' at least
# the gap apart (measured, where the record carries measured starts).
check_mix_record() {
  local rec=$1 mix=$2 counts=$3
  jq -se --slurpfile m "$mix" --argjson counts "$counts" '
    ($m[0]) as $mix | $mix.gap_us as $gap
    | ($mix.patterns | map({c: .currents_mA, T: (1e6 / .pulse.frequency_hz | round), ph: .phase_us})) as $p
    | (group_by(.pattern) | map(length)) as $n
    | (if ($n | length) != ($counts | length) then error("patterns seen: \($n)") else . end)
    | (range(0; $n | length) as $i | if $n[$i] < $counts[$i][0] or $n[$i] > $counts[$i][1]
         then error("pattern \($i): \($n[$i]) pulses, expected \($counts[$i])") else empty end),
      (map(. as $r | $p[$r.pattern].c as $c
         | [range(0; $c | length) | (($r.currents_mA[.] - $c[.]) | fabs)] | max) | max
         | if . > 0.000978 then error("a current \(.) mA from its weights x amplitude") else empty end),
      (map(.currents_mA | add | fabs) | max | if . > 1e-9 then error("sum \(.)") else empty end),
      (map(.slip_us) | max | if . > 1000 then error("slip \(.) us") else empty end),
      (map(. as $r | (($r.t_s * 1e6 | round) - $r.slip_us - $p[$r.pattern].ph) % $p[$r.pattern].T)
         | map(select(. != 0)) | if length > 0 then error("pulses off their slots: \(.)") else empty end),
      # As measured where the device measures (the firmware: start_us and the widths, to a
      # tick of 1 us), else as scheduled.
      (if all(.[]; .start_us != null) then [1, "start_us", 1] else [1e6, "t_s", 1e-3] end) as [$u, $key, $tol]
      | ([range(1; length) as $k | .[$k - 1] as $a | .[$k] as $b
         | ($b[$key] - $a[$key]) * $u - ($a.width_us + $a.interphase_us + $a.balance_width_us)
           - (if $a.pattern != $b.pattern then $gap else 0 end)]
         | min | if . < -$tol then error("pulses overlap or closer than the gap: \(.) us (\($key))") else empty end),
      true
    ' "$rec" > /dev/null 2> check.err || fail "record $rec: $(cat check.err)"
}
