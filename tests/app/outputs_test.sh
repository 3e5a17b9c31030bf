#!/bin/bash
# No command removes or replaces data unless asked: an existing output is refused (exit 2, named)
# without --force; --force replaces it only once the new one is complete, so a run whose write
# fails keeps the old bytes; deskew and match never write into their input.
source "$(dirname "$0")/cli_lib.sh"

# expect_write_failure KB ARGS...: runs slamprep with every write beyond KB kilobytes failing
# (EFBIG: SIGXFSZ is ignored, which exec keeps), so the new dataset or file cannot be completed
# (60 kB: a dataset's small files are written, its trajectories are not). It must exit 2 naming
# what it could not write; what matters then is that the old bytes are still there.
expect_write_failure() {
  local kb=$1 got
  shift
  set +e
  (ulimit -f "$kb" && trap '' XFSZ && exec "$slamprep" "$@") >"$dir/out" 2>"$dir/err"
  got=$?
  set -e
  [ "$got" = 2 ] || fail "slamprep $* exited $got with writes beyond $kb kB failing: $(cat "$dir/err")"
}
unchanged() {  # unchanged PATH BEFORE_FINGERPRINT_FILE WHAT
  fingerprint "$1" | cmp -s - "$2" || fail "$3 changed $1"
}
no_partials() {
  ! ls -d "$dir"/*.partial-* >/dev/null 2>&1 || fail "a partial sibling was left: $(ls -d "$dir"/*.partial-*)"
}

ds=$dir/ds
simulate_arc "$ds"
fingerprint "$ds" >"$dir/ds.before"

# simulate over a dataset: refused, named, nothing simulated; a failed --force keeps the old.
expect 2 simulate --scenario worlds/scenarios/arc.yaml --duration 3 --quiet --out "$ds"
err_has "$ds: exists; give --force to replace it"
unchanged "$ds" "$dir/ds.before" "a refused simulate"
echo "not a dataset" >"$dir/file"
start=$SECONDS
expect 2 simulate --duration 0 --out "$dir/file"  # the 60 s default drive: refused at once
[ $((SECONDS - start)) -lt 5 ] || fail "simulate ran before refusing an existing file"
err_has "$dir/file: exists and is not a dataset directory"
expect 2 simulate --force --out "$dir/file"
[ "$(cat "$dir/file")" = "not a dataset" ] || fail "simulate --force replaced a plain file"
expect_write_failure 60 simulate --scenario worlds/scenarios/arc.yaml --duration 3 --mode kinematic \
  --quiet --force --set lidar.rate_hz=5 --out "$ds"
unchanged "$ds" "$dir/ds.before" "a failed simulate --force"
no_partials

# import over a dataset: the same.
expect 0 export "$ds" --format carmen --out "$dir/ds.carmen"
expect 2 import --format carmen "$dir/ds.carmen" --out "$ds"
err_has "give --force"
unchanged "$ds" "$dir/ds.before" "a refused import"
expect_write_failure 60 import --format carmen "$dir/ds.carmen" --out "$ds" --force
unchanged "$ds" "$dir/ds.before" "a failed import --force"
no_partials
expect 0 import --format carmen "$dir/ds.carmen" --out "$dir/imported"
expect 0 import --format carmen "$dir/ds.carmen" --out "$dir/imported" --force

# deskew: never into its input; --out is a new dataset with the de-skewed scans.
expect 0 deskew "$ds" --method all
out_has "no --out: no de-skewed scans written"
unchanged "$ds" "$dir/ds.before" "deskew without --out"
expect 2 deskew "$ds" --out "$ds" --force
err_has "is the input DATASET"
expect 2 deskew "$ds" --out "$ds/deskewed"
expect 2 deskew "$ds" --json "$ds/deskew.json"
unchanged "$ds" "$dir/ds.before" "a refused deskew"
expect 0 deskew "$ds" --method odom-linear --out "$dir/fixed"
out_has "wrote $dir/fixed: a copy of the dataset plus deskewed_odom-linear.jsonl"
[ -f "$dir/fixed/dataset.json" ] && [ -f "$dir/fixed/deskewed_odom-linear.jsonl" ] ||
  fail "deskew --out lacks the dataset or the scans: $(ls "$dir/fixed")"
fingerprint "$dir/fixed" >"$dir/fixed.before"
expect 2 deskew "$ds" --method none --out "$dir/fixed"
unchanged "$dir/fixed" "$dir/fixed.before" "a refused deskew --out"
expect_write_failure 60 deskew "$ds" --method none --out "$dir/fixed" --force
unchanged "$dir/fixed" "$dir/fixed.before" "a failed deskew --force"
no_partials
expect 0 deskew "$ds" --method none --out "$dir/fixed" --force
[ -f "$dir/fixed/deskewed_none.jsonl" ] && [ ! -e "$dir/fixed/deskewed_odom-linear.jsonl" ] ||
  fail "deskew --force did not replace the folder: $(ls "$dir/fixed")"
expect 0 export "$dir/fixed" --format csm --scans none --out "$dir/fixed.csm"
err_has "sm2 -in $dir/fixed.csm -laser_x "  # CSM's sm2 needs the mount: the export says how

# match: nothing without --out, never into its input, an existing file only with --force.
expect 0 match "$ds"
out_has "no --out"
expect 2 match "$ds" --out "$ds/matches.jsonl"
unchanged "$ds" "$dir/ds.before" "match"
expect 0 match "$ds" --out "$dir/matches.jsonl"
expect 2 match "$ds" --out "$dir/matches.jsonl"
err_has "$dir/matches.jsonl: exists; give --force"
expect 0 match "$ds" --out "$dir/matches.jsonl" --force
expect 2 match "$ds" --trajectory "$ds/match.tum"
expect 0 match "$ds" --trajectory "$dir/match.tum" --json "$dir/match.json"
expect 2 match "$ds" --trajectory "$dir/match.tum"
err_has "$dir/match.tum: exists; give --force"
expect 2 match "$ds" --json "$dir/match.json"
expect 0 match "$ds" --trajectory "$dir/match.tum" --json "$dir/match.json" --force

# export, a file and a folder of trajectories.
fingerprint "$dir/ds.carmen" >"$dir/carmen.before"
expect 2 export "$ds" --format carmen --out "$dir/ds.carmen"
expect_write_failure 60 export "$ds" --format carmen --out "$dir/ds.carmen" --force
unchanged "$dir/ds.carmen" "$dir/carmen.before" "a failed export --force"
expect 0 export "$ds" --format tum --out "$dir/tum"
fingerprint "$dir/tum" >"$dir/tum.before"
expect 2 export "$ds" --format tum --out "$dir/tum"
expect_write_failure 60 export "$ds" --format tum --out "$dir/tum" --force
unchanged "$dir/tum" "$dir/tum.before" "a failed export --force"
no_partials
expect 0 export "$ds" --format tum --out "$dir/tum" --force
mkdir "$dir/notes" && echo keep >"$dir/notes/todo.md"
expect 2 export "$ds" --format kitti --out "$dir/notes" --force
err_has "not a trajectories folder"
expect 2 export "$ds" --format tum --out "$ds/tum"
unchanged "$ds" "$dir/ds.before" "export"

# calibrate: --json and --intervals are outputs like any other.
echo '[]' >"$dir/cal.json"
expect 2 calibrate "$ds" --motion groundtruth --method model --json "$dir/cal.json"
err_has "$dir/cal.json: exists; give --force"
[ "$(cat "$dir/cal.json")" = "[]" ] || fail "a refused calibrate replaced its --json"
expect 2 calibrate "$ds" --motion groundtruth --method model --intervals "$ds/intervals.jsonl"
expect_write_failure 0 calibrate "$ds" --motion groundtruth --method model --json "$dir/cal.json" \
  --intervals "$dir/intervals.jsonl" --force
[ "$(cat "$dir/cal.json")" = "[]" ] || fail "a failed calibrate --force replaced its --json"
unchanged "$ds" "$dir/ds.before" "calibrate"
echo "outputs ok"
