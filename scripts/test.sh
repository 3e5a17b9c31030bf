#!/usr/bin/env bash
# Installs what is needed, builds, and runs every test, then the reader-facing tests again under
# AddressSanitizer + UndefinedBehaviorSanitizer (scripts/sanitize.sh --ci; the whole suite under
# the sanitizers is `bash scripts/sanitize.sh`). This is the README's test command and exactly
# what .ci/run runs.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
ctest --test-dir build --output-on-failure --parallel "$(nproc)" --timeout 600
bash scripts/sanitize.sh --ci
