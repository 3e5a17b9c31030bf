#!/bin/bash
# `slamprep twin` end to end on a committed real excerpt (the first 120 s of the ACES CARMEN
# log, tests/data/carmen_aces): import, twin, compare; and its refusals.
source "$(dirname "$0")/cli_lib.sh"

expect 0 import --format carmen tests/data/carmen_aces/aces_first120s.clf --out "$dir/aces" \
  --odometry laser
expect 0 twin "$dir/aces" --out "$dir/twin" --no-calibrate -q
for f in world.yaml scenario.yaml twin.json dataset/dataset.json dataset/groundtruth.tum; do
  [ -f "$dir/twin/$f" ] || fail "twin did not write $f"
done
out_has "world: "
grep -qF '"sets"' "$dir/twin/twin.json" || fail "twin.json lacks the --set list"
grep -qF "type: track" "$dir/twin/scenario.yaml" || fail "the scenario is not a track"
# The --set list reproduces the dataset: the same world, scenario and sets give the same scans.
sets=$(python3 -c "import json,sys; print(' '.join('--set ' + s for s in json.load(open(sys.argv[1]))['sets']))" "$dir/twin/twin.json")
# shellcheck disable=SC2086
expect 0 simulate --world "$dir/twin/world.yaml" --scenario "$dir/twin/scenario.yaml" $sets \
  --out "$dir/again" -q
cmp -s "$dir/twin/dataset/scans.jsonl" "$dir/again/scans.jsonl" || fail "the --set list does not reproduce the twin"

before=$(fingerprint "$dir/twin")
expect 2 twin "$dir/aces" --out "$dir/twin" --no-calibrate -q  # exists, no --force
[ "$(fingerprint "$dir/twin")" = "$before" ] || fail "a refused twin changed its output"
mkdir "$dir/mine" && echo keep >"$dir/mine/notes.txt"
expect 2 twin "$dir/aces" --out "$dir/mine" --force -q  # not a twin folder: never replaced
expect 2 twin --out "$dir/x"
expect 2 twin "$dir/aces"
expect 2 twin --compare "$dir/aces"

expect 0 twin --compare "$dir/aces" "$dir/twin" --json "$dir/cmp.json" --plot "$dir/cmp.png" -q
for key in scan_rate_hz beams_per_scan_mean no_return_fraction scan_to_map_residual_median_m \
  scan_to_map_residual_p95_m scan_residual_neighbour_correlation \
  scan_residual_revisit_correlation match_converged_percent odometry_drift_per_m \
  odometry_step_noise_deg wheels_vs_scans_residual_deg calibration_sigma_b calibration_b_m; do
  grep -qF "\"$key\"" "$dir/cmp.json" || fail "comparison lacks $key"
done
[ -s "$dir/cmp.png" ] || fail "no plot"
# The layout is copied, so its statistics agree; the twin's scans match as the recording's do.
python3 - "$dir/cmp.json" <<'PY' || fail "the twin's statistics are off: $(cat "$dir/cmp.json")"
import json, sys
s = json.load(open(sys.argv[1]))["statistics"]
assert abs(s["scan_rate_hz"]["ratio"] - 1) < 0.05, s["scan_rate_hz"]
assert abs(s["beams_per_scan_mean"]["ratio"] - 1) < 0.01, s["beams_per_scan_mean"]
assert s["match_converged_percent"]["twin"] > 80, s["match_converged_percent"]
assert 0.5 < s["scan_to_map_residual_median_m"]["ratio"] < 2, s["scan_to_map_residual_median_m"]
# Both have wheels and scans to compare (the log's odometry poses, the twin's encoders).
assert s["wheels_vs_scans_residual_deg"]["real"] > 0, s["wheels_vs_scans_residual_deg"]
assert s["wheels_vs_scans_residual_deg"]["twin"] > 0, s["wheels_vs_scans_residual_deg"]
# Both measure the odometry's noise per scan step (a heading noise, in degrees).
assert 0 < s["odometry_step_noise_deg"]["real"] < 10, s["odometry_step_noise_deg"]
assert 0 < s["odometry_step_noise_deg"]["twin"] < 10, s["odometry_step_noise_deg"]
PY
echo "twin: ok"
