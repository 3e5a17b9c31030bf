#!/bin/bash
# Input limits (docs/design.md "Input limits"), through the binary: inputs that crashed, hung,
# ate gigabytes or ran a command are refused up front, exit 2, naming the file and key or the
# option; --compare is read before any trial runs; an edited suite recomputes instead of mixing.
source "$(dirname "$0")/cli_lib.sh"

# --- finding 8: a dataset.json whose config is nested 200 000 deep (SIGSEGV in every reader).
simulate_arc "$dir/sim"
cp -r "$dir/sim" "$dir/deep"
python3 - "$dir/deep/dataset.json" <<'PY'
import sys
path = sys.argv[1]
text = open(path).read()
open(path, "w").write(text.replace('"config": {', '"config": {"deep": ' + "[" * 200000 + "]" * 200000 + ",", 1))
PY
for cmd in "calibrate $dir/deep" "deskew $dir/deep --method odom-linear --out $dir/deep-out" \
  "export $dir/deep --format tum --out $dir/deep-tum" "simulate --config $dir/deep/dataset.json --out $dir/x"; do
  # shellcheck disable=SC2086
  expect 2 $cmd
  err_has "$dir/deep/dataset.json:"
  err_has "JSON nested deeper than 64 levels"
done
[ ! -e "$dir/deep-out" ] || fail "deskew wrote the deep config back"

# --- finding 9 and the low items: files that never end, work that never ends.
expect 2 simulate --world /dev/zero --out "$dir/x"
err_has "/dev/zero: cannot read world file: a character device, not a regular file"
printf 'segments:\n  - {type: include, file: /dev/zero}\n' >"$dir/zero.yaml"
expect 2 simulate --scenario "$dir/zero.yaml" --out "$dir/x"
err_has "include: /dev/zero: cannot read scenario file"
expect 2 calibrate --tuples /dev/zero
err_has "/dev/zero: cannot read record file"
expect 2 simulate --set lidar.rate_hz=1e9 --out "$dir/x"
err_has "lidar.rate_hz: must be at most 100"
{ cat worlds/room.yaml; printf 'walls:\n  - {from: [1, 1], to: [2, 2]}\n'; } >"$dir/twice.yaml"
expect 2 simulate --world "$dir/twice.yaml" --mode kinematic --out "$dir/x"
err_has "twice.yaml:"
err_has "walls: key appears twice in one mapping (first on line"
python3 -c "
print('walls:')
for i in range(10001): print('  - {from: [0, %d], to: [1, %d]}' % (i, i))" >"$dir/walls.yaml"
expect 2 simulate --world "$dir/walls.yaml" --out "$dir/x"
err_has "walls.yaml:2:3: walls: the world has more than 10000 objects"
expect 2 simulate --seed -1 --out "$dir/x"
err_has "--seed: must be >= 0"
[ ! -e "$dir/x" ] || fail "a refused simulate wrote --out"

# A file size limit (ulimit -f) used to kill with SIGXFSZ and no word: now the write fails,
# named, and the partial output is removed.
set +e
(ulimit -f 64 && "$slamprep" simulate --scenario worlds/scenarios/arc.yaml --duration 3 \
  --mode kinematic --quiet --out "$dir/capped" >"$dir/out" 2>"$dir/err")
code=$?
set -e
[ "$code" = 2 ] || fail "simulate past ulimit -f exited $code, expected 2: $(cat "$dir/err")"
err_has "File too large"
[ -z "$(find "$dir" -maxdepth 1 -name 'capped*')" ] || fail "a partial output was left behind"

# --- bench: sweeps, jobs, Slurm names, --compare, reuse.
values=$(python3 -c "print(', '.join(str(i * 1e-4) for i in range(1000)))")
cat >"$dir/huge.yaml" <<YAML
worlds: [worlds/room.yaml]
scenarios: [worlds/scenarios/arc.yaml]
sweep:
  lidar.range_noise_m: [$values]
  imu.gyro_noise_radps: [$values]
  imu.accel_noise_mps2: [$values]
YAML
expect 2 bench --suite "$dir/huge.yaml" --results "$dir/res"
err_has "huge.yaml: sweep: worlds x scenarios x sweep points x seeds is 1000000000 trials"
cat >"$dir/tiny.yaml" <<YAML
name: tiny
worlds: [worlds/room.yaml]
scenarios: [worlds/scenarios/arc.yaml]
mode: kinematic
duration_s: 1
seeds: 2
calibration_methods: []
deskew_methods: [none]
YAML
expect 2 bench --suite "$dir/tiny.yaml" --results "$dir/res" --jobs -5
err_has "--jobs: must be >= 0"
expect 2 bench --suite "$dir/tiny.yaml" --results "$dir/res" --jobs 100000
err_has "--jobs 100000: more than 4 worker processes per core"
printf '{"metrics": [1,,]' >"$dir/garbage.json"
expect 2 bench --suite "$dir/tiny.yaml" --results "$dir/res" --quiet --no-plots \
  --compare "$dir/garbage.json"
err_has "$dir/garbage.json:1: bad JSON"
[ ! -e "$dir/res/tiny" ] || fail "bench ran the suite before reading --compare"
printf '{"metrics": {"deskew/none/mean_m": {"mean": "low"}}}' >"$dir/garbage.json"
expect 2 bench --suite "$dir/tiny.yaml" --results "$dir/res" --quiet --no-plots \
  --compare "$dir/garbage.json"
err_has "garbage.json: metrics.deskew/none/mean_m.mean: missing or not a number"

printf 'name: "x'"'"'\\ntouch pwned\\n#"\nworlds: [worlds/room.yaml]\nscenarios: [worlds/scenarios/arc.yaml]\n' \
  >"$dir/evil.yaml"
(cd "$dir" && expect 2 bench --suite "$dir/evil.yaml" --results "$dir/slurm" --slurm --shards 2)
err_has "control character"
[ -z "$(find "$dir/slurm" -name '*.sh' 2>/dev/null)" ] || fail "a script was written for the name"
[ ! -e "$dir/pwned" ] || fail "the suite name ran a command"

expect 0 bench --suite "$dir/tiny.yaml" --results "$dir/res" --quiet --no-plots
expect 0 bench --suite "$dir/tiny.yaml" --results "$dir/res" --quiet --no-plots
err_has "2 trials (2 reused, 0 computed"
sed -i 's/deskew_methods: \[none\]/deskew_methods: [none, odom-linear]/' "$dir/tiny.yaml"
expect 0 bench --suite "$dir/tiny.yaml" --results "$dir/res" --quiet --no-plots
err_has "2 trials (0 reused, 2 computed"
grep -q "deskew/odom-linear/mean_m" "$dir/res/tiny/summary.json" || fail "the added method is not summarised"

# --- finding 10: malformed results name the file and field (exit 2, not 1).
cp -r "$dir/res/tiny" "$dir/bad"
python3 - "$dir/bad/summary.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
s["groups"][0]["world"] = 3
json.dump(s, open(sys.argv[1], "w"))
PY
expect 2 plot "$dir/bad"
err_has "$dir/bad/summary.json: groups[0].world: missing or not a string"
mkdir -p "$dir/bad/shards/1-of-1"
cp -r "$dir/res/tiny/trials" "$dir/bad/shards/1-of-1/"
first=$(find "$dir/bad/shards/1-of-1/trials" -name '*.json' | sort | head -1)
echo '{"trial": 5, "sim": {}}' >"$first"
expect 2 merge "$dir/bad" --no-plots
err_has "trial: missing or not an object"
echo "limits ok"
