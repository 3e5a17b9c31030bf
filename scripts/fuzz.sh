#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/, clang, ASan + UBSan) into build-fuzz/ and runs each for a
# bounded time on its corpus in fuzz/corpus/<reader>/ (new inputs are added there).
#   scripts/fuzz.sh [SECONDS_PER_READER] [READER...]     default: 60 s, every reader
# Crashes (and non-InputError exceptions, hangs > 10 s, > 2 GB) are kept in
# build-fuzz/artifacts/<reader>/ and the run goes on (fork mode); copy each one, minimised, to
# fuzz/regressions/<reader>/ so ctest replays it (tests/formats/fuzz_regression_test.cpp).
# Exit status: 0 when no reader produced an artifact, 1 otherwise.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
shift || true
readers=("$@")
((${#readers[@]})) || readers=(mcap carmen dataset world scenario suite censi relations calibration bag)
jobs="${FUZZ_BUILD_JOBS:-2}"

mkdir -p build-fuzz
log=build-fuzz/build.log
cmake -S fuzz -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ > "$log" 2>&1 || { cat "$log"; exit 2; }
targets=()
for r in "${readers[@]}"; do targets+=("fuzz_$r"); done
cmake --build build-fuzz --target "${targets[@]}" -j"$jobs" >> "$log" 2>&1 || { tail -50 "$log"; exit 2; }

status=0
for r in "${readers[@]}"; do
  corpus="fuzz/corpus/$r"
  artifacts="build-fuzz/artifacts/$r"
  rm -rf "$artifacts"  # findings of this run only
  mkdir -p "$corpus" "$artifacts" "build-fuzz/logs"
  log="build-fuzz/logs/$r.log"
  # -fork=1 -ignore_crashes=1: keep fuzzing after a finding; -max_total_time bounds the run.
  ./build-fuzz/fuzz_"$r" "$corpus" -fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 \
    -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
    -artifact_prefix="$artifacts/" > "$log" 2>&1 || true
  execs=$(grep -o 'exec/s: [0-9]*\|#[0-9]*' "$log" | grep '^#' | tail -1 | tr -d '#')
  # Keep the committed corpus small: merge it down to the inputs that add edge coverage
  # (-use_counters=0: hit counts would keep ~4x more files, 1350 instead of 332 for dataset).
  merged="build-fuzz/merge/$r"
  rm -rf "$merged" && mkdir -p "$merged"
  if ./build-fuzz/fuzz_"$r" -merge=1 -use_counters=0 -timeout=10 -rss_limit_mb=2048 \
    "$merged" "$corpus" >> "$log" 2>&1 &&
    [ -n "$(ls -A "$merged")" ]; then
    rm -rf "$corpus" && mv "$merged" "$corpus"
  fi
  found=$(find "$artifacts" -type f | wc -l)
  echo "fuzz $r: ${seconds}s, ${execs:-?} executions, corpus $(ls "$corpus" | wc -l) files, $found artifacts"
  ((found == 0)) || status=1
done
exit "$status"
