#!/usr/bin/env bash
# Configures build/ (Release, warnings on) and builds the given targets, or everything.
#   scripts/build.sh [TARGET...]     run.sh: `slamprep` and what it links; test.sh: everything
set -euo pipefail
cd "$(dirname "$0")/.."
# Unity build (CMakeLists.txt, SLAMPREP_UNITY_BUILD): less CPU from scratch (the command's files
# -48 %, docs/notebook.md "Build time"); a developer's own build folder leaves it off.
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DSLAMPREP_UNITY_BUILD=ON
targets=()
(($#)) && targets=(--target "$@")
cmake --build build --parallel "$(nproc)" "${targets[@]}"
