#!/bin/bash
# What slamprep says when it is used wrongly: an unknown choice lists the valid ones and the
# closest; an unknown command or none lists the commands; --version; every --help clean.
source "$(dirname "$0")/cli_lib.sh"
commands="bench calibrate deskew export import match merge plot score simulate twin"
ds=$dir/ds
simulate_arc "$ds"

# Unknown choices, with the closest valid name.
expect 2 calibrate "$ds" --method cerse
err_has "unknown method 'cerse' (valid: direct, model, joint, ceres, umbmark, all); did you mean 'ceres'?"
expect 2 calibrate "$ds" --deskew foo
err_has "unknown de-skew method 'foo' (valid: auto, none, oracle, const-velocity, vicp, odom-linear, odom-quadratic, imu, odom-icp)"
expect 2 deskew "$ds" --method odom-lin
err_has "did you mean 'odom-linear'?"
expect 2 export "$ds" --format kiti --out "$dir/k"
err_has "did you mean 'kitti'?"
expect 2 import --format carmn x --out "$dir/i"
err_has "did you mean 'carmen'?"
expect 2 simulate --mode physic --out "$dir/s"
err_has "did you mean 'physics'?"

# Numbers out of their range say the rule and the value.
expect 2 match "$ds" --keyframe-distance 0
err_has "--keyframe-distance: must be > 0 (got 0)"
expect 2 calibrate "$ds" --trim-sigmas -1
err_has "--trim-sigmas: must be >= 0 (got -1)"
expect 2 calibrate "$ds" --mount-prior 0,2
err_has "--mount-prior: the 1-sigmas must be > 0 (none: no prior)"
expect 2 calibrate "$ds" --mount-prior 2
err_has "--mount-prior: expected sigma_cm,sigma_deg"
: >"$dir/none.clf"
expect 2 import --format carmen "$dir/none.clf" --out "$dir/i" --time-increment -1
err_has "--time-increment: must be >= 0 (got -1)"
expect 2 import --format carmen "$dir/none.clf" --out "$dir/i" --time-increment fast
err_has "--time-increment: expected seconds or auto (got fast)"
expect 2 import --format carmen "$dir/none.clf" --out "$dir/i" --time-increment auto
err_has "--time-increment: auto is for bags"
expect 2 deskew "$ds" --stamps grid
err_has "unknown stamps 'grid' (valid: auto, raw)"

# Unknown options: CLI11's message, then the closest option.
# (calibrate takes several DATASETs, so "joint" is read as one and only --methd is unexpected.)
expect 2 calibrate "$ds" --methd joint
err_has "The following argument was not expected: --methd"
err_has "unknown option '--methd'; did you mean '--method'?"
expect 2 deskew "$ds" --stamp-is-last
err_has "did you mean '--stamp-is-last-beam'?"

# No command, an unknown one: every command on a line of its own, and the closest.
expect 2
for c in $commands; do grep -qE "^  $c +[A-Z]" "$dir/err" || fail "bare slamprep does not list $c"; done
expect 2 calib
err_has "unknown command 'calib'"
err_has "did you mean 'calibrate'?"
for c in $commands; do grep -qE "^  $c +[A-Z]" "$dir/err" || fail "unknown command does not list $c"; done
expect 2 dskew "$ds"
err_has "did you mean 'deskew'?"

# --version: the project version and the git revision it was configured from.
version=$(sed -n 's/^project(slamprep VERSION \([0-9.]*\).*/\1/p' CMakeLists.txt)
expect 0 --version
grep -qE "^slamprep $version \(git ([0-9a-f]{12}|unknown)\)$" "$dir/out" ||
  fail "--version printed '$(cat "$dir/out")', expected 'slamprep $version (git REVISION)'"

# Clean --help: no CLI11 flag defaults such as {false}; units said where they are not SI radians.
for c in $commands; do
  expect 0 "$c" --help
  ! grep -qE '\{(true|false)\}' "$dir/out" || fail "$c --help shows a flag default: $(grep -E '\{(true|false)\}' "$dir/out")"
done
expect 0 import --help
grep -q -- "--lidar-mount TEXT *x,y,yaw_deg of the lidar on the base: metres, metres, degrees" "$dir/out" ||
  fail "import --help does not give --lidar-mount's units"

# One name per concept: the deprecated deskew --geometry FILE still works, with a note.
echo '[{"method": "model", "ok": true, "r_L": 0.101, "r_R": 0.099, "b": 0.51}]' >"$dir/cal.json"
expect 0 deskew "$ds" --method odom-linear --calibration "$dir/cal.json"
out_has "geometry $dir/cal.json (method model)"
expect 0 deskew "$ds" --method odom-linear --geometry "$dir/cal.json"
err_has "--geometry FILE is deprecated; use --calibration FILE"
out_has "geometry $dir/cal.json (method model)"
expect 2 deskew "$ds" --geometry true --calibration "$dir/cal.json"
expect 3 calibrate "$ds" --motion groundtruth --method model --stamp-is-last-beam
out_has "model: REFUSED"

# The estimate against the nominal: the simulator's nominal is wrong (r_L +2 %, r_R -1.5 %,
# b +4 %), so the true motion shows it, each parameter on its side of the nominal.
"$slamprep" simulate --scenario worlds/scenarios/default.yaml --duration 30 --mode kinematic \
  --quiet --out "$dir/drive" >/dev/null || fail "simulate $dir/drive"
expect 0 calibrate "$dir/drive" --motion groundtruth --method model
out_has "against the nominal model: r_L -"
out_has ", r_R +"
out_has "the recording shows the nominal geometry wrong"

# Every path is checked before any work: a missing square run, a missing calibration file.
expect 2 calibrate "$ds" --square "$dir/nowhere"
err_has "--square $dir/nowhere"
expect 2 deskew "$ds" --calibration "$dir/nowhere.json"
err_has "--calibration $dir/nowhere.json: cannot open file"
echo "messages ok"
