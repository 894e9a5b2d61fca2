# Sourced by scripts/sanitize.sh (address) and scripts/fuzz.sh: the one AddressSanitizer +
# UndefinedBehaviorSanitizer build both use, so CI compiles the project once for the unit tests
# under ASan+UBSan and for the libFuzzer targets. clang (libFuzzer needs it), -O1 -g with asserts
# on, every library instrumented with -fsanitize=fuzzer-no-link,address,undefined
# (CMake option MESOCAP_FUZZ).
ASAN_BUILD=$ROOT/build-asan

configure_asan_build() {
  CC=clang CXX=clang++ cmake -S "$ROOT" -B "$ASAN_BUILD" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g" \
    -DMESOCAP_FUZZ=ON -DMESOCAP_SANITIZE= -DMESOCAP_BUILD_TESTS=ON -DMESOCAP_BUILD_BENCH=OFF >/dev/null
}
