#!/bin/bash
# The exit-code table of the README, command by command: 0 done, 2 bad input or usage (CLI11's
# parse errors included), 3 the requested work could not be done, 1 internal error.
source "$(dirname "$0")/cli_lib.sh"
internal() { SLAMPREP_TEST_INTERNAL_ERROR=1 expect 1 "$@"; err_has "internal error"; }

# The top level.
expect 2
err_has "commands:"
expect 2 calib
expect 0 --version
expect 0 --help
expect 2 --no-such-flag

# simulate: 0, 2 (a CLI11 check, a missing option, an unknown option, a bad --set), 1.
sim=$dir/sim
simulate_arc "$sim"
expect 2 simulate --mode kinematc --out "$dir/x"
expect 2 simulate --quiet
err_has "--out is required"
expect 2 simulate --durat 3 --out "$dir/x"
expect 2 simulate --set lidar.rat_hz=5 --out "$dir/x"
internal simulate --out "$dir/x"
[ ! -e "$dir/x" ] || fail "a refused simulate wrote $dir/x"

# export: 0, 2, 1.
expect 0 export "$sim" --format carmen --out "$dir/sim.carmen"
expect 2 export "$sim" --format carmn --out "$dir/y.carmen"
expect 2 export "$sim" --format carmen
expect 2 export "$dir/nowhere" --format carmen --out "$dir/y.carmen"
internal export "$sim" --format carmen --out "$dir/y.carmen"

# import: 0 (a log without ground truth, like a real one), 2, 1.
real=$dir/real
expect 0 import --format carmen "$dir/sim.carmen" --out "$real"
expect 2 import --format mcp "$dir/sim.carmen" --out "$dir/z"
expect 2 import --format carmen "$dir/nowhere.log" --out "$dir/z"
expect 2 import --format carmen "$dir/sim.carmen" --out "$dir/z" --lidar-mount 1,2
internal import --format carmen "$dir/sim.carmen" --out "$dir/z"

# deskew: 0, 3 (the only method asked for does not apply), 2, 1.
expect 0 deskew "$sim" --method odom-linear
expect 0 deskew "$real" --method all
out_has "not applicable: no ground truth"
expect 3 deskew "$real" --method oracle
expect 2 deskew "$sim" --method linear
expect 2 deskew "$sim" --metod all
expect 2 deskew "$real" --geometry true
internal deskew "$sim"

# match: 0, 3 (no pair converges when every beam misses), 2, 1.
expect 0 match "$sim"
"$slamprep" simulate --scenario worlds/scenarios/arc.yaml --duration 1 --mode kinematic --quiet \
  --set lidar.range_max_m=0.1 --out "$dir/blind" >/dev/null || fail "simulate blind"
expect 3 match "$dir/blind"
expect 2 match "$dir/nowhere"
expect 2 match "$sim" --deskew vic
internal match "$sim"

# calibrate: 0 on the figure eight with every interval method ok (umbmark does not apply: not
# asked), 3 when the one method asked for refuses or with --strict, 2, 1.
fig8=$dir/fig8
"$slamprep" simulate --scenario worlds/scenarios/figure_eight.yaml --mode kinematic --quiet \
  --out "$fig8" >/dev/null || fail "simulate figure eight"
expect 0 calibrate "$fig8" --motion groundtruth
out_has "umbmark: not applicable"
expect 3 calibrate "$fig8" --motion groundtruth --method umbmark
expect 3 calibrate "$sim" --motion groundtruth --method joint
expect 3 calibrate "$sim" --motion groundtruth --strict
expect 2 calibrate "$fig8" --method cerse
expect 2 calibrate "$fig8" --methd joint
expect 2 calibrate "$fig8" --deskew foo
expect 2 calibrate "$fig8" --sideslip --time-offset
err_has "excludes"
expect 2 calibrate "$fig8" --loop-closure --motion groundtruth
err_has "--loop-closure: closes the loops of scan-matched motion"
expect 2 calibrate "$dir/nowhere"
internal calibrate "$fig8"

# calibrate: 3 where the wheels turn and the gyro does not (a lifted robot: the gyro zeroed from
# 20 to 24 s), naming the span and its cause; 0 with --exclude-disagreement.
lifted=$dir/lifted
cp -r "$fig8" "$lifted"
awk -F, 'NR > 1 && $1 >= 20 && $1 < 24 { $2 = 0 } { print }' OFS=, "$fig8/imu.csv" >"$lifted/imu.csv"
expect 3 calibrate "$lifted" --motion groundtruth --method joint
out_has "lifted or blocked"
expect 0 calibrate "$lifted" --motion groundtruth --method joint --exclude-disagreement
err_has "left out (--exclude-disagreement)"

# calibrate several recordings of one robot: 0 with the combined JSON object (one DATASET keeps
# the list), 2 for the options of one recording and for nominal geometries that differ, 3 for a
# flagged estimate (more than 15 % from the nominal) only with --strict.
fig8b=$dir/fig8b
"$slamprep" simulate --scenario worlds/scenarios/figure_eight.yaml --mode kinematic --seed 2 \
  --quiet --out "$fig8b" >/dev/null || fail "simulate figure eight 2"
expect 0 calibrate "$fig8" "$fig8b" --motion groundtruth --method joint --validate-fraction 0.3 \
  --leave-one-out --json "$dir/multi.json" --ros2-params "$dir/multi.yaml"
out_has "combined over 2 recordings"
out_has "held-out validation"
grep -q '"consistency"' "$dir/multi.json" || fail "several DATASETs: no consistency in --json"
grep -q '"validation"' "$dir/multi.json" || fail "--validate-fraction: no validation in --json"
out_has "leave one recording out"
grep -q '"leave_one_out"' "$dir/multi.json" || fail "--leave-one-out: nothing in --json"
[ -s "$dir/multi.yaml" ] || fail "several DATASETs: --ros2-params not written"
grep -q '"r_R/b"' "$dir/multi.json" || fail "several DATASETs: no r/b consistency in --json"
# A wheel base 4 % longer on a second robot, the same nominal: its rotation per wheel turn
# differs, and the output says so.
wide=$dir/wide
"$slamprep" simulate --scenario worlds/scenarios/figure_eight.yaml --mode kinematic --seed 2 \
  --set robot.wheel_base_m=0.52 --quiet --out "$wide" >/dev/null || fail "simulate wide"
expect 0 calibrate "$fig8" "$wide" --motion groundtruth --method joint --nominal 0.1,0.1,0.5 \
  --json "$dir/wide.json"
out_has "disagree on how far the robot turns per wheel turn"
# A combined r or b outside the two recordings' values is said, and only then (weighted with
# their correlations, two discrepant estimates can combine outside their range).
outside=$(python3 -c '
import json, sys
d = json.load(open(sys.argv[1]))
c, runs = d["combined"][0], [r["methods"][0] for r in d["recordings"]]
print(any(not min(r[k] for r in runs) <= c[k] <= max(r[k] for r in runs) for k in ("r_L", "r_R", "b")))
' "$dir/wide.json")
if [ "$outside" = True ]; then
  out_has "outside the recordings' range"
else
  ! grep -qF "outside the recordings' range" "$dir/out" || fail "an in-range combination called outside"
fi
expect 0 export "$fig8" --format tum --out "$dir/multi_tum" --calibration "$dir/multi.json"
[ -s "$dir/multi_tum/odom_calibrated.tum" ] || fail "export read no combined calibration"
expect 0 calibrate "$fig8" --motion groundtruth --method joint --json "$dir/one.json"
[ "$(head -c1 "$dir/one.json")" = "[" ] || fail "one DATASET: --json is no longer a list"
for option in "--odometry-out $dir/o.tum" "--intervals $dir/i.jsonl" "--square $fig8"; do
  # shellcheck disable=SC2086
  expect 2 calibrate "$fig8" "$fig8b" $option
  err_has "${option%% *}: describes one recording"
done
"$slamprep" simulate --scenario worlds/scenarios/arc.yaml --duration 1 --mode kinematic --quiet \
  --set nominal.wheel_base_error=0.1 --out "$dir/other" >/dev/null || fail "simulate other"
expect 2 calibrate "$fig8" "$dir/other" --motion groundtruth
err_has "nominal geometries differ"
expect 2 calibrate "$fig8" --validate-fraction 1.5
err_has "--validate-fraction"
expect 2 calibrate "$fig8" --leave-one-out
err_has "--leave-one-out: needs two or more DATASETs"
expect 0 calibrate "$fig8" --motion groundtruth --method joint --nominal 0.1,0.1,0.7
out_has "FLAG joint: b = 0.7"
expect 3 calibrate "$fig8" --motion groundtruth --method joint --nominal 0.1,0.1,0.7 --strict

# bench, merge, plot on a two-trial suite: 0, 3 (a shard missing, a regression), 2, 1.
cat >"$dir/tiny.yaml" <<YAML
name: tiny
description: Two short kinematic arcs.
worlds: [worlds/room.yaml]
scenarios: [worlds/scenarios/arc.yaml]
mode: kinematic
duration_s: 1
seeds: 2
calibration_methods: []
deskew_methods: [none, odom-linear]
tolerances:
  deskew/odom-linear/mean_m: {abs: 0.001}
YAML
echo '{}' >"$dir/empty-baseline.json"
expect 0 bench --suite "$dir/tiny.yaml" --results "$dir/half" --quiet --no-plots --shard 1/2
expect 3 merge "$dir/half/tiny" --no-plots
expect 0 bench --suite "$dir/tiny.yaml" --results "$dir/res" --quiet --no-plots
expect 3 bench --suite "$dir/tiny.yaml" --results "$dir/res" --quiet --no-plots \
  --compare "$dir/empty-baseline.json"
expect 2 bench --suite no-such-suite --results "$dir/res"
expect 2 bench --suite "$dir/tiny.yaml" --results "$dir/res" --compare "$dir/nowhere.json"
err_has "--compare $dir/nowhere.json"
expect 2 bench --suite "$dir/tiny.yaml" --slurm --compare "$dir/empty-baseline.json"
err_has "cannot be combined with --shard, --fresh, --compare"
expect 2 bench --suite "$dir/tiny.yaml" --jobs many
internal bench --suite "$dir/tiny.yaml" --results "$dir/res"
expect 0 bench --suite "$dir/tiny.yaml" --results "$dir/half" --quiet --no-plots --shard 2/2
expect 0 merge "$dir/half/tiny" --no-plots
expect 2 merge "$dir/nowhere"
expect 2 merge
internal merge "$dir/half/tiny"
expect 0 plot "$dir/res/tiny"
expect 2 plot "$dir/nowhere"
expect 2 plot "$dir/res/tiny" --bogus
internal plot "$dir/res/tiny"
echo "exit codes ok"
