# Protocol-level safety through a real pty, frame by frame (raw-frames), as a second,
# hostile or confused host would talk: only the session that started the output feeds the
# watchdog; a replayed start after stop restarts nothing; over-limit codes and more
# channels than a frame may carry are refused.  The record shows what was delivered.
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
A=$(le32 $((0x1234ABCD))) B=$(le32 $((0x0BADF00D)))
start_emu --record raw.jsonl --watchdog-ms 300
{
  echo "send 250 4 $A"                                 # start before any configure
  echo "send 251 3 ${A}$(codes 100 -100 0 0 0 0 0 0)"  # weights before any configure
  echo "send 252 2 $(config $((0x1234ABCD)) 8)00"      # a configure one byte too long
  echo "send 253 9"                                    # an unknown message type
  echo "send 1 2 $(config $((0x1234ABCD)) 8)"          # configure: session A
  echo "send 2 3 ${A}$(codes 100 -100 0 0 0 0 0 0)"    # set_weights
  echo "send 3 4 $A"                                   # start
  seq=10
  for _ in $(seq 40); do                               # host B for 0.8 s, every 20 ms
    echo "send $((seq++)) $((seq % 2 ? 1 : 6))"        # identify or status
    echo "send $((seq++)) 2 $(config $((0x0BADF00D)) 9)"  # configure: refused (running; 9 channels)
    echo "send $((seq++)) 7 $B"                        # keep-alive of another session
    echo "send $((seq++)) 3 ${B}$(codes 500 -500 0 0 0 0 0 0)"  # its weights
    echo "sleep 20"
  done
  echo "send 200 5 $A"                                 # stop (the watchdog already did)
  echo "send 3 4 $A"                                   # the old start again, same seq
  echo "send 201 4 $A"                                 # and with a new seq
  echo "send 202 2 $(config $((0x0BADF00D)) 8)"        # a new session B may begin
  echo "send 203 3 ${B}$(codes 29683 -29683 0 0 0 0 0 0)"  # 29 mA codes
  echo "send 204 3 ${B}$(codes $(for i in $(seq 65); do echo 0; done))"  # 65 codes
  echo "send 205 2 $(config $((0x0BADF00D)) 65)"       # 65 channels
  echo "send 206 4 $B"                                 # start without weights
  echo "sleep 400"
} | raw-frames "$PORT" > acks.txt || fail "raw-frames: $(cat acks.txt)"
stop_emu
result() { awk -v s="$1" '$1 == s { r = $2 } END { print r }' acks.txt; }  # the last
expect() { [[ $(result "$1") == "$2" ]] || fail "frame $1 ($3): result $(result "$1"), expected $2"; }
expect 250 8 "start before configure"; expect 251 8 "weights before configure"
expect 252 2 "configure too long"; expect 253 1 "unknown type"
expect 1 0 configure; expect 2 0 set_weights; expect 3 8 "replayed start after stop"
expect 201 8 "start after stop"; expect 202 0 "new session"; expect 203 3 "29 mA codes"
expect 204 2 "65 codes"; expect 205 6 "65 channels"; expect 206 4 "start without weights"
# Host B's keep-alives and weights were refused; its configure was refused while running.
awk '$1 >= 10 && $1 < 200 && ($1 - 10) % 4 == 2 && $2 != 8 { exit 1 }' acks.txt || fail "another session's keep-alive accepted"
awk '$1 >= 10 && $1 < 200 && ($1 - 10) % 4 == 3 && $2 != 8 { exit 1 }' acks.txt || fail "another session's weights accepted"
awk '$1 >= 10 && $1 < 200 && ($1 - 10) % 4 == 1 && $2 != 7 && $2 != 6 { exit 1 }' acks.txt || fail "configure while running: $(cat acks.txt)"
n=$(lines raw.jsonl)
last=$(tail -1 raw.jsonl | jq .t_s)
# The output started at t = 0 and nothing of session A came after: it must end at the
# watchdog (300 ms: 60 pulses at 200 Hz), although host B talked every 20 ms for 0.8 s.
awk -v t="$last" 'BEGIN { exit !(t >= 0.28 && t < 0.3) }' || fail "output ended at $last s, not at the 300 ms watchdog"
[[ $n -ge 57 && $n -le 61 ]] || fail "$n pulses, expected ~60 (300 ms at 200 Hz)"
jq -se 'map(.currents_mA[0] > 0.09 and .currents_mA[0] < 0.1) | all' raw.jsonl > /dev/null || fail "a pulse carried another session's weights"
echo "ok: session A's output ended at the watchdog ($n pulses, last at $last s) while host B talked; B's frames refused; replayed start refused"
