# Shared by the CLI contract tests (sourced): the binary, a scratch folder, `expect CODE ARGS...`.
# Usage of every test: bash <test>.sh SLAMPREP_BINARY SOURCE_DIR
set -euo pipefail
slamprep=${1:?usage: $0 SLAMPREP_BINARY SOURCE_DIR}
source_dir=${2:?usage: $0 SLAMPREP_BINARY SOURCE_DIR}
dir=$(mktemp -d /tmp/slamprep-cli.XXXXXX)
trap 'rm -rf "$dir"' EXIT
cd "$source_dir"  # scenario paths below are relative to the source tree
fail() { echo "FAIL: $*"; exit 1; }

# expect CODE ARGS...: runs `slamprep ARGS` (stdout in $dir/out, stderr in $dir/err) and fails
# the test unless it exits with CODE.
expect() {
  local want=$1 got
  shift
  set +e
  "$slamprep" "$@" >"$dir/out" 2>"$dir/err"
  got=$?
  set -e
  [ "$got" = "$want" ] || fail "slamprep $* exited $got, expected $want; stderr: $(cat "$dir/err")"
}
err_has() { grep -qF -- "$1" "$dir/err" || fail "stderr lacks '$1': $(cat "$dir/err")"; }
out_has() { grep -qF -- "$1" "$dir/out" || fail "stdout lacks '$1': $(cat "$dir/out")"; }
out_lacks() { ! grep -qF -- "$1" "$dir/out" || fail "stdout has '$1': $(cat "$dir/out")"; }

# The bytes of a file or folder: one checksum line per file, names included.
fingerprint() { (cd "$1" 2>/dev/null && find . -type f | sort | xargs sha256sum) || sha256sum "$1"; }

# A 3 s kinematic arc: small, exact, with ground truth, IMU and encoders.
simulate_arc() {
  "$slamprep" simulate --scenario worlds/scenarios/arc.yaml --duration 3 --mode kinematic --quiet \
    --out "$1" >/dev/null || fail "simulate $1"
}
