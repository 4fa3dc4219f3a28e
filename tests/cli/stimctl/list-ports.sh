# --list prints CSV through libserialport (the machine may have no ports at all).
stimctl --list > ports.csv 2> err.txt || fail "--list: $(cat err.txt)"
[[ $(head -1 ports.csv) == port,description ]] || fail "header: $(head -1 ports.csv)"
echo "ok: $(($(wc -l < ports.csv) - 1)) ports"
