#!/bin/bash
# `slamprep plot RESULTS_DIR`: re-renders a finished results folder's plots and README, keeps
# the PNGs it cannot redraw (no trials/), and refuses a folder that is not one (exit 2, naming
# the missing file).
set -euo pipefail
slamprep=${1:?usage: plot_cli_test.sh SLAMPREP_BINARY SOURCE_DIR}
source_dir=${2:?usage: plot_cli_test.sh SLAMPREP_BINARY SOURCE_DIR}
dir=$(mktemp -d /tmp/slamprep-plot.XXXXXX)
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

cat >"$dir/plot-tiny.yaml" <<YAML
name: plot-tiny
description: One short kinematic arc.
worlds: [worlds/room.yaml]
scenarios: [worlds/scenarios/arc.yaml]
mode: kinematic
duration_s: 1
calibration_methods: []
deskew_methods: [none, oracle, odom-linear]
YAML
cd "$source_dir"
"$slamprep" bench --suite "$dir/plot-tiny.yaml" --results "$dir" --quiet --no-plots >/dev/null \
  || fail "bench"
results=$dir/plot-tiny
[ ! -e "$results/plots" ] || fail "--no-plots rendered plots"
grep -q "## Plots" "$results/README.md" && fail "README embeds plots before any were rendered"
cp "$results/summary.json" "$dir/summary.before"

"$slamprep" plot "$results" >"$dir/out.txt" || fail "plot exited $?"
for png in deskew_by_method.png trajectory.png scan.png; do
  [ "$(head -c 8 "$results/plots/$png" | od -An -tx1 | tr -d ' ')" = 89504e470d0a1a0a ] \
    || fail "$png is not a PNG"
  grep -q "](plots/$png)" "$results/README.md" || fail "README does not embed $png"
  grep -q "plot: $results/plots/$png" "$dir/out.txt" || fail "plot did not print $png"
done
cmp -s "$results/summary.json" "$dir/summary.before" || fail "plot changed summary.json"

# A committed folder has no trials/ (git ignores it): plot cannot redraw the first trial's
# figures, so it keeps their PNGs byte for byte and their README lines, and says so on stderr.
kept=$dir/kept
cp -r "$results" "$kept"
rm -r "$kept/trials"
"$slamprep" plot "$kept" >"$dir/kept.out" 2>"$dir/kept.err" || fail "plot without trials/ exited $?"
cmp -s "$results/README.md" "$kept/README.md" \
  || fail "README changed without trials/: $(diff "$results/README.md" "$kept/README.md")"
for png in trajectory.png odometry_error.png scan.png; do
  cmp -s "$results/plots/$png" "$kept/plots/$png" || fail "$png changed without trials/"
  grep -qx "plot: trials/ missing: kept plots/$png as it was" "$dir/kept.err" \
    || fail "no note that $png was kept: $(cat "$dir/kept.err")"
  grep -q "plots/$png" "$dir/kept.out" && fail "stdout lists the kept $png as rendered"
done
cmp -s "$results/plots/deskew_by_method.png" "$kept/plots/deskew_by_method.png" \
  || fail "deskew_by_method.png rendered differently without trials/"
# Neither trials/ nor the PNG: nothing to keep, the README leaves it out.
rm "$kept/plots/scan.png"
"$slamprep" plot "$kept" >/dev/null 2>&1 || fail "plot without trials/ and scan.png exited $?"
[ ! -e "$kept/plots/scan.png" ] || fail "plot made a scan.png without trials/"
grep -q "](plots/scan.png)" "$kept/README.md" && fail "README embeds a scan.png that is gone"
grep -q "](plots/trajectory.png)" "$kept/README.md" || fail "README lost the kept trajectory.png"

# Box plots (10+ seeds) read trials.csv: bench and plot must still write the same bytes.
cat >"$dir/plot-seeds.yaml" <<YAML
name: plot-seeds
description: Ten seeds of a short calibration drive, enough for box plots.
worlds: [worlds/room.yaml]
scenarios: [worlds/scenarios/default.yaml]
seeds: 10
mode: kinematic
duration_s: 20
calibration_methods: [model, joint]
deskew_methods: []
YAML
"$slamprep" bench --suite "$dir/plot-seeds.yaml" --results "$dir" --quiet >/dev/null \
  || fail "bench of 10 seeds"
seeds=$dir/plot-seeds/plots
cp "$seeds/calibration_error.png" "$dir/boxes.bench.png"
"$slamprep" plot "$dir/plot-seeds" >/dev/null || fail "plot of 10 seeds exited $?"
cmp -s "$seeds/calibration_error.png" "$dir/boxes.bench.png" \
  || fail "plot re-rendered the box plots of bench differently"

# Not a results folder: exit 2, the missing file named, nothing written.
mkdir "$dir/empty"
set +e
"$slamprep" plot "$dir/empty" 2>"$dir/err.txt"
code=$?
set -e
[ "$code" = 2 ] || fail "expected exit 2 on an empty folder, got $code"
grep -q "suite.yaml" "$dir/err.txt" || fail "error does not name suite.yaml: $(cat "$dir/err.txt")"
[ -z "$(ls -A "$dir/empty")" ] || fail "plot wrote into a folder it refused"
echo "plot CLI ok"
