# fiber-threshold --population: the same seed gives the same bytes (the table and the
# recruitment curves), another seed another population; every class sampled in its ranges
# over the array and its margin; each class's recruitment monotone, ending at the fraction
# that fires; the SAI mode's SAI recruitment leads; refusals.
optimize-weights --mode SAI 2> /dev/null > sai.json || fail "optimize-weights"
ft=(fiber-threshold --config sai.json --population 15)
"${ft[@]}" --seed 3 --recruitment r1.csv > p1.csv 2> e1.txt || fail "population: $(cat e1.txt)"
"${ft[@]}" --seed 3 --recruitment r2.csv > p2.csv 2> /dev/null || fail "population again"
cmp -s p1.csv p2.csv && cmp -s r1.csv r2.csv || fail "the same seed gave other bytes"
"${ft[@]}" --seed 4 > p3.csv 2> /dev/null || fail "population, seed 4"
cmp -s p1.csv p3.csv && fail "seeds 3 and 4 gave the same population"
# Every seed from 0 to 2^64 - 1 is its own (beyond it, or below 0, refused: issue 38).
fiber-threshold --config sai.json --population 1 --seed 18446744073709551615 > p5.csv 2> e5.txt ||
  fail "the largest seed: $(cat e5.txt)"
grep -F "seed 18446744073709551615:" e5.txt > /dev/null || fail "the largest seed: $(cat e5.txt)"
# (A last column at_cut_end, 0 or 1, where any afferent fired first at a cut end of its fibre.)
[[ $(head -1 p1.csv) == class,x_mm,offset_mm,depth_mm,diameter_um,threshold_mA?(,at_cut_end) ]] || fail "header: $(head -1 p1.csv)"
if [[ $(head -1 p1.csv) == *,at_cut_end ]]; then
  awk -F, 'NR > 1 && $7 != 0 && $7 != 1 { exit 1 }' p1.csv || fail "at_cut_end not 0 or 1"
  grep -E "RA 15 of 15 fire .*, [0-9]+ of them at a cut end" e1.txt > /dev/null || fail "stderr does not count the cut ends: $(cat e1.txt)"
fi
awk -F, 'NR > 1 {
    n[$1]++
    if ($1 == "RA" && !($5 >= 3 && $5 <= 5 && $4 == 0.7 && $2 >= -8.5 && $2 <= 8.5 && $3 == "")) bad = $0
    if ($1 == "SAI" && !($5 >= 7 && $5 <= 12 && $4 == 0.9 && $2 == "" && $3 >= 0)) bad = $0
    if ($1 == "PC" && !($5 >= 5 && $5 <= 13 && $4 >= 2 && $4 <= 3 && $2 == "")) bad = $0 }
  END { if (bad != "") { print "out of range: " bad; exit 1 }
        if (n["RA"] != 15 || n["SAI"] != 15 || n["PC"] != 15) { print "counts"; exit 1 } }' p1.csv > chk.txt \
  || fail "$(cat chk.txt)"
# Recruitment: from 0 at 0 mA, non-decreasing, ending at each class's fraction that fires.
awk -F, 'NR == 1 { if ($0 != "current_mA,recruited_RA,recruited_SAI,recruited_PC,si_RA,si_SAI,si_PC") { print "header " $0; exit 1 } next }
  NR == 2 { if ($1 != 0 || $2 != 0 || $3 != 0 || $4 != 0) { print "not 0 at 0 mA"; exit 1 } }
  { for (k = 2; k <= 4; ++k) { if ($k < last[k]) { print "falls at " $1; exit 1 } last[k] = $k }
    if (NR > 2 && $1 <= prev) { print "currents not increasing"; exit 1 } prev = $1 }
  END { printf "%s %s %s\n", last[2], last[3], last[4] }' r1.csv > ends.txt || fail "recruitment: $(cat ends.txt)"
read -r fra fsai fpc < ends.txt
for c in RA SAI PC; do
  fired=$(awk -F, -v c=$c 'NR > 1 && $1 == c && $6 != ""' p1.csv | wc -l)
  want=$(awk -v f="$fired" 'BEGIN { printf "%.10g", f / 15 }')
  got=$(case $c in RA) echo "$fra" ;; SAI) echo "$fsai" ;; PC) echo "$fpc" ;; esac)
  awk -v a="$got" -v b="$want" 'BEGIN { exit !((a - b) < 1e-9 && (b - a) < 1e-9) }' || fail "$c ends at $got, $fired of 15 fire"
done
# The SAI mode recruits SAI first: its lowest threshold is below every RA and PC fibre's.
awk -F, 'NR > 1 && $6 != "" { if (!($1 in lo) || $6 < lo[$1]) lo[$1] = $6 }
  END { exit !(lo["SAI"] < lo["RA"] && lo["SAI"] < lo["PC"]) }' p1.csv || fail "SAI is not first: $(cat e1.txt)"
grep -E "^fiber-threshold: mrg, .*seed 3: RA [0-9]+ of 15 fire" e1.txt > /dev/null || fail "stderr: $(cat e1.txt)"
echo "ok: $(cat e1.txt)"
# Refusals: one line, nothing on stdout, no curves file left.
refuses 2 --says "--population: 0 outside [1, 10000]" -- fiber-threshold --config sai.json --population 0
refuses 2 --says "--seed, --recruitment: apply to --population only" -- fiber-threshold --config sai.json --seed 3
refuses 2 --says "give one" -- fiber-threshold --config sai.json --population 3 --strength-duration
# Over a 2-D array: placed in x and z over the pads and margin, a column z_mm; the same
# bytes twice.  Each afferent passes through its own place, so --at (one point for every
# fibre) is refused with --population, not ignored.
fiber-threshold --grid 2x2 --weights 1,-1,0,0 --population 3 > g1.csv 2> g.txt || fail "2-D: $(cat g.txt)"
fiber-threshold --grid 2x2 --weights 1,-1,0,0 --population 3 > g2.csv 2> g.txt || fail "2-D: $(cat g.txt)"
cmp -s g1.csv g2.csv || fail "2-D: not the same bytes twice"
[[ $(head -1 g1.csv) == class,x_mm,offset_mm,depth_mm,diameter_um,threshold_mA,z_mm?(,at_cut_end) ]] || fail "2-D header: $(head -1 g1.csv)"
awk -F, 'NR > 1 && ($7 < -5.5 || $7 > 5.5) { exit 1 }' g1.csv || fail "2-D: a z outside the pads and margin"
[[ $(wc -l < g1.csv) -eq 10 ]] || fail "2-D: $(wc -l < g1.csv) lines"
echo "ok: 2-D: $(cat g.txt)"
refuses 2 --says "--recruitment: cannot write 'missing/r.csv': No such file or directory" \
  -- fiber-threshold --config sai.json --population 3 --recruitment missing/r.csv
refuses 2 --says "--at: does not apply to --population" -- \
  fiber-threshold --grid 2x2 --weights 1,-1,0,0 --population 3 --at 0,0
refuses 2 --says "--at: does not apply to --population" -- \
  fiber-threshold --grid 2x2 --weights 1,-1,0,0 --population 3 --at 100,100
