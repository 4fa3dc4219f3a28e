# The Debian package (cpack -G DEB): its runtime dependencies are derived by dpkg-shlibdeps
# and are runtime libraries only, never a -dev package; it holds the programs, man pages,
# completion and data; lintian finds no error in it.
: "${TP_BUILD:?}"
cpack -G DEB -B "$PWD/pkg" --config "$TP_BUILD/CPackConfig.cmake" > cpack.log 2>&1 || fail "cpack: $(tail -3 cpack.log)"
deb=$(ls pkg/tactile-primaries_*.deb) || fail "no package: $(ls pkg)"
depends=$(dpkg-deb -f "$deb" Depends)
[[ -n $depends ]] || fail "no Depends"
if tr ',' '\n' <<< "$depends" | grep -E -- '-dev( |$)' > /dev/null; then fail "Depends holds a -dev package: $depends"; fi
tr ',' '\n' <<< "$depends" | grep -E '^ ?libc6 ' > /dev/null || fail "Depends lacks libc6: $depends"
dpkg-deb -c "$deb" > contents.txt
for f in ./usr/bin/af-field ./usr/bin/stimctl ./usr/bin/tp-sweep-spacing ./usr/share/man/man1/af-field.1.gz \
         ./usr/share/man/man7/tactile-primaries.7.gz ./usr/share/man/man1/tp-sweep-spacing.1.gz \
         ./usr/share/bash-completion/completions/af-field ./usr/share/bash-completion/completions/tp-sweep-spacing \
         ./usr/share/tactile-primaries/receptors.json ./usr/share/doc/tactile-primaries/copyright \
         ./usr/share/doc/tactile-primaries/changelog.gz ./usr/lib/cmake/TactilePrimaries/TactilePrimariesConfig.cmake; do
  grep -F " $f" contents.txt > /dev/null || fail "not in the package: $f"
done
if [[ $TP_PYTHON_BUILT == ON ]]; then
  for f in ./usr/lib/python3/dist-packages/tactile_primaries/__init__.py \
           ./usr/lib/python3/dist-packages/tactile_primaries/__init__.pyi \
           ./usr/lib/python3/dist-packages/tactile_primaries/_core.cpython-; do
    grep -F " $f" contents.txt > /dev/null || fail "not in the package: $f"
  done
  for d in "python3 (>= 3." "python3 (<< 3." "python3-numpy"; do
    grep -F "$d" <<< "$depends" > /dev/null || fail "Depends lacks $d: $depends"
  done
fi
command -v lintian > /dev/null || fail "lintian is not installed (scripts/setup installs it)"
lintian --fail-on error "$deb" > lintian.txt 2>&1 || fail "lintian: $(grep '^E:' lintian.txt | head -5 | tr '\n' ';')"
echo "ok: $(basename "$deb"); Depends: $depends; lintian: $(grep -c '^W:' lintian.txt) warnings, no error"
