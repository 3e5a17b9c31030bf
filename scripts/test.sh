#!/usr/bin/env bash
# Installs what is needed, builds, and runs every test: the tests of slamprep::formats (its
# readers, exports and imports, the corpus replay of its readers) under AddressSanitizer +
# UndefinedBehaviorSanitizer (scripts/sanitize.sh --ci), every other test in the Release build.
# The whole suite under the sanitizers is `bash scripts/sanitize.sh`. This is the README's test
# command and exactly what .ci/run runs; it must stay under 10 minutes on 2 cores
# (docs/notebook.md, "Test command").
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh -DSLAMPREP_FORMATS_TESTS=OFF
log=$(mktemp /tmp/slamprep-ctest.XXXXXX)
# One test more than cores: the script tests wait on the processes they start.
ctest --test-dir build --output-on-failure --parallel "$(($(nproc) + 1))" --timeout 600 | tee "$log"
# ctest counts a skipped test as passed; in CI a skip means something was not tested.
if [ "${CI:-}" = true ] && grep -E '\*\*\*(Skipped|Not Run)' "$log"; then
  echo "test.sh: CI=true and the tests above were skipped or not run" >&2
  exit 1
fi
rm -f "$log"
bash scripts/sanitize.sh --ci
