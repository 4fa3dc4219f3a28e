# The Debian package, installed system-wide with apt-get as a user would: the README's main
# pipeline, sweep-spacing, man pages, bash completion and the library (tests/consumer)
# from /usr, then removed.  It
# changes the machine, so it runs only with TP_SYSTEM_INSTALL=1 (CI's fresh machine sets
# it), as root or with sudo; skipped (77) otherwise.
: "${TP_BUILD:?}"
if [[ ${TP_SYSTEM_INSTALL:-0} != 1 ]]; then
  echo "SKIP: installs into /usr: run with TP_SYSTEM_INSTALL=1 (CI does)"
  exit 77
fi
sudo=()
if [[ $(id -u) -ne 0 ]]; then
  sudo -n true 2> /dev/null || fail "TP_SYSTEM_INSTALL=1 needs root or sudo without a password"
  sudo=(sudo -n)
fi
dpkg-query -W -f='${Status}' tactile-primaries 2> /dev/null | grep -q 'install ok installed' \
  && fail "tactile-primaries is installed already; remove it first (apt-get remove tactile-primaries)"

cpack -G DEB -B "$PWD/pkg" --config "$TP_BUILD/CPackConfig.cmake" > cpack.log 2>&1 || fail "cpack: $(tail -3 cpack.log)"
deb=$(ls "$PWD"/pkg/tactile-primaries_*.deb) || fail "no package: $(ls pkg)"
chmod 755 "$PWD" "$PWD/pkg" && chmod 644 "$deb"  # apt's _apt user reads it
remove() { "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get remove -y -qq tactile-primaries > /dev/null 2>&1 || true; }
trap 'remove; cleanup' EXIT
"${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "$deb" > apt.log 2>&1 \
  || fail "apt-get install: $(grep -E '^E:' apt.log | head -3 | tr '\n' ' ')"
echo "ok: apt-get install $(basename "$deb")"

# From now on only what a user of the package has: /usr/bin and /bin, an empty home.
mkdir home
user_env=(env -i HOME="$PWD/home" PATH=/usr/bin:/bin LANG=C.UTF-8)
run=("${user_env[@]}")
source "$TP_SOURCE/tests/cli/install/helpers.sh"
[[ $("${user_env[@]}" bash -c 'command -v af-field') == /usr/bin/af-field ]] || fail "af-field is not /usr/bin/af-field"
version=$("${user_env[@]}" af-field --version) || fail "af-field --version"
[[ $version =~ ^af-field\ [0-9]+\.[0-9]+\.[0-9]+$ ]] || fail "af-field --version: $version"

# The README's main pipeline.
"${user_env[@]}" bash -o pipefail -c \
  'optimize-weights --mode SAI | make-pulse --amplitude 1.0 --frequency 200 | stimctl --port emu --duration 1' \
  > pipeline.out 2> pipeline.err || fail "the pipeline: $(cat pipeline.err)"
grep -E '^stimctl: .*200 of 200 pulses on 8 channels at 200 Hz, peak 1\.0[0-9]* mA.*stimulus complete; output stopped' \
  pipeline.err > /dev/null || fail "the pipeline's summary: $(cat pipeline.err)"
echo "ok: $(grep '^stimctl:' pipeline.err)"
# A sweep with the installed script and programs.
"${user_env[@]}" tp-sweep-spacing --electrodes 4,6 --pitch 1:1.5:0.5 --modes SAI > sweep.csv 2> err.txt \
  || fail "tp-sweep-spacing: $(cat err.txt)"
[[ $(wc -l < sweep.csv) -eq 5 ]] || fail "tp-sweep-spacing: $(cat sweep.csv)"
# The receptor table, with no path given.
"${user_env[@]}" af-field --summary > summary.json 2> err.txt || fail "af-field --summary: $(cat err.txt)"
grep -F '"SAI"' summary.json > /dev/null || fail "af-field --summary: $(head -c 300 summary.json)"

# man af-field, and the overview.
[[ $("${user_env[@]}" man -w af-field) == /usr/share/man/man1/af-field.1.gz ]] || fail "man -w af-field: $("${user_env[@]}" man -w af-field 2>&1)"
"${user_env[@]}" MANWIDTH=100 MANPAGER=cat man af-field > man.txt 2> /dev/null || fail "man af-field"
grep -E '^NAME' man.txt > /dev/null && grep -- '--electrodes' man.txt > /dev/null || fail "man af-field: $(head -5 man.txt)"
"${user_env[@]}" MANPAGER=cat man 7 tactile-primaries 2> /dev/null | grep 'make-pulse --amplitude' > /dev/null || fail "man 7 tactile-primaries"
echo "ok: man af-field ($(wc -l < man.txt) lines), man 7 tactile-primaries"

# Bash completion as an interactive bash loads it: bash-completion's loader, on first TAB.
"${user_env[@]}" bash -c 'source /usr/share/bash-completion/bash_completion; __load_completion af-field; complete -p af-field' \
  > complete.txt 2>&1 || fail "complete -p af-field: $(cat complete.txt)"
grep -E '^complete -F _tactile_primaries.* af-field$' complete.txt > /dev/null || fail "complete -p af-field: $(cat complete.txt)"
complete_words_from - optimize-weights --mode "" > modes.txt 2>&1
[[ $(sort modes.txt | tr '\n' ' ') == "PC RA SAI " ]] || fail "optimize-weights --mode TAB: $(cat modes.txt)"
echo "ok: $(cat complete.txt); optimize-weights --mode TAB: $(sort modes.txt | tr '\n' ' ')"
# The installed sweep script: its page and its completion.
"${user_env[@]}" MANPAGER=cat man tp-sweep-spacing 2> /dev/null | grep -- '--sshloginfile' > /dev/null || fail "man tp-sweep-spacing"
complete_words_from - tp-sweep-spacing --engine "" > engines.txt 2>&1
[[ $(tr '\n' ' ' < engines.txt) == "local parallel slurm " ]] || fail "tp-sweep-spacing --engine TAB: $(cat engines.txt)"
echo "ok: man tp-sweep-spacing; tp-sweep-spacing --engine TAB: $(tr '\n' ' ' < engines.txt)"

# The library from the package: tests/consumer found in /usr by CMake (no prefix given)
# and by pkg-config (no path given).
build_consumer ""
grep -E '^TactilePrimaries_DIR:PATH=/usr/lib/' consumer/CMakeCache.txt > /dev/null \
  || fail "consumer: $(grep TactilePrimaries_DIR consumer/CMakeCache.txt)"
echo "ok: tests/consumer against /usr, by CMake and pkg-config: $(tr '\n' ';' < cmake.out)"

# The Python module from /usr, with no path given.
if [[ $TP_PYTHON_BUILT == ON ]]; then
  (cd home && "${user_env[@]}" python3 -c '
import tactile_primaries as tp
assert tp.__file__.startswith("/usr/lib/python3/dist-packages/"), tp.__file__
doc = tp.optimize_weights(tp.Document.create(), "SAI")
with tp.Stimulator("emu") as s:
    r = s.deliver(tp.make_pulse(doc, 1.0, 200, duration_s=0.1))
print(tp.__file__, r["pulses"], "pulses")' > ../py.txt 2> ../err.txt) || fail "import tactile_primaries from /usr: $(cat err.txt)"
  echo "ok: $(cat py.txt)"
fi

remove
[[ ! -e /usr/bin/af-field && ! -e /usr/share/man/man1/af-field.1.gz ]] || fail "apt-get remove left files"
[[ ! -e /usr/lib/python3/dist-packages/tactile_primaries ]] || fail "apt-get remove left $(find /usr/lib/python3/dist-packages/tactile_primaries | head -3)"
echo "ok: apt-get remove tactile-primaries"
