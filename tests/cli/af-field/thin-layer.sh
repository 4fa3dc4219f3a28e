# A skin with a 5 um top layer (the thinnest in range) far from the electrodes (issue 20,
# item 6): the layered model's Hankel rule is bounded per depth, so in-range rows work and
# agree with a peer; what it cannot evaluate is refused before the first row is written.
thin=$TP_INPUTS/skin-thin-5um.json
peer=$TP_INPUTS/skin-thin-5um-uniform-top.json  # the same stack, its top layer as the next
af-field --model layered --skin "$thin" --x 0:100:5 --y 1:1:1 > thin.csv 2> err ||
  fail "5 um layer, 100 mm away: $(cat err)"
[[ $(wc -l < thin.csv) -eq 22 ]] || fail "$(wc -l < thin.csv) lines, expected 22"
af-field --model layered --skin "$peer" --x 0:100:5 --y 1:1:1 > peer.csv 2> err || fail "peer: $(cat err)"
# A 5 um resistive layer under a current source barely changes the field 1 mm deep: every
# value finite and within 1 % of the stack without it.
paste -d, thin.csv peer.csv | awk -F, 'NR > 1 {
    for (k = 3; k <= 4; ++k) {
      if ($k !~ /^-?[0-9]/ || $(k + 4) !~ /^-?[0-9]/) { print "not a number: " $0; bad = 1 }
      else if ((($k - $(k + 4)) ^ 2) > (0.01 * $(k + 4)) ^ 2) { print "differs by more than 1 %: " $0; bad = 1 }
    }
  } END { exit bad }' > diff.txt || fail "$(head -3 diff.txt)"
# The 20 um layer of the issue, 200 mm across at the default depths: every row.
jq '.layers[0].thickness_mm = 0.02 | .layers[1].thickness_mm = 0.58' "$thin" > thin20.json
af-field --model layered --skin thin20.json --x 0:200:1 --y 1:2:1 > t20.csv 2> err || fail "20 um: $(cat err)"
[[ $(wc -l < t20.csv) -eq 403 ]] || fail "20 um: $(wc -l < t20.csv) lines, expected 403"
grep -qi nan t20.csv && fail "20 um: a non-finite value"
# Shallow rows 500 mm away would need a rule of over 1e6 panels: refused, nothing written.
refuses 2 --says "Hankel rule" -- af-field --model layered --skin "$thin" --x 0:500:50 --y 0.01:0.03:0.01
echo "ok: in-range rows of a 5 um and a 20 um layer, within 1 % of the peer; the rest refused"
