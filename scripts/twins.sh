#!/bin/bash
# The `twins` suite (docs/twin.md "The twins suite"): real recordings of different robots, each
# twinned with several seeds, every twin compared with its recording, and the tables of
# results/twins/README.md.
#
#   scripts/twins.sh DATA_DIR WORK_DIR RESULTS_DIR [SLAMPREP]
#
# DATA_DIR holds the recordings as /work/data does (MANIFEST.md: sources, commits, licences);
# WORK_DIR gets the imported datasets, the twins and the match outputs (large: not committed);
# RESULTS_DIR gets the small outputs: per recording and seed the comparison JSON, per recording
# the comparison plot of seed 1 and the de-skew errors, summary.json and README.md (written by
# scripts/twins_report.py). SEEDS (default "1 2 3 4 5 6 7 8") sets the seeds. Per recording: import, match
# with every de-skew method (the real ranking by residual; per scan, for the orderings it
# resolves), then per seed: twin, twin --compare,
# deskew on the twin (the twin's ranking by ground-truth error), match on the twin with every
# method (the twin's ranking by the real side's residual). Every match and deskew runs with
# --sync auto, as a user would on a robot whose scans lag its wheels (the Neatos' by 0.3 s): a
# ranking without it ranks how each method suffers the delay. REUSE=1 keeps what an earlier run left
# in WORK_DIR and RESULTS_DIR (an interrupted run goes on where it stopped; a step added since is
# run on the twins already made).
set -euo pipefail
data=${1:?usage: $0 DATA_DIR WORK_DIR RESULTS_DIR [SLAMPREP]}
work=${2:?usage: $0 DATA_DIR WORK_DIR RESULTS_DIR [SLAMPREP]}
results=${3:?usage: $0 DATA_DIR WORK_DIR RESULTS_DIR [SLAMPREP]}
slamprep=$(realpath "${4:-build/slamprep}")
seeds=${SEEDS:-1 2 3 4 5 6 7 8}
first=${seeds%% *}
here=$(cd "$(dirname "$0")" && pwd)
deskew_methods="none const-velocity odom-linear odom-quadratic vicp odom-icp"

# name | robot | format | path under DATA_DIR | import flags. aces600 is the first 600 s of the
# ACES log (cut here by its timestamps): the 10-minute recording the timing goal names.
recordings=(
  "aces600|carmen-aces|carmen|carmen-radish-mola/aces.clf|--odometry laser"
  "tb4lite-macfirst|turtlebot4-lite|rosbag2|tb4lite-olin-macfirst-floor-take2/macfirst_floor_take_2|--nominal 0.036,0.036,0.233 --trim --reverse-beam-time"
  "neato-EarlJr53-wall_follower_real|neato|rosbag2|neato-EarlJr53-comprobo-warmup/wall_follower_real|--nominal 0.036,0.036,0.248 --trim"
  "neato-DanPark13-finite-state-controller|neato|rosbag2|neato-DanPark13-comprobo24_warmup_project/finite-state-controller|--nominal 0.036,0.036,0.248 --trim"
  "neato-DanPark13-test-bag|neato|rosbag2|neato-DanPark13-comprobo24_warmup_project/test-bag|--nominal 0.036,0.036,0.248 --trim"
  "neato-lhwitten-fsm_bag|neato|rosbag2|neato-lhwitten-comprobo_warmup/fsm_bag|--nominal 0.036,0.036,0.248 --trim"
)

# REUSE=1 and FILE made before from the twin at hand ($fresh = 0: not made again in this run).
done_before() { [ "${REUSE:-0}" = 1 ] && [ "$fresh" = 0 ] && [ -f "$1" ]; }

mkdir -p "$work" "$results"
echo "slamprep results folder: scripts/twins.sh created it and rewrites what it wrote (docs/twin.md)." \
  >"$results/.slamprep-results"
: >"$results/recordings.tsv"
for entry in "${recordings[@]}"; do
  IFS='|' read -r name robot format path flags <<<"$entry"
  printf '%s\t%s\t%s\t%s\t%s\n' "$name" "$robot" "$format" "$path" "$flags" >>"$results/recordings.tsv"
  real="$work/$name"
  src="$data/$path"
  if [ "${REUSE:-0}" = 1 ] && [ -f "$work/$name.matched" ]; then
    : # imported and matched before
  elif [ "$name" = aces600 ]; then  # lines up to 600 s after the first stamped one
    awk 'NF > 3 && $1 !~ /^#/ { t = $(NF - 2); if (t0 == "") t0 = t; if (t - t0 > 600) exit } { print }' \
      "$src" >"$work/aces600.clf"
    src="$work/aces600.clf"
  fi
  if [ "${REUSE:-0}" != 1 ] || [ ! -f "$work/$name.match.odom-icp.jsonl" ]; then
    # shellcheck disable=SC2086
    "$slamprep" import --format "$format" "$src" --out "$real" --force $flags >/dev/null 2>&1
    for m in $deskew_methods; do
      "$slamprep" match "$real" --deskew "$m" --sync auto \
        --json "$work/$name.match.$m.json" --out "$work/$name.match.$m.jsonl" --force -q \
        >/dev/null 2>&1 || true  # exit 3 (nothing matched) leaves the method out
    done
    touch "$work/$name.matched"
  fi
  for seed in $seeds; do
    twin="$work/$name.twin.$seed"
    # REUSE: a seed whose outputs all exist is done; a twin made before is not made again, and
    # what is missing of its outputs is made from it.
    made=("$results/$name.seed$seed.json" "$work/$name.seed$seed.deskew.json")
    for m in $deskew_methods; do made+=("$work/$name.twin.$seed.match.$m.json"); done
    fresh=0
    if done_before "${made[0]}" && ls "${made[@]}" >/dev/null 2>&1; then
      continue
    fi
    if ! done_before "${made[0]}" || [ ! -f "$twin/dataset/scans.jsonl" ]; then
      fresh=1
      "$slamprep" twin "$real" --out "$twin" --seed "$seed" --force -q >"$work/$name.twin.$seed.log"
      tail -1 "$work/$name.twin.$seed.log"
      cp "$twin/twin.json" "$work/$name.seed$seed.twin.json"
      [ "$seed" = "$first" ] && cp "$twin/twin.json" "$results/$name.twin.json"
      plot=()
      [ "$seed" = "$first" ] && plot=(--plot "$results/$name.png")
      "$slamprep" twin --compare "$real" "$twin" --json "$results/$name.seed$seed.json" \
        "${plot[@]}" --force -q >/dev/null
    fi
    # The twin's ranking by ground-truth error ...
    done_before "$work/$name.seed$seed.deskew.json" ||
      "$slamprep" deskew "$twin/dataset" --sync auto --json "$work/$name.seed$seed.deskew.json" \
        --force -q \
        >/dev/null 2>&1 || true
    # ... and by the residual the real ranking uses: can that residual rank at all?
    for m in $deskew_methods; do
      done_before "$work/$name.twin.$seed.match.$m.json" ||
        "$slamprep" match "$twin/dataset" --deskew "$m" --sync auto --json \
          "$work/$name.twin.$seed.match.$m.json" --force -q >/dev/null 2>&1 || true
    done
  done
done
python3 "$here/twins_report.py" "$work" "$results" "$seeds"
