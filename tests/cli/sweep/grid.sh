# sweep-spacing --grid: a 2-D grid's pitch swept (issue 21), one pixel per mode at --at;
# local and GNU parallel write the same bytes, each row is optimize-weights' own for that
# grid, and the Slurm engine's batch script runs the grid.
sweep=$TP_SOURCE/scripts/sweep-spacing
args=(--grid 3x3,5x5 --pitch 1.5:2.5:0.5 --modes SAI,PC --model rect3d -- --at 0,0)
"$sweep" "${args[@]}" > local.csv 2> err.txt || fail "local: $(cat err.txt)"
[[ ! -s err.txt ]] || fail "local: stderr $(cat err.txt)"
[[ $(head -1 local.csv) == "$(optimize-weights --grid 5x5 --pitch 2 --model rect3d --at 0,0 --mode SAI,PC --format csv --header-only)" ]] \
  || fail "header: $(head -1 local.csv)"
[[ $(tail -n +2 local.csv | cut -d, -f1-3 | tr '\n' ' ') == "9,1.5,PC 9,1.5,SAI 9,2,PC 9,2,SAI 9,2.5,PC 9,2.5,SAI 25,1.5,PC 25,1.5,SAI 25,2,PC 25,2,SAI 25,2.5,PC 25,2.5,SAI " ]] \
  || fail "rows: $(tail -n +2 local.csv | cut -d, -f1-3 | tr '\n' ' ')"
expected=$(optimize-weights --grid 5x5 --pitch 2.5 --model rect3d --at 0,0 --mode SAI --format csv --no-header 2> /dev/null)
[[ $(grep '^25,2.5,SAI,' local.csv) == "$expected" ]] || fail "row 25,2.5,SAI differs from optimize-weights alone"
# The pixel's weights sum to zero, and the 3 x 3 grid's are symmetric about its centre pad.
tail -n +2 local.csv | awk -F, '{ s = 0; for (i = 9; i <= NF; i++) s += $i; if (s > 1e-9 || s < -1e-9) { print "row " NR " sums to " s; exit 1 } }' \
  || fail "weights do not sum to zero"
grep '^9,2,SAI,' local.csv | awk -F, '{ for (i = 0; i < 9; i++) { d = $(9 + i) - $(17 - i); if (d > 1e-6 || d < -1e-6) exit 1 } }' \
  || fail "3x3 SAI pixel at the centre: weights not symmetric"
if command -v parallel > /dev/null; then
  "$sweep" --engine parallel "${args[@]}" > parallel.csv 2> err.txt || fail "parallel: $(cat err.txt)"
  cmp local.csv parallel.csv || fail "parallel's CSV differs from local's"
fi
"$sweep" --engine slurm --dry-run --state "$PWD/st" "${args[@]}" > dry.txt 2> err.txt || fail "dry run: $(cat err.txt)"
grep -qx "array_opt='--grid'" dry.txt || fail "the Slurm script does not run the grid: $(grep array_opt dry.txt)"
# --header-only with --at checks and computes nothing (no pixel's talk on stderr).
optimize-weights --grid 3x3 --pitch 2 --at 0,0 --mode SAI --format csv --header-only > h.csv 2> err.txt \
  || fail "--header-only --at: $(cat err.txt)"
[[ $(wc -l < h.csv) -eq 1 && ! -s err.txt ]] || fail "--header-only --at wrote $(wc -l < h.csv) lines, stderr $(cat err.txt)"
# Refused before any job: two grids of as many pads, --grid with --electrodes, a bad form,
# a grid without its pixel's place; an infeasible pixel fails the sweep naming the grid.
for bad in "--grid 2x4,4x2 -- --at 0,0" "--grid 3x3 --electrodes 4 -- --at 0,0" "--grid 3by3 -- --at 0,0" \
           "--grid 3x3 --pitch 2:2:1" "--grid 3x3 --pitch 2:2:1 -- --at 0,0 --row-pitch 1"; do
  set +e; "$sweep" $bad > out.csv 2> err.txt; rc=$?; set -e
  [[ $rc -eq 2 && ! -s out.csv && $(wc -l < err.txt) -eq 1 ]] || fail "$bad: exit $rc, $(cat err.txt)"
done
set +e; "$sweep" --grid 4x4 --pitch 2:2:1 --modes SAI -- --at 0,0 > out.csv 2> err.txt; rc=$?; set -e
[[ $rc -eq 1 && ! -s out.csv ]] && grep -q "^sweep-spacing: grid 4x4 pitch 2: optimize-weights: no weights put" err.txt \
  || fail "infeasible pixel: exit $rc, $(cat err.txt)"
echo "ok: $(($(wc -l < local.csv) - 1)) rows"
