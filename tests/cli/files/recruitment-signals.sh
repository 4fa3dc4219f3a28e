# fiber-threshold --population N --recruitment FILE interrupted mid-run by SIGINT or SIGTERM
# (issue 38, finding 8: it left an empty FILE, which the rerun then refused to overwrite):
# FILE absent when there was none, a previous FILE as it was, no temporary beside it; the
# same with --output; and the command again, to its end, replaces them.
optimize-weights --mode SAI > sai.json 2> /dev/null || fail "optimize-weights"
# 900 afferents: about a minute on 2 cores; each run is stopped within a second.
long=(fiber-threshold --config sai.json --population 300)

# interrupt SIG FILES...: runs "${long[@]}" with FILES' options in the background, sends SIG
# once its temporaries exist (the work has begun) and 0.3 s more, and checks that the signal
# ended it (exit 128 + SIG), with nothing on stdout and no temporary left.
interrupt() {
  local sig=$1; shift
  env --default-signal "${long[@]}" "$@" > stdout.txt 2> err.txt &
  local pid=$! rc=0
  for _ in $(seq 500); do compgen -G '.r.csv.*' > /dev/null && break; sleep 0.01; done
  sleep 0.3
  kill -s "$sig" "$pid"
  wait "$pid" || rc=$?
  [[ $rc -eq $((128 + $(kill -l "$sig"))) ]] || fail "SIG$sig: exit $rc, not ended by the signal mid-run: $(cat err.txt)"
  [[ ! -s stdout.txt ]] || fail "SIG$sig: wrote to stdout"
  local left; left=$(find . -maxdepth 1 -name '.?*' -printf '%f ')
  [[ -z $left ]] || fail "SIG$sig: temporaries left: $left"
}

for sig in INT TERM; do
  rm -f r.csv
  interrupt "$sig" --recruitment r.csv
  [[ ! -e r.csv ]] || fail "SIG$sig: left r.csv ($(wc -c < r.csv) bytes) where there was none"
  echo "previous curves" > r.csv
  interrupt "$sig" --recruitment r.csv
  [[ $(cat r.csv) == "previous curves" ]] || fail "SIG$sig: the previous r.csv changed: $(head -c 200 r.csv)"
  echo "ok: SIG$sig mid-run: no r.csv left where there was none, a previous one kept, no temporary"
done
echo "previous table" > p.csv
interrupt TERM --recruitment r.csv --output p.csv
[[ $(cat r.csv) == "previous curves" && $(cat p.csv) == "previous table" ]] || fail "SIGTERM: --output or --recruitment changed"
echo "ok: SIGTERM mid-run with --output: both previous files kept"

# Again, to its end: both replaced, as every output is.
fiber-threshold --config sai.json --population 2 --recruitment r.csv --output p.csv 2> err.txt || fail "the rerun: $(cat err.txt)"
[[ $(head -1 r.csv) == current_mA,recruited_RA,* ]] || fail "the rerun's r.csv: $(head -2 r.csv)"
[[ $(head -1 p.csv) == class,x_mm,* && $(wc -l < p.csv) -eq 7 ]] || fail "the rerun's p.csv: $(head -2 p.csv)"
left=$(find . -maxdepth 1 -name '.?*' -printf '%f ')
[[ -z $left ]] || fail "temporaries left: $left"
echo "ok: the rerun replaced r.csv ($(wc -l < r.csv) lines) and p.csv"
