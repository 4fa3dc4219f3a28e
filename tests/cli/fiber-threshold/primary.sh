# A mode whose target does not fire first is said on stderr (a warning naming who fires
# first, and both thresholds), and the document is as without it; a mode whose target fires
# first (SAI on the paper's array) and a document without a mode get no such warning.
optimize-weights --mode PC 2>/dev/null | fiber-threshold > pc.json 2> pc.txt
grep -q '^fiber-threshold: warning: PC mode: SAI fires first (0.2612 mA, PC 0.504 mA): the pattern is not a primary for PC' pc.txt ||
  fail "PC: no warning, or another: $(cat pc.txt)"
jq -e '.threshold_ratio.PC > 1 and .mode == "PC"' pc.json >/dev/null || fail "PC: the ratio: $(jq -c .threshold_ratio pc.json)"
optimize-weights --mode SAI 2>/dev/null | fiber-threshold > sai.json 2> sai.txt
! grep -q "fires first" sai.txt || fail "SAI fires first, yet warned: $(cat sai.txt)"
jq -e '.threshold_ratio.SAI < 1' sai.json >/dev/null || fail "SAI: the ratio: $(jq -c .threshold_ratio sai.json)"
# Without a mode (weights given), nothing to compare against.
fiber-threshold --weights 0,0,-1,1,1,-1,0,0 > none.json 2> none.txt
! grep -q "fires first" none.txt || fail "no mode, yet warned: $(cat none.txt)"
echo "ok: $(grep -c 'fires first' pc.txt) warning for PC, none for SAI or weights without a mode"
