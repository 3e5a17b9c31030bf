#!/usr/bin/env bash
# Installs what is needed, builds, and runs every test. This is the README's test command and
# exactly what .ci/run runs.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
ctest --test-dir build --output-on-failure --parallel "$(nproc)" --timeout 600
