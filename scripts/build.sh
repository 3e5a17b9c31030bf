#!/usr/bin/env bash
# Configures build/ (Release, warnings on) and builds the given targets, or everything.
#   scripts/build.sh [-DOPTION=VALUE...] [TARGET...]
#     run.sh: `slamprep` and what it links; test.sh: everything but the formats tests, which it
#     runs in its sanitizer build (-DSLAMPREP_FORMATS_TESTS=OFF)
set -euo pipefail
cd "$(dirname "$0")/.."
# A fresh build/ compiles with clang when there is one (scripts/install-deps.sh installs it): it
# builds everything in 0.8x the CPU time of GCC 12, and the default suite's results are the same
# bytes with either (docs/notebook.md, "Build time"). A build/ already configured keeps its compiler.
options=()
while (($#)) && [[ $1 == -D* ]]; do
  options+=("$1")
  shift
done
compiler=()
if [[ ! -f build/CMakeCache.txt ]] && command -v clang++ > /dev/null; then
  compiler=(-DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++)
fi
# Unity build (CMakeLists.txt, SLAMPREP_UNITY_BUILD): less CPU from scratch (the command's files
# -48 %); a developer's own build folder leaves it off. The tests compile at -O0
# (SLAMPREP_TEST_COMPILE_OPTIONS): the code they test is in the optimised libraries.
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DSLAMPREP_UNITY_BUILD=ON \
  -DSLAMPREP_TEST_COMPILE_OPTIONS=-O0 "${compiler[@]}" "${options[@]}"
targets=()
(($#)) && targets=(--target "$@")
cmake --build build --parallel "$(nproc)" "${targets[@]}"
