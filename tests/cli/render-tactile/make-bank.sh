# The fixture: the 8 x 8 bank the render-tactile scripts share (written whole, then moved).
mkdir -p "$(dirname "$TP_RENDER_BANK")"
optimize-weights --bank --grid 8x8 --pitch 2 --pad 1x1 --neighbourhood 3 > bank.tmp 2> err.txt || fail "optimize-weights: $(cat err.txt)"
mv bank.tmp "$TP_RENDER_BANK"
echo "ok: $(cat err.txt)"
