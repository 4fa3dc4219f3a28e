# The acceptance check: one electrode, 125 rows, af_h proportional to
# (y^2 - x^2)/(x^2 + y^2)^2 (Eq. 23), positive under the electrode, af_v = -af_h.
af-field --electrodes 1 --pitch 1 --weights 1 --x -3:3:0.25 --y 0.5:2.5:0.5 > out.csv
[[ $(head -1 out.csv) == x_mm,y_mm,af_h,af_v ]] || fail "header: $(head -1 out.csv)"
rows=$(tail -n +2 out.csv | wc -l)
[[ $rows -eq 125 ]] || fail "expected 125 rows, got $rows"
tail -n +2 out.csv | awk -F, '
  function abs(v) { return v < 0 ? -v : v }
  {
    x = $1; y = $2; h = $3; v = $4
    shape = (y*y - x*x) / ((x*x + y*y)^2)
    if (abs(shape) > 1e-9) {
      k = h / shape
      if (n++ == 0) k0 = k
      else if (abs(k - k0) > 1e-8 * abs(k0)) { printf "ratio af_h/shape varies at x=%s y=%s: %g vs %g\n", x, y, k, k0; bad = 1 }
    }
    if (x == 0 && !(h > 0)) { printf "af_h not positive under the electrode at y=%s\n", y; bad = 1 }
    if (abs(v + h) > 1e-9 * abs(h) + 1e-15) { printf "af_v != -af_h at x=%s y=%s\n", x, y; bad = 1 }
  }
  END { if (!(k0 > 0)) { print "proportionality constant not positive"; bad = 1 }; exit bad }' \
  || fail "Eq. 23 check"
echo "ok: 125 rows follow Eq. 23"
