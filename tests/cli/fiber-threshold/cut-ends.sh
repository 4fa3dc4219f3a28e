# The cut-end rule (docs/fibres.md, "Cut ends"): no threshold comes from a cut end of the
# simulated fibre.  One anodic pad of the paper's array, 200 us monophasic, fired every
# class at a cut end before the rule (RA 1.571, SAI 1.036, PC 1.089 mA); each fibre is now
# lengthened where it fired until the action potential starts inside.
fiber-threshold --weights 0,0,0,-1,0,0,0,0 --monophasic --threads 2 > anode.json 2> err.txt ||
  fail "anodic pad: $(cat err.txt)"
jq -e '[.thresholds.receptors[] | has("at_cut_end")] | any | not' anode.json > /dev/null ||
  fail "a threshold from a cut end: $(jq -c .thresholds.receptors anode.json)"
grep -q "cut end" err.txt && fail "stderr warns of a cut end: $(cat err.txt)"
# The thresholds inside the fibres (within 1 % of those with every fibre doubled again,
# fibre-tests "[cut]"): RA 4.328 mA at 3.24 mm deep, SAI 2.255 and PC 3.805 mA.
for want in RA:4.328 SAI:2.255 PC:3.805; do
  r=${want%%:*} v=${want#*:}
  jq -e --argjson v "$v" ".thresholds.receptors.$r.threshold_mA | (. / \$v - 1) | fabs < 1e-3" \
    anode.json > /dev/null || fail "$r: $(jq -c .thresholds.receptors.$r anode.json), expected $v mA"
done
echo "ok: anodic pad: $(head -1 err.txt)"
# A small population on the layered fingertip under the paper's SAI pattern, seed fixed:
# before the rule 6 of its 10 RA fibres fired at their deep cut ends.  Now none does: no
# at_cut_end column, and stderr counts none.
fiber-threshold --weights 0,0,-0.5,1,-0.5,0,0,0 --conductor layered --population 10 --seed 1 \
  --threads 2 > pop.csv 2> perr.txt || fail "population: $(cat perr.txt)"
[[ $(head -1 pop.csv) == class,x_mm,offset_mm,depth_mm,diameter_um,threshold_mA ]] ||
  fail "population header: $(head -1 pop.csv)"
grep -q "cut end" perr.txt && fail "population: $(cat perr.txt)"
[[ $(wc -l < pop.csv) -eq 31 ]] || fail "population: $(wc -l < pop.csv) lines"
echo "ok: layered population: $(cat perr.txt)"
