#!/usr/bin/env bash
# Installs what is needed, builds, and runs the main job: `slamprep bench` on the default suite
# (report in results/default/README.md, plots in results/default/plots/).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh slamprep  # the binary and its libraries; no tests, no benchmarks
./build/slamprep bench "$@"
