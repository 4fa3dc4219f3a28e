# sweep-spacing --engine parallel over ssh: an sshd on a free loopback port, with its own
# host and user keys in this test's directory, is "another host" in the --sshloginfile;
# every array runs through it, and the CSV is the local engine's, byte for byte.
# Skipped (77) where sshd cannot start, unless TP_REQUIRE_CLUSTER=1 (CI).
sshd=$(command -v sshd || echo /usr/sbin/sshd)
[[ -x $sshd ]] || skip TP_REQUIRE_CLUSTER "no sshd (scripts/setup cluster installs openssh-server)"
command -v ssh > /dev/null && command -v parallel > /dev/null || skip TP_REQUIRE_CLUSTER "no ssh or GNU parallel"
[[ $(id -u) -eq 0 ]] || skip TP_REQUIRE_CLUSTER "sshd's privilege separation needs root (this is uid $(id -u))"

chmod 755 "$PWD"
ssh-keygen -q -t ed25519 -N '' -f hostkey && ssh-keygen -q -t ed25519 -N '' -f userkey || skip TP_REQUIRE_CLUSTER "ssh-keygen failed"
cp userkey.pub authorized_keys
port=$((30000 + $$ % 5000))
while (echo > /dev/tcp/127.0.0.1/$port) 2> /dev/null; do port=$((port + 1)); done
cat > sshd_config << EOF2
Port $port
ListenAddress 127.0.0.1
HostKey $PWD/hostkey
AuthorizedKeysFile $PWD/authorized_keys
AuthenticationMethods publickey
PasswordAuthentication no
KbdInteractiveAuthentication no
PermitRootLogin prohibit-password
UsePAM no
StrictModes no
PidFile $PWD/sshd.pid
LogLevel INFO
EOF2
mkdir -p /run/sshd
"$sshd" -f "$PWD/sshd_config" -E "$PWD/sshd.log" || skip TP_REQUIRE_CLUSTER "sshd did not start: $(tail -3 sshd.log)"
trap 'kill "$(cat sshd.pid 2> /dev/null)" 2> /dev/null || true; cleanup' EXIT
for _ in $(seq 100); do (echo > /dev/tcp/127.0.0.1/$port) 2> /dev/null && break; sleep 0.05; done
login="ssh -p $port -i $PWD/userkey -o StrictHostKeyChecking=no -o UserKnownHostsFile=/dev/null -o BatchMode=yes -o LogLevel=ERROR 127.0.0.1"
$login true || skip TP_REQUIRE_CLUSTER "ssh to the test's sshd failed: $(tail -3 sshd.log)"
echo "ok: sshd on 127.0.0.1:$port"

sweep=$TP_SOURCE/scripts/sweep-spacing
args=(--electrodes 4,6,8 --pitch 0.6:1.4:0.4 --modes RA,SAI,PC)
"$sweep" "${args[@]}" > local.csv || fail "local engine"
echo "2/$login" > hosts
before=$(grep -c 'Accepted publickey' sshd.log)
"$sweep" --engine parallel --sshloginfile hosts --state st "${args[@]}" > ssh.csv 2> err.txt || fail "over ssh: $(cat err.txt)"
cmp local.csv ssh.csv || fail "the CSV over ssh differs from local's"
# Every array ran on the ssh "host" (GNU parallel's joblog names it), each through a login.
on_ssh=$(awk -F'\t' -v h="$login" 'NR > 1 && $2 == h && $7 == 0' st/joblog | wc -l)
[[ $on_ssh -eq 9 ]] || fail "$on_ssh of 9 arrays ran over ssh: $(cut -f1,2,7 st/joblog)"
logins=$(($(grep -c 'Accepted publickey' sshd.log) - before))
[[ $logins -ge 9 ]] || fail "only $logins ssh logins for 9 arrays"
echo "ok: 9 arrays over ssh ($logins logins), the local engine's CSV byte for byte"
