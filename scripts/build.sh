#!/usr/bin/env bash
# Configures build/ (Release, warnings on) and builds the given targets, or everything.
#   scripts/build.sh [TARGET...]     run.sh: `slamprep` and what it links; test.sh: everything
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
targets=()
(($#)) && targets=(--target "$@")
cmake --build build --parallel "$(nproc)" "${targets[@]}"
