# scripts/plot-field turns af-field CSV into a PNG; it refuses input that is not af-field CSV.
af-field --electrodes 1 --pitch 1 --weights 1 --x -2:2:0.05 --y 0.2:2:0.05 > field.csv
"$TP_SOURCE/scripts/plot-field" -c af_v -o field.png field.csv 2> err.txt
[[ $(head -c 8 field.png | od -An -tx1 | tr -d ' \n') == 89504e470d0a1a0a ]] || fail "not a PNG"
[[ $(stat -c %s field.png) -gt 5000 ]] || fail "PNG suspiciously small"
echo "a,b" | { "$TP_SOURCE/scripts/plot-field" -o bad.png - 2>/dev/null && fail "accepted non-af-field CSV"; } || true
[[ ! -e bad.png ]] || fail "wrote a PNG for bad input"
# A plane map (x_mm,z_mm,...) is drawn too.
af-field --grid 3x3 --pitch 2 --pad 1x1 --plane-depth 0.9 --x -4:4:0.1 --z-grid -4:4:0.1 > plane.csv
"$TP_SOURCE/scripts/plot-field" -o plane.png plane.csv 2> err.txt
[[ $(head -c 8 plane.png | od -An -tx1 | tr -d ' \n') == 89504e470d0a1a0a ]] || fail "plane: not a PNG"
[[ $(stat -c %s plane.png) -gt 5000 ]] || fail "plane: PNG suspiciously small"
echo "ok: PNG written"
