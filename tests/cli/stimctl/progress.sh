# Long work is visible (issue 38): on a terminal, stimctl shows the time, the pulses
# delivered of those scheduled, and live frames, on one line rewritten in place, cleared
# before its summary; after Ctrl-C the summary says how many pulses went out of how many.
# Not a terminal: nothing but the summary.
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
make_stimulus stim.json --frequency 200 --duration 1.5
python3 - stim.json > tty.out <<'PY' || fail "pty run: $(cat tty.out)"
import os, pty, sys, time
pid, fd = pty.fork()
if pid == 0:
    os.execvp("stimctl", ["stimctl", "--port", "emu", "--stimulus", sys.argv[1]])
out = b""
t0 = time.time()
interrupted = False
while True:
    if not interrupted and time.time() - t0 > 1.0:
        os.write(fd, b"\x03")  # Ctrl-C, through the terminal
        interrupted = True
    try:
        d = os.read(fd, 4096)
    except OSError:
        break
    if not d:
        break
    out += d
os.waitpid(pid, 0)
sys.stdout.write(out.decode(errors="replace"))
PY
grep -qE $'\rstimctl: 0\\.[0-9] of 1\\.5 s, [0-9]+ of 300 pulses' tty.out ||
  fail "no progress line on the terminal: $(cat -v tty.out)"
grep -qE 'stimctl: emu \(in-process emulator\): [0-9]+ of 300 pulses .*interrupted \(SIGINT\); output stopped' tty.out ||
  fail "no summary of the pulses after Ctrl-C: $(cat -v tty.out)"
# The summary is the last word: no second "stopped:" line repeats why.
! grep -q 'stimctl: stopped:' tty.out || fail "a second line after the summary: $(cat -v tty.out)"
# The summary starts a clean line: the progress line was cleared (\r, then erase).
grep -q $'\r\e\\[K' tty.out || fail "the progress line was not cleared: $(cat -v tty.out)"
stimctl --port emu --stimulus stim.json --duration 0.5 2> plain.err || fail "plain: $(cat plain.err)"
[[ $(wc -l < plain.err) -eq 1 ]] && ! grep -q $'\r' plain.err || fail "not a terminal, yet: $(cat -v plain.err)"
echo "ok: $(tr '\r' '\n' < tty.out | grep -c 'of 300 pulses') progress lines, then: $(grep -a 'output stopped' tty.out | tr -d '\r\033')"
