#!/usr/bin/env bash
# Builds slamprep and its tests with AddressSanitizer + UndefinedBehaviorSanitizer into
# build-asan/ and runs the test suite under them. Any sanitizer report fails the test it occurs
# in (UBSan does not recover; ASan aborts), so a clean run is a passing ctest.
#   scripts/sanitize.sh            the whole test suite
#   scripts/sanitize.sh --fast     every test except the Bullet ones (ctest label `sim`)
#   scripts/sanitize.sh -- ARGS    extra ctest arguments, e.g. -- -L export
set -euo pipefail
cd "$(dirname "$0")/.."
ctest_args=()
if [[ "${1:-}" == "--fast" ]]; then
  ctest_args+=(-LE sim)
  shift
fi
[[ "${1:-}" == "--" ]] && shift
ctest_args+=("$@")
jobs="${SANITIZE_JOBS:-$(nproc)}"

flags="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_C_FLAGS="$flags" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=address,undefined"
cmake --build build-asan --parallel "$jobs"

# detect_leaks: LeakSanitizer needs ptrace-like access that some containers deny; it is on
# unless SANITIZE_LEAKS=0.
export ASAN_OPTIONS="detect_leaks=${SANITIZE_LEAKS:-1}:abort_on_error=1:strict_string_checks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
ctest --test-dir build-asan --output-on-failure --parallel "$jobs" --timeout 1800 "${ctest_args[@]}"
