# The waveform CSV: every instant sums to zero over the channels and each channel's charge
# per pulse is zero (trapezoid rule over the corners); scripts/plot-pulse draws it.
make-pulse --amplitude 1.5 --frequency 100 --width 200 --balance-width 600 --interphase 30 --count 3 --format csv \
  < "$TP_INPUTS/sai-weights.json" > wave.csv 2> /dev/null
[[ $(head -1 wave.csv) == t_us,ch0_mA,ch1_mA,ch2_mA,ch3_mA,ch4_mA,ch5_mA,ch6_mA,ch7_mA ]] || fail "header $(head -1 wave.csv)"
tail -n +2 wave.csv | awk -F, '
  function abs(v) { return v < 0 ? -v : v }
  { s = 0; for (i = 2; i <= NF; i++) s += $i; if (abs(s) > 1e-9) { print "sum " s " at t=" $1; bad = 1 }
    if (NR > 1) for (i = 2; i <= NF; i++) q[i] += (prev_t == $1 ? 0 : ($1 - prev_t) * prev[i])
    prev_t = $1; for (i = 2; i <= NF; i++) prev[i] = $i }
  END { for (i in q) if (abs(q[i]) > 1e-9) { print "channel " i - 2 " net charge " q[i] " nC"; bad = 1 }; exit bad }' \
  || fail "waveform not balanced"
"$TP_SOURCE/scripts/plot-pulse" -o pulse.png wave.csv 2> /dev/null || fail "plot-pulse"
[[ $(head -c 4 pulse.png | od -An -tx1 | tr -d ' \n') == 89504e47 ]] || fail "not a PNG"
echo "ok"
