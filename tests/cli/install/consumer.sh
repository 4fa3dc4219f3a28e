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
cmake -S "$TP_SOURCE/tests/consumer" -B consumer -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_CXX_FLAGS="$san" -DCMAKE_EXE_LINKER_FLAGS="${san%% -D*}" \
  -DCMAKE_PREFIX_PATH="$P" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF > configure.log 2>&1 \
  || fail "configure: $(grep -m3 -i error configure.log)"
grep -F "$P" consumer/CMakeCache.txt | grep -q TactilePrimaries_DIR || fail "not found under P: $(grep TactilePrimaries_DIR consumer/CMakeCache.txt)"
cmake --build consumer > build.log 2>&1 || fail "build: $(grep -m3 error build.log)"
./consumer/consumer > cmake.out || fail "consumer (CMake): $(cat cmake.out)"
# pkg-config
export PKG_CONFIG_PATH=$P/lib/pkgconfig:$P/lib/x86_64-linux-gnu/pkgconfig
pkg-config --exists tactile-primaries || fail "pkg-config: $(pkg-config --print-errors --exists tactile-primaries 2>&1)"
c++ -std=c++17 -O1 $san "$TP_SOURCE/tests/consumer/main.cpp" -o pc-consumer $(pkg-config --cflags --libs tactile-primaries) \
  2> pc.log || fail "pkg-config build: $(grep -m3 error pc.log)"
./pc-consumer > pc.out || fail "consumer (pkg-config): $(cat pc.out)"
cmp -s cmake.out pc.out || fail "the two builds disagree"
echo "ok: $(tr '\n' ';' < cmake.out)"
