#!/usr/bin/env bash
# Reproduces results/real/README.md, "Calibration": per benchmark log, the raw odometry and the
# odometry re-integrated with the calibrated geometry, scored on the log's relations.
#   scripts/real_calibration.sh [SLAMPREP] [REALDATA] [WORKDIR]
# REALDATA holds intel/intel.clf, aces/aces.clf, fr079/fr079.clf and their .relations (not
# committed; sources in docs/score.md). Writes WORKDIR/<log>/{raw,calibrated,notrim}.json and
# calibration*.json, and prints one table row per log.
set -euo pipefail
SLAMPREP=${1:-./build/slamprep}
REAL=${2:-/work/realdata}
WORK=${3:-/tmp/slamprep-real-calibration}
mkdir -p "$WORK"

# log, import flags (docs/score.md, "Raw odometry of the benchmark logs").
LOGS=("intel|--odometry laser --reorder-tolerance 1" "aces|" "fr079|--trim")

for entry in "${LOGS[@]}"; do
  name=${entry%%|*}
  flags=${entry#*|}
  w="$WORK/$name"
  rm -rf "$w" && mkdir -p "$w"
  # shellcheck disable=SC2086
  "$SLAMPREP" import --format carmen "$REAL/$name/$name.clf" --out "$w/dataset" $flags \
    > "$w/import.log" 2>&1
  "$SLAMPREP" export "$w/dataset" --format tum --out "$w/tum" > /dev/null 2>&1
  "$SLAMPREP" score relations "$REAL/$name/$name.relations" "$w/tum/odom_nominal.tum" \
    --json "$w/raw.json" > /dev/null
  # The odometry re-integrated from the derived increments with the nominal geometry: the
  # derivation drops sideways steps no wheel explains, so this, not the log, is the like baseline.
  "$SLAMPREP" import --format carmen "$REAL/$name/$name.clf" --out "$w/nominal-dataset" $flags \
    --nominal 0.1,0.1,0.5 > /dev/null 2>&1
  echo '[{"method": "model", "ok": true, "r_L": 0.1, "r_R": 0.1, "b": 0.5}]' > "$w/nominal.json"
  "$SLAMPREP" export "$w/nominal-dataset" --format tum --out "$w/tum-nominal" \
    --calibration "$w/nominal.json" > /dev/null 2>&1
  "$SLAMPREP" score relations "$REAL/$name/$name.relations" \
    "$w/tum-nominal/odom_calibrated.tum" --json "$w/reintegrated.json" > /dev/null
  for variant in trim notrim; do
    extra=()
    [ "$variant" = notrim ] && extra=(--trim-sigmas 0)
    "$SLAMPREP" calibrate "$w/dataset" --json "$w/calibration-$variant.json" \
      --odometry-out "$w/odom-$variant.tum" --ros2-params "$w/ros2-$variant.yaml" \
      "${extra[@]}" > "$w/calibrate-$variant.log" 2> "$w/calibrate-$variant.err"
    "$SLAMPREP" score relations "$REAL/$name/$name.relations" "$w/odom-$variant.tum" \
      --json "$w/$variant.json" > /dev/null
  done
done

python3 - "$WORK" <<'PY'
import json, sys, os
work = sys.argv[1]
def cell(j, s, k):
    v = j[s][k]
    return f"{v['mean']:.4g} ± {v['std']:.3g}"
print("| log | odometry | all: trans [m] | all: rot [deg] | < 5 s: trans [m] | < 5 s: rot [deg] | best method: scale r_L, r_R, b | intervals trimmed / used |")
print("|---|---|---|---|---|---|---|---|")
for name in ("intel", "aces", "fr079"):
    w = os.path.join(work, name)
    for variant, label in (("raw", "raw (log)"), ("reintegrated", "re-integrated, nominal"), ("trim", "calibrated, trimmed"), ("notrim", "calibrated, --trim-sigmas 0")):
        j = json.load(open(os.path.join(w, variant + ".json")))
        extra = ""
        if variant in ("trim", "notrim"):
            runs = json.load(open(os.path.join(w, f"calibration-{variant}.json")))
            order = ["ceres", "joint", "model", "direct"]
            best = sorted([r for r in runs if r["ok"]], key=lambda r: order.index(r["method"]))[0]
            sc = best.get("scale", {})
            extra = (f"{best['method']}: {sc.get('r_L', 0):.4f}, {sc.get('r_R', 0):.4f}, {sc.get('b', 0):.4f}"
                     f" | {best['intervals_trimmed']} / {best['intervals']}")
        else:
            extra = " | "
        print(f"| {name} | {label} | {cell(j,'all','translation_m')} | {cell(j,'all','rotation_deg')} | "
              f"{cell(j,'short','translation_m')} | {cell(j,'short','rotation_deg')} | {extra} |")
PY
