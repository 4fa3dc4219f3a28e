# Helpers of the install tests (sourced by their scripts).  Commands run behind the array
# `run` when a script sets it (apt.sh: only what a user of the package has).
run=("${run[@]}")

# complete_words_from DIR WORD...: what TAB offers after the last word, bash-completion loaded
# and the program's completion sourced from DIR/<program>; DIR "-": found by
# bash-completion's own loader, as an interactive bash does on the first TAB.
complete_words_from() {
  "${run[@]}" bash -c 'source /usr/share/bash-completion/bash_completion
    if [[ $0 == - ]]; then __load_completion "$1"; else source "$0/$1"; fi
    COMP_WORDS=("$@"); COMP_CWORD=$(($# - 1)); COMP_LINE="$*"; COMP_POINT=${#COMP_LINE}
    spec=$(complete -p "$1"); fn=${spec#*-F }; fn=${fn%% *}
    "$fn" "$1" "${COMP_WORDS[COMP_CWORD]}" "${COMP_WORDS[COMP_CWORD-1]}"
    printf "%s\n" "${COMPREPLY[@]}"' "$@"
}

# build_consumer CXXFLAGS [CMAKE ARGS...]: tests/consumer built by CMake (./consumer) and by
# pkg-config (./pc-consumer), both with CXXFLAGS, and run; they must agree (cmake.out).
build_consumer() {
  local flags=$1; shift
  "${run[@]}" cmake -S "$TP_SOURCE/tests/consumer" -B consumer -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF "$@" > configure.log 2>&1 \
    || fail "consumer: configure: $(grep -m3 -i error configure.log)"
  "${run[@]}" cmake --build consumer > build.log 2>&1 || fail "consumer: build: $(grep -m3 error build.log)"
  ./consumer/consumer > cmake.out || fail "consumer (CMake): $(cat cmake.out)"
  "${run[@]}" bash -c 'c++ -std=c++17 -O1 $0 "$1" -o pc-consumer $(pkg-config --cflags --libs tactile-primaries)' \
    "$flags" "$TP_SOURCE/tests/consumer/main.cpp" 2> pc.log || fail "consumer (pkg-config): $(grep -m3 error pc.log)"
  ./pc-consumer > pc.out || fail "consumer (pkg-config): $(cat pc.out)"
  cmp -s cmake.out pc.out || fail "the CMake and pkg-config builds disagree: $(cat cmake.out) / $(cat pc.out)"
}
