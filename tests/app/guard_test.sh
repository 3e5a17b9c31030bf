#!/bin/bash
# The output guard (README, "Outputs"), one case per data loss a probe of 571 hostile inputs found: no command replaces,
# deletes or writes into an input, one output never lands on another, an output that appears
# during a run is not replaced without --force, --force replaces only what slamprep wrote, bench
# writes only into a results folder it created, and an interrupted run leaves no partial behind.
# Every refusal is exit 2 naming the option, before any work.
source "$(dirname "$0")/cli_lib.sh"

unchanged() {  # unchanged PATH BEFORE_FINGERPRINT_FILE WHAT
  fingerprint "$1" | cmp -s - "$2" || fail "$3 changed $1"
}
no_partials() {  # no_partials FOLDER
  ! ls -d "$1"/*.partial-* >/dev/null 2>&1 || fail "a partial was left: $(ls -d "$1"/*.partial-*)"
}

ds=$dir/ds
simulate_arc "$ds"
fingerprint "$ds" >"$dir/ds.before"
fig8=$dir/fig8
"$slamprep" simulate --scenario worlds/scenarios/figure_eight.yaml --mode kinematic --quiet \
  --duration 20 --out "$fig8" >/dev/null || fail "simulate figure eight"

# 4. import --force onto the folder that holds its own log.
mkdir "$dir/dsimp"
expect 0 export "$ds" --format carmen --out "$dir/dsimp/log.clf"
echo '{}' >"$dir/dsimp/dataset.json"
fingerprint "$dir/dsimp" >"$dir/dsimp.before"
expect 2 import --format carmen "$dir/dsimp/log.clf" --out "$dir/dsimp" --force
err_has "--out $dir/dsimp: contains the input PATH $dir/dsimp/log.clf"
unchanged "$dir/dsimp" "$dir/dsimp.before" "import --force onto its input's folder"
expect 2 import --format carmen "$dir/dsimp/log.clf" --out "$dir/dsimp/../dsimp/" --force
err_has "contains the input"

# 5. deskew --force onto a folder that contains the input dataset (also through a symlink).
mkdir "$dir/nest" && cp -r "$ds" "$dir/nest/child" && echo '{}' >"$dir/nest/dataset.json"
fingerprint "$dir/nest" >"$dir/nest.before"
expect 2 deskew "$dir/nest/child" --method none --out "$dir/nest" --force
err_has "--out $dir/nest: contains the input DATASET $dir/nest/child"
ln -s "$dir/nest" "$dir/nest-link"
expect 2 deskew "$dir/nest/child" --method none --out "$dir/nest-link" --force
err_has "contains the input DATASET"
expect 2 deskew "$dir/nest-link/child" --method none --out "$dir/nest/child/../child" --force
err_has "is the input DATASET"
unchanged "$dir/nest" "$dir/nest.before" "deskew --force onto its input"

# 6. --force onto an input file, and outputs inside an input folder.
expect 0 export "$ds" --format tum --out "$dir/tum"
cp "$dir/tum/groundtruth.tum" "$dir/gt.tum" && cp "$dir/tum/odom_nominal.tum" "$dir/est.tum"
fingerprint "$dir/est.tum" >"$dir/est.before"
expect 2 score ape "$dir/gt.tum" "$dir/est.tum" --json "$dir/est.tum" --force
err_has "--json $dir/est.tum: is the input ESTIMATE"
unchanged "$dir/est.tum" "$dir/est.before" "score --json --force onto its estimate"
expect 0 calibrate "$fig8" --motion groundtruth --method joint --json "$dir/cal.json" \
  --intervals "$dir/t.jsonl"
fingerprint "$dir/cal.json" >"$dir/cal.before"
fingerprint "$dir/t.jsonl" >"$dir/t.before"
expect 2 deskew "$ds" --method none --calibration "$dir/cal.json" --json "$dir/cal.json" --force
err_has "--json $dir/cal.json: is the input --calibration"
expect 2 export "$ds" --format carmen --calibration "$dir/cal.json" --out "$dir/cal.json" --force
err_has "--out $dir/cal.json: is the input --calibration"
unchanged "$dir/cal.json" "$dir/cal.before" "--force onto a --calibration input"
expect 2 calibrate "$fig8" --tuples "$dir/t.jsonl" --intervals "$dir/t.jsonl" --force \
  --method joint
err_has "--intervals $dir/t.jsonl: is the input --tuples"
unchanged "$dir/t.jsonl" "$dir/t.before" "calibrate --intervals onto its --tuples"
cp -r "$ds" "$dir/sq"
expect 2 calibrate "$fig8" --square "$dir/sq" --json "$dir/sq/cal.json"
err_has "--json $dir/sq/cal.json: is inside the input --square $dir/sq"
[ ! -e "$dir/sq/cal.json" ] || fail "calibrate wrote into its --square input"
expect 2 calibrate "$fig8" --json "$fig8/calibration.json"
err_has "is inside the input DATASET"
mkdir "$dir/bagdir"
expect 0 export "$ds" --format mcap --out "$dir/bagdir/b.mcap"
expect 2 import --format mcap "$dir/bagdir" --out "$dir/bagdir/imported"
err_has "--out $dir/bagdir/imported: is inside the input PATH $dir/bagdir"
expect 2 simulate --scenario worlds/scenarios/arc.yaml --config "$ds/dataset.json" --out "$ds" \
  --force
err_has "--out $ds: contains the input --config"
unchanged "$ds" "$dir/ds.before" "simulate --force onto the dataset its --config came from"

# Two outputs on one path, or one inside the other.
expect 2 calibrate "$fig8" --motion groundtruth --method joint --json "$dir/same.json" \
  --intervals "$dir/same.json"
err_has "--intervals $dir/same.json: is also --json $dir/same.json"
grep -q "intervals (" "$dir/err" && fail "calibrate worked before refusing two outputs on one path"
expect 2 match "$ds" --trajectory "$dir/m.tum" --json "$dir/./m.tum"
err_has "is also --trajectory"
expect 2 deskew "$ds" --method none --out "$dir/dk" --json "$dir/dk/deskew.json"
err_has "--json $dir/dk/deskew.json: is inside --out $dir/dk"
[ ! -e "$dir/m.tum" ] && [ ! -e "$dir/same.json" ] && [ ! -e "$dir/dk" ] ||
  fail "a refused command wrote an output"

# 12. export --force into a folder with a file of the user's: refused, the file kept.
mkdir "$dir/keepdir" && echo precious >"$dir/keepdir/k.txt"
expect 2 export "$ds" --format tum --out "$dir/keepdir" --force
err_has "not a trajectories folder an export wrote"
[ "$(cat "$dir/keepdir/k.txt")" = precious ] || fail "export --force deleted a user's k.txt"
cp "$dir/tum/odom_nominal.tum" "$dir/keepdir/"
expect 2 export "$ds" --format kitti --out "$dir/keepdir" --force
[ -f "$dir/keepdir/k.txt" ] || fail "export --force deleted a user's k.txt"
expect 0 export "$ds" --format kitti --out "$dir/tum" --force  # only what export writes

# Empty, long and unwritable paths: refused naming the option, before any work.
expect 2 simulate --scenario worlds/scenarios/arc.yaml --duration 3 --out ""
err_has "--out: is empty"
expect 2 calibrate "$fig8" --motion groundtruth --json ""
err_has "--json: is empty"
long=$(printf 'n%.0s' $(seq 250))  # legal: 250 bytes; its partial sibling is shortened to fit
expect 0 simulate --scenario worlds/scenarios/arc.yaml --duration 1 --mode kinematic --quiet \
  --out "$dir/$long"
[ -f "$dir/$long/dataset.json" ] || fail "a 250-byte --out was not written"
expect 0 match "$ds" --json "$dir/$long.json"
expect 2 match "$ds" --json "$dir/$long$long.json"
err_has "longer than 255 bytes"
echo "a file" >"$dir/plain"
expect 2 calibrate "$fig8" --motion groundtruth --method joint --json "$dir/plain/cal.json"
err_has "--json $dir/plain/cal.json: $dir/plain is not a folder"
grep -q "intervals (" "$dir/err" && fail "calibrate worked before finding its --json unwritable"
if [ "$(id -u)" != 0 ]; then  # root writes anywhere
  mkdir "$dir/ro" && chmod 555 "$dir/ro"
  expect 2 deskew "$ds" --method none --out "$dir/ro/sub/fixed"
  err_has "cannot write into $dir/ro"
fi
no_partials "$dir"

# 7. An output that appears during a run is not replaced without --force. A long run is past its
# checks once it has used 0.3 s of CPU (they take milliseconds); then another run writes the same
# --out, or the user puts a dataset there. The long run must end refused, the other's intact.
long_run() {  # long_run OUT: a 200 s kinematic drive in the background, $! its pid
  "$slamprep" simulate --scenario worlds/scenarios/arc.yaml --duration 200 --mode kinematic \
    --quiet --out "$1" >/dev/null 2>"$1.err" &
}
past_checks() {  # past_checks PID: waits until the process has used 30 clock ticks of CPU
  for _ in $(seq 1 1000); do
    [ "$(awk '{print $14 + $15}' "/proc/$1/stat" 2>/dev/null || echo 0)" -ge 30 ] && return
    sleep 0.01
  done
  fail "the long run never got going"
}
refused_at_the_end() {  # refused_at_the_end PID OUT
  local code
  set +e
  wait "$1"
  code=$?
  set -e
  [ "$code" = 2 ] || fail "a run whose --out appeared meanwhile exited $code: $(cat "$2.err")"
  grep -qF -- "--out $2: appeared while this command ran" "$2.err" ||
    fail "no message naming --out: $(cat "$2.err")"
}
long_run "$dir/race"
first=$!
past_checks "$first"
expect 0 simulate --scenario worlds/scenarios/arc.yaml --duration 1 --mode kinematic --quiet \
  --seed 7 --out "$dir/race"
fingerprint "$dir/race" >"$dir/race.second"
refused_at_the_end "$first" "$dir/race"
unchanged "$dir/race" "$dir/race.second" "a run without --force, at its end"
long_run "$dir/placed"
late=$!
past_checks "$late"
mkdir "$dir/placed" && cp -r "$ds"/. "$dir/placed/"
refused_at_the_end "$late" "$dir/placed"
unchanged "$dir/placed" "$dir/ds.before" "a run without --force, at its end"
no_partials "$dir"

# Interrupted: SIGINT or SIGTERM while the new dataset is being written removes the partial
# folder; the old dataset stays as it was. (Job control: a background job keeps its SIGINT.)
set -m
for signal in INT TERM; do
  "$slamprep" simulate --scenario worlds/scenarios/arc.yaml --duration 200 --mode kinematic \
    --quiet --force --out "$ds" >/dev/null 2>&1 &
  pid=$!
  for _ in $(seq 1 3000); do ls -d "$dir"/ds.partial-* >/dev/null 2>&1 && break; sleep 0.01; done
  ls -d "$dir"/ds.partial-* >/dev/null 2>&1 || fail "no partial folder to interrupt"
  kill -"$signal" "$pid"
  set +e
  wait "$pid"
  code=$?
  set -e
  [ "$code" -gt 128 ] || fail "SIG$signal: the run exited $code, not by the signal"
  no_partials "$dir"
  unchanged "$ds" "$dir/ds.before" "an interrupted simulate --force"
done
set +m

# 1. and 2. bench writes only into a results folder it created (.slamprep-results), under its
# --results, named by one file-name part.
cat >"$dir/tiny.yaml" <<YAML
name: tiny
worlds: [worlds/room.yaml]
scenarios: [worlds/scenarios/arc.yaml]
mode: kinematic
duration_s: 1
calibration_methods: []
deskew_methods: [none]
YAML
mkdir -p "$dir/home/tiny/trials" && echo mine >"$dir/home/tiny/trials/mine.csv" &&
  echo mine >"$dir/home/tiny/README.md"
fingerprint "$dir/home" >"$dir/home.before"
for extra in "" "--fresh" "--shard 1/2"; do
  # shellcheck disable=SC2086
  expect 2 bench --suite "$dir/tiny.yaml" --results "$dir/home" --quiet --no-plots $extra
  err_has "--results $dir/home/tiny: exists but has no .slamprep-results"
done
expect 2 merge "$dir/home/tiny" --no-plots
expect 2 plot "$dir/home/tiny"
cp "$dir/tiny.yaml" "$dir/home/tiny/suite.yaml" && echo '{}' >"$dir/home/tiny/summary.json"
fingerprint "$dir/home" >"$dir/home.before"
expect 2 merge "$dir/home/tiny" --no-plots
err_has "RESULTS_DIR $dir/home/tiny: exists but has no .slamprep-results"
expect 2 plot "$dir/home/tiny"
err_has "RESULTS_DIR $dir/home/tiny: exists but has no .slamprep-results"
unchanged "$dir/home" "$dir/home.before" "bench, merge or plot in a folder they did not create"
expect 0 bench --suite "$dir/tiny.yaml" --results "$dir/res" --quiet --no-plots
[ -f "$dir/res/tiny/.slamprep-results" ] || fail "bench made a results folder without its marker"
expect 0 bench --suite "$dir/tiny.yaml" --results "$dir/res" --quiet --no-plots --fresh
expect 0 plot "$dir/res/tiny"
mkdir -p "$dir/a/b"
for name in '../../victim' "$dir/abs" '""' '.' '"x'"'"'\ntouch pwned\n#"'; do
  { echo "name: $name" && tail -n +2 "$dir/tiny.yaml"; } >"$dir/bad.yaml"
  expect 2 bench --suite "$dir/bad.yaml" --results "$dir/a/b/res" --quiet --no-plots
  err_has "$dir/bad.yaml:1:7: name: "
done
[ ! -e "$dir/a/victim" ] && [ ! -e "$dir/abs" ] && [ ! -e "$dir/a/b/res" ] && [ ! -e pwned ] ||
  fail "a suite name wrote outside --results: $(ls "$dir/a" "$dir/a/b")"
echo "guard ok"
