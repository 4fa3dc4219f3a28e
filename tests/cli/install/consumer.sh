# A project of someone else's builds against the installed package, not the build tree:
# find_package(TactilePrimaries CONFIG) and TactilePrimaries::model (tests/consumer), and
# the same program through pkg-config.  It computes a field, checked against a finite
# difference of the potential.
: "${TP_BUILD:?}"
P=$PWD/P
cmake --install "$TP_BUILD" --prefix "$P" > install.log 2>&1 || fail "install: $(tail -3 install.log)"
[[ -f $P/include/tactile-primaries/model/conductor.hpp ]] || fail "headers not installed"
[[ ! -e $P/include/tactile-primaries/cli ]] || fail "the programs' cli/ headers were installed"
# A sanitizer build's archives need the consumer built with the same instrumentation.
san=
if nm "$P/lib/libtactile-primaries-model.a" 2> /dev/null | grep -- __asan_ > /dev/null; then
  san="-fsanitize=address,undefined -DEIGEN_MALLOC_ALREADY_ALIGNED=1"
fi
# The package registry and the build tree stay out of the search: only P.
source "$TP_SOURCE/tests/cli/install/helpers.sh"
export PKG_CONFIG_PATH=$P/lib/pkgconfig:$P/lib/x86_64-linux-gnu/pkgconfig
pkg-config --exists tactile-primaries || fail "pkg-config: $(pkg-config --print-errors --exists tactile-primaries 2>&1)"
build_consumer "$san" -DCMAKE_EXE_LINKER_FLAGS="${san%% -D*}" -DCMAKE_PREFIX_PATH="$P"
grep -F "$P" consumer/CMakeCache.txt | grep -q TactilePrimaries_DIR || fail "not found under P: $(grep TactilePrimaries_DIR consumer/CMakeCache.txt)"
echo "ok: $(tr '\n' ';' < cmake.out)"
