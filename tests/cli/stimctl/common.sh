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
