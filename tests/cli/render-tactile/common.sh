# Shared by the render-tactile scripts: PNGs from pixel lists, a profile, the bank, record
source "$TP_SOURCE/tests/cli/stimctl/common.sh"  # check_mix_record
# checks.
# mkpng FILE COLUMNS ROWS [C,R,RED,GREEN,BLUE ...]: an 8-bit RGB PNG (netpbm's pnmtopng),
# black but for the pixels listed.
mkpng() {
  local f=$1 w=$2 h=$3; shift 3
  local -A px=()
  for p in "$@"; do IFS=, read -r c r R G B <<< "$p"; px[$c,$r]="$R $G $B"; done
  { echo P3; echo "$w $h"; echo 255
    for ((r = 0; r < h; ++r)); do for ((c = 0; c < w; ++c)); do echo "${px[$c,$r]:-0 0 0}"; done; done
  } | pnmtopng -force > "$f" 2> /dev/null || fail "pnmtopng"
}
# The person: per primary, threshold and comfort (mA).
cat > profile.json <<'JSON'
{"format": "tactile-primaries/profile/1",
 "primaries": {"RA": {"threshold_mA": 0.4, "comfort_mA": 1.0},
               "SAI": {"threshold_mA": 0.3, "comfort_mA": 0.9},
               "PC": {"threshold_mA": 0.5, "comfort_mA": 1.2}}}
JSON
# The bank: the fixture's 8 x 8 grid (2 mm, 1 x 1 mm pads, 3 x 3 neighbourhoods); on the
# firmware (8 channels) a 4 x 2 grid of whole-array patterns, made here.
if [[ ${TP_DEVICE:-} == firmware ]]; then
  optimize-weights --bank --grid 4x2 --pitch 2 --pad 1x1 > bank.json 2> /dev/null || fail "optimize-weights --bank 4x2"
  BANK=bank.json COLUMNS=4 ROWS=2 CHANNELS=8
else
  [[ -s $TP_RENDER_BANK ]] || fail "no bank at $TP_RENDER_BANK (the render-tactile.bank fixture)"
  BANK=$TP_RENDER_BANK COLUMNS=8 ROWS=8 CHANNELS=64
fi
# as_mix DOC: a stimulus document as a mix (a single pattern becomes a table of one).
as_mix() {
  jq 'if .format == "tactile-primaries/stimulus/1"
      then {format: "tactile-primaries/stimulus/2", gap_us: 100, patterns: [del(.format) | .phase_us = (.phase_us // 0)]}
      else . end' "$1"
}
# check_pixels REC DOC: every pulse's currents are its pattern's pixels' currents times their
# bank weights (within one DAC step, 0.977 uA), so nothing but the planned pixels is felt.
check_pixels() {
  jq -se --slurpfile d "$2" --slurpfile b "$BANK" '
    ($d[0] | if .patterns then .patterns else [.] end) as $p
    | map(. as $r | $p[$r.pattern] as $g
        | [range(0; $r.currents_mA | length) as $e
           | ([range(0; $g.pixels | length) as $m
               | $g.pixel_currents_mA[$m] * $b[0].pixels[$g.pixels[$m]].patterns[$g.primary].weights[$e]] | add)
           - $r.currents_mA[$e] | fabs] | max) | max
    | if . > 0.000978 then error("a current \(.) mA from its pixels x weights") else true end' "$1" > /dev/null 2> pix.err \
    || fail "record $1: $(cat pix.err)"
}
