#!/usr/bin/env bash
# Builds slamprep and its tests with AddressSanitizer + UndefinedBehaviorSanitizer into
# build-asan/ and runs the test suite under them. Any sanitizer report fails the test it occurs
# in (UBSan does not recover; ASan aborts), so a clean run is a passing ctest.
#   scripts/sanitize.sh            the whole test suite
#   scripts/sanitize.sh --fast     every test except the Bullet ones (ctest label `sim`)
#   scripts/sanitize.sh --ci       only the tests of slamprep::formats (tests/formats_dataset,
#                                  tests/formats, the corpus replay of its readers: mcap, carmen,
#                                  dataset, relations, bag), built against formats and metrics
#                                  alone (fuzz/CMakeLists.txt) into build-asan-ci/: the subset
#                                  .ci/run can afford in its 10 minutes
#   scripts/sanitize.sh -- ARGS    extra ctest arguments, e.g. -- -L export
set -euo pipefail
cd "$(dirname "$0")/.."
jobs="${SANITIZE_JOBS:-$(nproc)}"
# detect_leaks: LeakSanitizer needs ptrace-like access that some containers deny; it is on
# unless SANITIZE_LEAKS=0.
export ASAN_OPTIONS="detect_leaks=${SANITIZE_LEAKS:-1}:abort_on_error=1:strict_string_checks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
# Leaks inside system libraries (Mesa) are not ours: scripts/lsan-suppressions.txt names them.
export LSAN_OPTIONS="suppressions=$PWD/scripts/lsan-suppressions.txt:print_suppressions=0"

if [[ "${1:-}" == "--ci" ]]; then
  shift
  [[ "${1:-}" == "--" ]] && shift
  compiler=()  # clang when there is one: it builds this subset ~2.4x faster than GCC 12
  command -v clang++ > /dev/null && compiler=(-DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++)
  # Unity build: the libraries compile in batches (CMakeLists.txt, SLAMPREP_UNITY_BUILD).
  cmake -S fuzz -B build-asan-ci -G Ninja -DSLAMPREP_READER_TESTS=ON -DCMAKE_BUILD_TYPE= \
    -DSLAMPREP_UNITY_BUILD=ON "${compiler[@]}"
  cmake --build build-asan-ci --parallel "$jobs"
  log=$(mktemp /tmp/slamprep-ctest-asan.XXXXXX)
  ctest --test-dir build-asan-ci --output-on-failure --parallel "$jobs" --timeout 600 "$@" |
    tee "$log"
  # As in scripts/test.sh: in CI a skipped test is a test that did not run.
  if [ "${CI:-}" = true ] && grep -E '\*\*\*(Skipped|Not Run)' "$log"; then
    echo "sanitize.sh: CI=true and the tests above were skipped or not run" >&2
    exit 1
  fi
  rm -f "$log"
  exit 0
fi

ctest_args=()
if [[ "${1:-}" == "--fast" ]]; then
  ctest_args+=(-LE sim)
  shift
fi
[[ "${1:-}" == "--" ]] && shift
ctest_args+=("$@")
flags="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_C_FLAGS="$flags" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=address,undefined"
cmake --build build-asan --parallel "$jobs"

ctest --test-dir build-asan --output-on-failure --parallel "$jobs" --timeout 1800 "${ctest_args[@]}"
