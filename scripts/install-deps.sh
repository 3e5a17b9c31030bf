#!/usr/bin/env bash
# Installs every Debian 12 package slamprep needs to build, test and plot.
# Idempotent: packages already present are skipped by apt-get.
set -euo pipefail

# Optional parts (node for the MCAP reader tests, Slurm) may fail to install on a developer's
# machine, and their tests then skip. Under CI=true every step must succeed.
optional_failed() {
  echo "install-deps: $1"
  if [ "${CI:-}" = true ]; then
    echo "install-deps: CI=true, so this is an error (no test may skip in CI)" >&2
    exit 1
  fi
}

packages=(
  build-essential cmake ninja-build pkg-config git clang-format
  clang  # the sanitizer subset in scripts/test.sh (builds ~2.4x faster than GCC) and libFuzzer
  libbullet-dev libeigen3-dev libceres-dev libosmesa6-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libyaml-cpp-dev nlohmann-json3-dev libcli11-dev libnanoflann-dev
  libfreetype-dev fonts-dejavu-core libpng-dev
  libzstd-dev liblz4-dev  # MCAP chunk compression (eval/formats/compression.cpp)
  libsqlite3-dev  # rosbag2's sqlite3 storage, .db3 (eval/formats/sqlite_storage.cpp)
  zlib1g-dev  # MCAP's CRC-32 (eval/formats/crc32.cpp)
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if ((${#missing[@]})); then
  echo "install-deps: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "install-deps: all packages present"
fi

# Node packages for the MCAP export tests (tests/formats/mcap_reader): the independent @mcap/core
# reader and ROS 2 CDR deserialiser, pinned by package-lock.json. Without node or npm those tests
# skip (GTEST_SKIP with the reason; under CI=true they fail); nothing else needs them.
if ! command -v npm >/dev/null 2>&1; then
  export DEBIAN_FRONTEND=noninteractive
  { apt-get update -qq && apt-get install -y -qq --no-install-recommends nodejs npm; } ||
    optional_failed "could not install nodejs/npm; the MCAP reader tests will skip"
fi
mcap_reader="$(dirname "$0")/../tests/formats/mcap_reader"
# Re-run npm ci whenever the lock file is newer than what was installed (a package was added).
if command -v npm >/dev/null 2>&1 &&
  { [ ! -f "$mcap_reader/node_modules/.package-lock.json" ] ||
    [ "$mcap_reader/package-lock.json" -nt "$mcap_reader/node_modules/.package-lock.json" ]; }; then
  (cd "$mcap_reader" && npm ci --no-audit --no-fund --loglevel=error) ||
    optional_failed "npm ci failed; the MCAP reader tests will skip"
fi

# Slurm and munge for the real single-node Slurm test (tests/slurm, ctest label `slurm`): it
# starts its own munged and slurmctld/slurmd in a temporary folder, never the system services.
# Without these packages (or without root) that test skips.
slurm_packages=(slurmctld slurmd slurm-client munge)
slurm_missing=()
for p in "${slurm_packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || slurm_missing+=("$p")
done
if ((${#slurm_missing[@]})); then
  export DEBIAN_FRONTEND=noninteractive
  { apt-get update -qq && apt-get install -y -qq --no-install-recommends "${slurm_missing[@]}"; } ||
    optional_failed "could not install ${slurm_missing[*]}; the Slurm test will skip"
fi
