# calibrate's files: the log's every write checked (/dev/full at its first line, a file
# size limit mid-session), and --output FILE written whole or left as it was: a previous
# profile survives q after a trial and SIGTERM during one.
source "$TP_SOURCE/tests/cli/render-tactile/common.sh"
base=(calibrate --bank "$BANK" --primaries SAI --port emu --emu-channels 64)
cal=("${base[@]}" --trial-duration 0.05)
refuses 1 --says "--log: cannot write '/dev/full': No space left on device" \
  -- "${cal[@]}" --log /dev/full --record full.jsonl --responses -
[[ $(lines full.jsonl) -eq 0 ]] || fail "/dev/full: pulses delivered"
# A log that fills up mid-session (1 KiB, SIGXFSZ ignored: write(2) fails with EFBIG).
rc=0
{ (trap '' XFSZ; ulimit -f 1; yes y | head -1000 | "${cal[@]}" --log big.csv --responses - 2>&1) | cat > big.err; } || rc=$?
[[ $rc == 1 ]] || fail "a full log: exit $rc: $(tail -2 big.err)"
[[ $(tail -1 big.err) == "calibrate: --log: cannot write 'big.csv': File too large" ]] \
  || fail "a full log: $(tail -2 big.err)"
[[ $(tail -c 1 big.csv | od -An -c | tr -d ' ') == '\n' ]] || fail "a full log ends in a cut line: $(tail -c 40 big.csv)"
awk -F, 'NF != 12 { exit 1 }' big.csv || fail "a full log: a row without its 12 columns"
echo "ok: a full log after $(($(lines big.csv) - 1)) trials: $(tail -1 big.err)"

# --output: the previous profile survives q, and a signal during a trial.
echo '{"the previous": "profile"}' > prof.json
cp prof.json before.json
no_temporaries() { compgen -G '.prof.json.*' > /dev/null && fail "$1: a temporary left: $(ls -A)"; true; }
echo q | "${cal[@]}" --log q.csv --responses - --output prof.json > q.out 2> q.err && fail "q: exit 0"
grep -q "stopped by the user (q) after trial 1" q.err || fail "q: $(cat q.err)"
cmp -s prof.json before.json || fail "q: the previous profile is gone: $(cat prof.json)"
[[ ! -s q.out ]] || fail "q: stdout"
no_temporaries q
echo "ok: q after a trial: the previous profile kept"
mkfifo answers
"${base[@]}" --log sig.csv --trial-duration 5 --rates SAI:10 --record sig.jsonl --responses - \
  --output prof.json < answers > sig.out 2> sig.err &
pid=$!
exec 3> answers
for _ in $(seq 500); do [[ $(lines sig.jsonl) -ge 2 ]] && break; sleep 0.01; done
kill -TERM "$pid"
rc=0; wait "$pid" || rc=$?
exec 3>&-
[[ $rc == 143 ]] || fail "SIGTERM: exit $rc: $(cat sig.err)"
grep -q "stopped by SIGTERM; output stopped" sig.err || fail "SIGTERM: $(cat sig.err)"
cmp -s prof.json before.json || fail "SIGTERM: the previous profile is gone: $(cat prof.json)"
no_temporaries SIGTERM
[[ $(lines sig.jsonl) -lt 30 ]] || fail "SIGTERM: $(lines sig.jsonl) pulses of 50"
echo "ok: SIGTERM during a trial after $(lines sig.jsonl) pulses of 50: the previous profile kept"
