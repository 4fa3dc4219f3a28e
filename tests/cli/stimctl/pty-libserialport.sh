# The libserialport backend against the same pty.  libserialport cannot open a Linux pty by
# itself (its lookup wants a /sys/class/tty entry, and sp_open fails on TIOCMGET, which ptys
# lack): the test reaches it through a symlink named so that the lookup resolves, and an
# LD_PRELOAD shim that answers the modem-line ioctls (tests/support/pty-modem-shim.c).
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
shim=$(dirname "$(command -v golden-diff)")/libpty-modem-shim.so
[[ -f $shim ]] || fail "no shim at $shim"
start_emu --record rec.jsonl
ln -s "$PORT" "$PWD/tty-link"
make_stimulus stim.json --frequency 200 --duration 0.5
# In the sanitizer build the ASan runtime must come first in the preload list.
asan=$(ldd "$(command -v stimctl)" | awk '/libasan/ { print $3 }')
LD_PRELOAD="${asan:+$asan:}$shim" stimctl --backend libserialport --port "/dev/../../..$PWD/tty-link" < stim.json 2> err.txt \
  || fail "stimctl over libserialport: $(cat err.txt)"
stop_emu
[[ $(lines rec.jsonl) -eq 100 ]] || fail "expected 100 pulses, got $(lines rec.jsonl)"
check_record rec.jsonl "$EXPECTED"
echo "ok: $(cat err.txt)"
