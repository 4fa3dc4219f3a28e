# Several modes in one process (--mode RA,SAI,PC --format csv) give, row for row, what one
# process per mode gives: nothing carries over from one mode to the next.  This is how
# sweep-spacing runs its jobs.
optimize-weights --mode PC,RA,SAI --electrodes 6 --pitch 1.3 --format csv > several.csv 2> several.err \
  || fail "several modes: $(cat several.err)"
[[ $(wc -l < several.csv) -eq 4 ]] || fail "expected a header and 3 rows, got $(wc -l < several.csv) lines"
[[ $(grep -c ' ratio ' several.err) -eq 3 ]] || fail "expected 3 summary lines: $(cat several.err)"
{
  optimize-weights --mode PC --electrodes 6 --pitch 1.3 --format csv
  for mode in RA SAI; do
    optimize-weights --mode "$mode" --electrodes 6 --pitch 1.3 --format csv --no-header
  done
} > single.csv 2> /dev/null
cmp several.csv single.csv || fail "rows differ from single-mode runs: $(diff several.csv single.csv)"
echo "ok: 3 modes in one process match 3 processes"
