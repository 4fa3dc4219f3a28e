# Grid axes never step past MAX (issue 20, item 11): 0.01 + 1999 * 0.01 is 20.000000000000004
# in doubles, which the depth range (0.01 to 20 mm) and a layered skin's valid_to_mm (20 mm
# here) used to refuse.  The last row printed is MAX itself.
af-field --x 0:0:1 --y 0.01:20:0.01 > uniform.csv 2> err || fail "line2d: $(cat err)"
[[ $(tail -1 uniform.csv | cut -d, -f2) == 20 ]] || fail "last row at y = $(tail -1 uniform.csv | cut -d, -f2), expected 20"
jq '.valid_to_mm = 20 | del(.note)' "$TP_SOURCE/data/skin/fingertip.json" > deep.json
af-field --model layered --skin deep.json --x 0:0:1 --y 0.01:20:0.01 > layered.csv 2> err ||
  fail "layered, valid_to_mm 20: $(cat err)"
[[ $(wc -l < layered.csv) -eq 2001 ]] || fail "layered: $(wc -l < layered.csv) lines, expected 2001"
[[ $(tail -1 layered.csv | cut -d, -f2) == 20 ]] || fail "layered: last row at y = $(tail -1 layered.csv | cut -d, -f2)"
echo "ok: both grids end at 20 mm and are accepted"
