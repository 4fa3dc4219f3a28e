# A keep-alive replayed byte for byte (the same sequence number, type and payload: what
# the device's retransmission cache answers) does not keep the output alive: the device
# answers it again, but only a new frame of the session feeds the watchdog.  Through a
# real pty (raw-frames), against stim-emu and, with TP_DEVICE=firmware, the firmware.
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
A=$(le32 $((0x5EED1234)))
start_emu --record rec.jsonl --watchdog-ms 300
{
  echo "send 1 2 $(config $((0x5EED1234)) 8)"          # configure: session A
  echo "send 2 3 ${A}$(codes 100 -100 0 0 0 0 0 0)"    # set_weights
  echo "send 3 4 $A"                                   # start
  echo "send 4 7 $A"                                   # the last genuine keep-alive
  for _ in $(seq 60); do                               # the same frame again for 1.2 s
    echo "sleep 20"
    echo "send 4 7 $A"
  done
  echo "send 5 6"                                      # status: a query, feeds nothing
} | raw-frames "$PORT" > acks.txt || fail "raw-frames: $(cat acks.txt)"
sleep 0.2
stop_emu
result() { awk -v s="$1" '$1 == s { r = $2 } END { print r }' acks.txt; }
[[ $(result 1) == 0 && $(result 2) == 0 && $(result 3) == 0 ]] || fail "session not started: $(cat acks.txt)"
# Every replay was answered (from the cache: the same reply as the first).
replies=$(awk '$1 == 4 && $2 == 0' acks.txt | wc -l)
[[ $replies -ge 50 ]] || fail "only $replies of 61 keep-alives answered: $(cat acks.txt)"
# The status: idle (0), ended by the watchdog (fault 1).
status=$(awk '$1 == 5 { print $3 }' acks.txt)
[[ ${status:0:4} == 0001 ]] || fail "status $status: expected idle, ended by the watchdog"
n=$(lines rec.jsonl)
last=$(tail -1 rec.jsonl | jq .t_s)
# The genuine keep-alive came within ~0.1 s of the start; the watchdog is 300 ms.  Had the
# replays fed it, the output would have run for the whole 1.2 s.
awk -v t="$last" 'BEGIN { exit !(t >= 0.25 && t < 0.45) }' \
  || fail "output ended at $last s ($n pulses): the replayed keep-alives fed the watchdog"
echo "ok: 61 replays of one keep-alive answered; the output still ended at the watchdog ($n pulses, last at $last s)"

# Two older keep-alives of the session replayed in turn (neither is the last frame, so the
# cache does not catch them): only a frame newer than the last that fed the watchdog feeds it.
start_emu --record rec2.jsonl --watchdog-ms 300
{
  echo "send 1 2 $(config $((0x5EED1234)) 8)"
  echo "send 2 3 ${A}$(codes 100 -100 0 0 0 0 0 0)"
  echo "send 3 4 $A"
  echo "send 4 7 $A"
  echo "send 5 7 $A"                                   # the last genuine keep-alive
  for _ in $(seq 30); do
    echo "sleep 20"; echo "send 4 7 $A"
    echo "sleep 20"; echo "send 5 7 $A"
  done
  echo "send 6 6"
} | raw-frames "$PORT" > acks2.txt || fail "raw-frames: $(cat acks2.txt)"
sleep 0.2
stop_emu
status=$(awk '$1 == 6 { print $3 }' acks2.txt)
[[ ${status:0:4} == 0001 ]] || fail "alternating replays: status $status, expected idle, ended by the watchdog"
last=$(tail -1 rec2.jsonl | jq .t_s)
awk -v t="$last" 'BEGIN { exit !(t >= 0.25 && t < 0.45) }' \
  || fail "alternating replays: output ended at $last s: older keep-alives fed the watchdog"
echo "ok: keep-alives 4 and 5 replayed in turn for 1.2 s; the output still ended at the watchdog (last at $last s)"
