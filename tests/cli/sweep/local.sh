# scripts/sweep-spacing writes one CSV row per (electrodes, pitch, mode), and plot-sweep a PNG.
"$TP_SOURCE/scripts/sweep-spacing" --electrodes 4,6 --pitch 0.5:1.5:0.5 --modes SAI,PC > sweep.csv 2> err.txt \
  || fail "sweep-spacing: $(cat err.txt)"
[[ $(head -1 sweep.csv) == electrodes,pitch_mm,mode,ratio,target_max_af,max_af_RA,max_af_SAI,max_af_PC,w0,w1,w2,w3,w4,w5 ]] \
  || fail "header: $(head -1 sweep.csv)"
rows=$(tail -n +2 sweep.csv | wc -l)
[[ $rows -eq 12 ]] || fail "expected 12 rows, got $rows"
# every row's weights sum to zero
tail -n +2 sweep.csv | awk -F, '{ s = 0; for (i = 9; i <= NF; i++) s += $i; if (s > 1e-9 || s < -1e-9) { print "row " NR " sums to " s; exit 1 } }' \
  || fail "weights do not sum to zero"
# each row is what optimize-weights gives for that array and mode alone
expected=$(optimize-weights --mode PC --electrodes 6 --pitch 1 --format csv --no-header 2> /dev/null)
[[ $(grep '^6,1,PC,' sweep.csv) == "$expected" ]] || fail "row 6,1,PC: $(grep '^6,1,PC,' sweep.csv) != $expected"
# optimize-weights --header-only (which the sweep checks its options with) prints what a
# computing run's first line is
[[ $(optimize-weights --mode SAI,PC --electrodes 6 --pitch 1 --format csv --header-only) \
   == "$(optimize-weights --mode SAI,PC --electrodes 6 --pitch 1 --format csv 2> /dev/null | head -1)" ]] \
  || fail "--header-only differs from the header of a computing run"
# options after -- reach every job; a bad mode or option is refused before any job runs
"$TP_SOURCE/scripts/sweep-spacing" --electrodes 4 --pitch 1:1.5:0.5 --modes SAI -- --pattern-starts 1 \
  > starts.csv 2> err.txt || fail "extra options: $(cat err.txt)"
[[ $(tail -n +2 starts.csv | wc -l) -eq 2 ]] || fail "extra options: $(cat starts.csv)"
for bad in "--modes SAI,XY" "--modes SAI -- --bogus"; do
  set +e; "$TP_SOURCE/scripts/sweep-spacing" --electrodes 4 --pitch 1:1:1 $bad > out.csv 2> err.txt; rc=$?; set -e
  [[ $rc -eq 2 && ! -s out.csv && $(wc -l < err.txt) -eq 1 ]] || fail "$bad: exit $rc, $(cat err.txt)"
done
# A stdout that cannot take the CSV: exit 1, one line.
set +e; "$TP_SOURCE/scripts/sweep-spacing" --electrodes 4 --pitch 1:1:1 --modes SAI > /dev/full 2> err.txt; rc=$?; set -e
[[ $rc -eq 1 && $(wc -l < err.txt) -eq 1 ]] && grep -Fx 'sweep-spacing: stdout: the CSV was not written in full' err.txt > /dev/null \
  || fail "stdout /dev/full: exit $rc, $(cat err.txt)"
"$TP_SOURCE/scripts/plot-sweep" -o sweep.png sweep.csv 2> /dev/null || fail "plot-sweep"
[[ $(head -c 4 sweep.png | od -An -tx1 | tr -d ' \n') == 89504e47 ]] || fail "not a PNG"
echo "ok: $rows rows"
