# scripts/plot-sd draws fiber-threshold's strength-duration CSV (the golden table is
# monophasic), its title naming the waveform it is told; other input, and no waveform, are
# refused.
"$TP_SOURCE/scripts/plot-sd" --waveform monophasic -o sd.png "$TP_GOLDEN/fiber-threshold/sd.csv" 2> err.txt ||
  fail "plot-sd --waveform monophasic: $(cat err.txt)"
[[ -s sd.png && $(head -c 4 sd.png | tail -c 3) == PNG ]] || fail "no PNG"
# The title, as gnuplot is given it (a gnuplot that keeps its script).
mkdir fake
printf '#!/bin/sh\ncat > "%s/plot.gp"\n' "$PWD" > fake/gnuplot
chmod +x fake/gnuplot
PATH=$PWD/fake:$PATH "$TP_SOURCE/scripts/plot-sd" --waveform "biphasic, 800 us balance" -o t.png \
  "$TP_GOLDEN/fiber-threshold/sd.csv" 2>/dev/null || fail "plot-sd with a named waveform"
grep -F "set title 'Strength-duration, biphasic, 800 us balance pulses: threshold current against main phase width'" plot.gp > /dev/null ||
  fail "the title does not name the waveform: $(grep title plot.gp)"
refuses 2 --says "give --waveform" -- "$TP_SOURCE/scripts/plot-sd" -o none.png "$TP_GOLDEN/fiber-threshold/sd.csv"
refuses 2 --says "--waveform needs a value" -- "$TP_SOURCE/scripts/plot-sd" "$TP_GOLDEN/fiber-threshold/sd.csv" --waveform
refuses 2 --says "no quotes" -- "$TP_SOURCE/scripts/plot-sd" --waveform "it's" "$TP_GOLDEN/fiber-threshold/sd.csv"
[[ ! -e none.png ]] || fail "a refused plot wrote its file"
rc=0; echo "x,y" | "$TP_SOURCE/scripts/plot-sd" --waveform biphasic -o bad.png 2>/dev/null || rc=$?
[[ $rc -eq 2 ]] || fail "plot-sd accepted other CSV (exit $rc)"
echo "ok: plot-sd"
