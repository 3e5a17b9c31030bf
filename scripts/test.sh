#!/usr/bin/env bash
# Installs what is needed, builds, and runs every test, then the reader-facing tests again under
# AddressSanitizer + UndefinedBehaviorSanitizer (scripts/sanitize.sh --ci; the whole suite under
# the sanitizers is `bash scripts/sanitize.sh`). This is the README's test command and exactly
# what .ci/run runs.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
log=$(mktemp /tmp/slamprep-ctest.XXXXXX)
ctest --test-dir build --output-on-failure --parallel "$(nproc)" --timeout 600 | tee "$log"
# ctest counts a skipped test as passed; in CI a skip means something was not tested.
if [ "${CI:-}" = true ] && grep -E '\*\*\*(Skipped|Not Run)' "$log"; then
  echo "test.sh: CI=true and the tests above were skipped or not run" >&2
  exit 1
fi
rm -f "$log"
bash scripts/sanitize.sh --ci
