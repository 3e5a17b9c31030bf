#!/usr/bin/env bash
# Reproduces results/real/README.md, "Calibration": per benchmark log, the raw odometry and the
# odometry re-integrated with the calibrated geometry, scored on the log's relations.
#   scripts/real_calibration.sh [SLAMPREP] [REALDATA] [WORKDIR]
# REALDATA holds intel/intel.clf, aces/aces.clf, fr079/fr079.clf and their .relations (not
# committed; sources in docs/score.md). Writes WORKDIR/<log>/{raw,reintegrated,trim,notrim,kf30}.json and
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
  # The log's own laser-line odometry at the scan stamps: the relations' baseline
  # (scripts/relation_steps.py; results/real/README.md "The relations' resolution").
  "$SLAMPREP" import --format carmen "$REAL/$name/$name.clf" --out "$w/laser-dataset" \
    --odometry laser --reorder-tolerance 1 > /dev/null 2>&1
  "$SLAMPREP" export "$w/laser-dataset" --format tum --out "$w/tum-laser" > /dev/null 2>&1
  for variant in trim notrim kf30 map; do
    # trim, notrim, kf30: chained scan-to-scan matches (--motion icp); map: the default motion.
    extra=(--motion icp)
    [ "$variant" = notrim ] && extra+=(--trim-sigmas 0)
    [ "$variant" = kf30 ] && extra+=(--keyframe-cm 30)
    [ "$variant" = map ] && extra=(--motion map)
    # Line fits as `match` makes them on these 180-beam scans: at the library's 0.2, 68 % of
    # ACES' scan matches fail (5029 of 7373), at 0.5 7 %.
    "$SLAMPREP" calibrate "$w/dataset" --json "$w/calibration-$variant.json" --line-thickness 0.5 \
      --odometry-out "$w/odom-$variant.tum" --ros2-params "$w/ros2-$variant.yaml" \
      "${extra[@]}" > "$w/calibrate-$variant.log" 2> "$w/calibrate-$variant.err"
    "$SLAMPREP" score relations "$REAL/$name/$name.relations" "$w/odom-$variant.tum" \
      --json "$w/$variant.json" > /dev/null
  done
done

python3 - "$WORK" "$REAL" <<'PY'
import json, math, os, sys
work, real = sys.argv[1], sys.argv[2]

def tum(path):
    poses = {}
    for line in open(path):
        if line.startswith("#") or not line.strip():
            continue
        t, x, y, _z, _qx, _qy, qz, qw = map(float, line.split()[:8])
        poses[round(t, 6)] = (x, y, 2.0 * math.atan2(qz, qw))
    return poses

def pose_at(poses, keys, t):
    """Linear interpolation, as `score relations` does (keys: sorted stamps)."""
    import bisect
    if round(t, 6) in poses:
        return poses[round(t, 6)]
    i = bisect.bisect_left(keys, t)
    if i == 0 or i >= len(keys):
        return None
    a, b = poses[keys[i - 1]], poses[keys[i]]
    w = (t - keys[i - 1]) / (keys[i] - keys[i - 1])
    dth = math.atan2(math.sin(b[2] - a[2]), math.cos(b[2] - a[2]))
    return (a[0] + w * (b[0] - a[0]), a[1] + w * (b[1] - a[1]), a[2] + w * dth)

def error(a, b, rx, ry):
    c, s = math.cos(a[2]), math.sin(a[2])
    dx, dy = b[0] - a[0], b[1] - a[1]
    return math.hypot(c * dx + s * dy - rx, -s * dx + c * dy - ry)

def informative(name, trajectory):
    """Mean short-relation translation error over the relations that are not the log's own
    odometry (differ from it by >= 0.5 mm), and their count."""
    laser = tum(os.path.join(work, name, "tum-laser", "odom_nominal.tum"))
    poses = tum(trajectory)
    keys = sorted(poses)
    total, n = 0.0, 0
    for line in open(os.path.join(real, name, name + ".relations")):
        f = line.split()
        if len(f) < 8 or line.startswith("#") or float(f[1]) - float(f[0]) >= 5.0:
            continue
        t1, t2, rx, ry = map(float, f[:4])
        a, b = laser.get(round(t1, 6)), laser.get(round(t2, 6))
        if a is None or b is None or error(a, b, rx, ry) < 5e-4:
            continue
        p, q = pose_at(poses, keys, t1), pose_at(poses, keys, t2)
        if p is not None and q is not None:
            total, n = total + error(p, q, rx, ry), n + 1
    return total / max(n, 1), n

def cell(j, s, k):
    v = j[s][k]
    return f"{v['mean']:.4g} ± {v['std']:.3g}"

print("| log | odometry | all: trans [m] | all: rot [deg] | < 5 s: trans [m] | < 5 s: rot [deg] | < 5 s, not the odometry: trans [m] (n) | best method: scale r_L, r_R, b | intervals trimmed / used |")
print("|---|---|---|---|---|---|---|---|---|")
trajectories = {"raw": "tum/odom_nominal.tum", "reintegrated": "tum-nominal/odom_calibrated.tum",
                "trim": "odom-trim.tum", "notrim": "odom-notrim.tum", "kf30": "odom-kf30.tum",
                "map": "odom-map.tum"}
labels = {"raw": "raw (log)", "reintegrated": "re-integrated, nominal", "trim": "calibrated, trimmed",
          "notrim": "calibrated, --trim-sigmas 0", "kf30": "calibrated, --keyframe-cm 30",
          "map": "calibrated, scan-to-map (the default)"}
for name in ("intel", "aces", "fr079"):
    w = os.path.join(work, name)
    for variant, label in labels.items():
        j = json.load(open(os.path.join(w, variant + ".json")))
        mean, n = informative(name, os.path.join(w, trajectories[variant]))
        extra = " | "
        if variant in ("trim", "notrim", "kf30", "map"):
            runs = json.load(open(os.path.join(w, f"calibration-{variant}.json")))
            order = ["ceres", "joint", "model", "direct"]
            best = sorted([r for r in runs if r["ok"]], key=lambda r: order.index(r["method"]))[0]
            sc = best.get("scale", {})
            extra = (f"{best['method']}: {sc.get('r_L', 0):.4f}, {sc.get('r_R', 0):.4f}, {sc.get('b', 0):.4f}"
                     f" | {best['intervals_trimmed']} / {best['intervals']}")
        print(f"| {name} | {label} | {cell(j,'all','translation_m')} | {cell(j,'all','rotation_deg')} | "
              f"{cell(j,'short','translation_m')} | {cell(j,'short','rotation_deg')} | {mean:.4f} ({n}) | {extra} |")
PY
