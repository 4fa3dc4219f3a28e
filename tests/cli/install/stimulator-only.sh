# A program that only drives a stimulator (stimctl, stim-emu) is the host over pulse/ and
# device/, without the model (issue 39; lib/CMakeLists.txt, docs/layout.md): its libraries
# (ldd) hold neither Ceres nor GLPK nor libpng (nor glog and gflags, Ceres' own), and no
# code of the model's is in it (nm: no symbol of fibre/, opt/, model/'s conductors, fields
# and arrays, render/ or psych/).  Before the split (47d114d) stimctl held 358 such
# symbols; its ldd showed no Ceres only because the linker drops a shared library nothing
# calls (--as-needed), hence the nm check.
: "${TP_BUILD:?}"
model='tp::(fibre|focus|minimax|render)::|tp::(Conductor|ConductorParams|Field|ElectrodeArray|Setup|Receptor|Skin|GridLattice|PixelBank|Calibration|Profile)\b'
for p in stimctl stim-emu; do
  exe=$TP_BUILD/tools/$p
  [[ -x $exe ]] || fail "$exe: not built"
  libs=$(ldd "$exe") || fail "ldd $p: $libs"
  heavy=$(grep -oE 'lib(ceres|glpk|png16|glog|gflags)[^ ]*' <<< "$libs" | tr '\n' ' ' || true)
  [[ -z $heavy ]] || fail "$p links $heavy"
  symbols=$(nm -C "$exe") || fail "nm $p"
  count=$(grep -cE "$model" <<< "$symbols" || true)
  [[ $count -eq 0 ]] || fail "$p holds $count symbols of the model, e.g. $(grep -m1 -oE "$model[^ (]*" <<< "$symbols" | head -1)"
  echo "ok: $p: $(grep -c '=>' <<< "$libs") shared libraries ($(grep -oE '^\s*lib[a-z0-9+_-]+' <<< "$libs" | tr -d ' \t' | tr '\n' ' ')), no symbol of the model"
done
