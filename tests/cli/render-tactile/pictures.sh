# Pictures as people make them: a palette PNG (pnmtopng's choice for few colours), grey,
# grey with alpha, 16-bit, and RGBA from Matplotlib's imsave.  Each renders byte for byte
# as the 8-bit RGB picture it shows (alpha composited onto black: v x alpha / 255, rounded),
# and transparency is said in one note on stderr.
source "$TP_SOURCE/tests/cli/render-tactile/common.sh"
rt=(render-tactile --bank "$BANK" --profile profile.json)
# colour_type PNG: the IHDR's colour type (0 grey, 2 RGB, 3 palette, 4 grey + alpha, 6 RGBA)
# and bit depth.
colour_type() { od -An -tu1 -j24 -N2 "$1" | awk '{ print $2 ":" $1 }'; }
# ppm FILE MAXVAL [C,R,RED,GREEN,BLUE ...]: a plain PPM, black but for the pixels listed.
ppm() {
  local f=$1 max=$2; shift 2
  local -A px=()
  for p in "$@"; do IFS=, read -r c r R G B <<< "$p"; px[$c,$r]="$R $G $B"; done
  { echo P3; echo 8 8; echo "$max"
    for ((r = 0; r < 8; ++r)); do for ((c = 0; c < 8; ++c)); do echo "${px[$c,$r]:-0 0 0}"; done; done
  } > "$f"
}
# same PNG RGB.png: both render to the same stimulus, byte for byte.
same() {
  "${rt[@]}" "$1" > a.json 2> a.err || fail "$1: $(cat a.err)"
  "${rt[@]}" "$2" > b.json 2> b.err || fail "$2: $(cat b.err)"
  cmp -s a.json b.json || fail "$1 and $2 render differently: $(jq -c '[.patterns[]? // . | {pixels, pixel_currents_mA}]' a.json b.json)"
  echo "ok: $1 ($(colour_type "$1")) renders as $2: $(tail -1 a.err)"
}

# A palette: three colours.
ppm pic.ppm 255 "3,2,0,128,0" "5,5,200,0,90" "6,1,0,128,0"
pnmtopng pic.ppm > palette.png 2> /dev/null
pnmtopng -force pic.ppm > rgb.png 2> /dev/null
[[ $(colour_type palette.png) == 3:* ]] || fail "pnmtopng wrote $(colour_type palette.png), not a palette"
same palette.png rgb.png
# Grey (R = G = B), 8-bit and 2-bit.
{ echo P2; echo 8 8; echo 255; for ((k = 0; k < 64; ++k)); do
    case $k in 19) echo 170 ;; 45) echo 85 ;; *) echo 0 ;; esac; done; } > grey.pgm
pnmtopng grey.pgm > grey.png 2> /dev/null
ppm grey.ppm 255 "3,2,170,170,170" "5,5,85,85,85"
pnmtopng -force grey.ppm > grey-rgb.png 2> /dev/null
[[ $(colour_type grey.png) == 0:* ]] || fail "pnmtopng wrote $(colour_type grey.png), not grey"
same grey.png grey-rgb.png
# 16-bit RGB: v x 257 reads back as v; 1000 of 65535 is 3.89 of 255, read as 4.
ppm deep.ppm 65535 "3,2,0,32896,0" "5,5,51400,0,1000"
pnmtopng deep.ppm > deep.png 2> /dev/null
ppm shallow.ppm 255 "3,2,0,128,0" "5,5,200,0,4"
pnmtopng -force shallow.ppm > shallow.png 2> /dev/null
[[ $(colour_type deep.png) == 2:16 ]] || fail "pnmtopng wrote $(colour_type deep.png), not 16-bit RGB"
same deep.png shallow.png
# Grey with alpha: 170 at alpha 128 is 85.3, read as 85; 85 at alpha 255 stays 85.
{ echo P2; echo 8 8; echo 255; for ((k = 0; k < 64; ++k)); do
    case $k in 19) echo 128 ;; 45) echo 255 ;; *) echo 0 ;; esac; done; } > alpha.pgm
pnmtopng -force -alpha=alpha.pgm grey.pgm > grey-alpha.png 2> /dev/null
ppm onto.ppm 255 "3,2,85,85,85" "5,5,85,85,85"
pnmtopng -force onto.ppm > onto.png 2> /dev/null
[[ $(colour_type grey-alpha.png) == 4:8 ]] || fail "pnmtopng wrote $(colour_type grey-alpha.png), not grey + alpha"
same grey-alpha.png onto.png
grep -qFx "render-tactile: note: image 'grey-alpha.png': 63 pixels of 64 not opaque: composited onto black (transparent is 0)" a.err \
  || fail "the note: $(cat a.err)"
# The same as a palette with transparency (tRNS): pnmtopng's choice without -force.
pnmtopng -alpha=alpha.pgm grey.pgm > palette-alpha.png 2> /dev/null
[[ $(colour_type palette-alpha.png) == 3:* ]] || fail "pnmtopng wrote $(colour_type palette-alpha.png), not a palette"
same palette-alpha.png onto.png

# Matplotlib's imsave: RGBA, one pixel half transparent, one opaque, the rest transparent
# white (composited: black); and an opaque picture (alpha 255 everywhere: no note).
MPLCONFIGDIR=$PWD MPLBACKEND=Agg /usr/bin/python3 - <<'PY' || fail "matplotlib imsave"
import numpy as np
import matplotlib.pyplot as plt
a = np.zeros((8, 8, 4), dtype=np.uint8)
a[..., :3] = 255                  # transparent white
a[2, 3] = [0, 255, 0, 128]        # SAI 255 at alpha 128: 128
a[5, 5] = [200, 0, 90, 255]       # opaque
plt.imsave("mpl-rgba.png", a)
b = a.copy()
b[..., 3] = 255
b[..., :3] = 0
b[2, 3] = [0, 128, 0, 255]
b[5, 5] = [200, 0, 90, 255]
plt.imsave("mpl-opaque.png", b)
PY
ppm mpl.ppm 255 "3,2,0,128,0" "5,5,200,0,90"
pnmtopng -force mpl.ppm > mpl-rgb.png 2> /dev/null
[[ $(colour_type mpl-rgba.png) == 6:8 ]] || fail "imsave wrote $(colour_type mpl-rgba.png), not RGBA"
same mpl-rgba.png mpl-rgb.png
grep -qF "render-tactile: note: image 'mpl-rgba.png': 63 pixels of 64 not opaque: composited onto black" a.err \
  || fail "the note: $(cat a.err)"
same mpl-opaque.png mpl-rgb.png
! grep -q "not opaque" a.err || fail "a note for an opaque picture: $(cat a.err)"
# A sequence of such frames: one note for them all.
"${rt[@]}" --sequence mpl-rgba.png grey-alpha.png mpl-opaque.png > seq.json 2> seq.err || fail "--sequence: $(cat seq.err)"
grep -qFx "render-tactile: note: image 'mpl-rgba.png': 63 pixels of 64 not opaque (and 1 image more): composited onto black (transparent is 0)" seq.err \
  || fail "the sequence's note: $(cat seq.err)"
echo "ok: $(head -1 seq.err)"
# A refusal is one line: no note before it (the corner's PC has no pattern).
ppm corner.ppm 255 "0,0,0,0,255"
{ echo P2; echo 8 8; echo 255; for ((k = 0; k < 64; ++k)); do echo 200; done; } > half.pgm
pnmtopng -force -alpha=half.pgm corner.ppm > corner.png 2> /dev/null
refuses 2 --says "could not find" -- "${rt[@]}" corner.png
