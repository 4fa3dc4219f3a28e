# --min-target-af buys target drive with a little selectivity; the default is the paper's problem.
optimize-weights --mode PC > free.json 2> /dev/null
free_af=$(jq -r '.target_max_af' free.json)
want=$(awk -v a="$free_af" 'BEGIN { print 1.5 * a }')
optimize-weights --mode PC --min-target-af "$want" > bound.json 2> /dev/null
awk -v f="$(jq -r .ratio free.json)" -v b="$(jq -r .ratio bound.json)" -v w="$want" \
    -v got="$(jq -r .target_max_af bound.json)" 'BEGIN {
  if (!(got >= 0.999 * w)) { print "target AF " got " < " w; exit 1 }
  if (!(b >= 0.999 * f)) { print "bounded ratio " b " better than free " f "?"; exit 1 }
  printf "free: ratio %s; with AF >= %s V/ms: ratio %s, AF %s\n", f, w, b, got }' || fail "efficiency"
