# scripts/plot-sd draws fiber-threshold's strength-duration CSV; other input is refused.
"$TP_SOURCE/scripts/plot-sd" -o sd.png "$TP_GOLDEN/fiber-threshold/sd.csv" 2>/dev/null
[[ -s sd.png && $(head -c 4 sd.png | tail -c 3) == PNG ]] || fail "no PNG"
rc=0; echo "x,y" | "$TP_SOURCE/scripts/plot-sd" -o bad.png 2>/dev/null || rc=$?
[[ $rc -eq 2 ]] || fail "plot-sd accepted other CSV (exit $rc)"
echo "ok: plot-sd"
