#!/usr/bin/env bash
# Scan-matching benchmark on the real SLAM-benchmark logs (results/real/README.md): for each log
# with relations, import -> match --trajectory -> score relations, then one table row per log.
#
#   bash scripts/real_bench.sh LOGS_DIR [OUT_DIR] [SLAMPREP]
#
# LOGS_DIR holds intel/intel.clf, aces/aces.clf, fr079/fr079.clf, fr-clinic/fr-clinic.clf (the
# Freiburg hospital's fr-clinic_robotlaser.clf), mit-csail/mit-csail.clf and their .relations
# files (missing logs are skipped; MIT CSAIL's relations are kept unscored in this repository:
# results/real/README.md "Generalisation"). OUT_DIR (default /tmp/slamprep-real) receives per log: the
# dataset, match.tum, match.json (summary of `match`), score.json (of `score relations`).
# Extra `match` flags can be given in MATCH_FLAGS (the defaults are the documented ones).
set -euo pipefail
logs=${1:?usage: real_bench.sh LOGS_DIR [OUT_DIR] [SLAMPREP]}
out=${2:-/tmp/slamprep-real}
bin=${3:-$(dirname "$0")/../build/slamprep}
mkdir -p "$out"

# The import flags of each log (docs/score.md, "Raw odometry of the benchmark logs"): the laser
# lines' own odometry, at the very stamps the relations name; Intel's stamps run back by < 1 s.
declare -A import_flags=(
  [intel]="--odometry laser --reorder-tolerance 1"
  [aces]="--odometry laser"
  [fr079]="--odometry laser"
  [fr-clinic]="--odometry laser"
  [mit-csail]="--odometry laser"
)

for name in intel aces fr079 fr-clinic mit-csail; do
  clf=$logs/$name/$name.clf
  rel=$logs/$name/$name.relations
  if [[ ! -f $clf || ! -f $rel ]]; then
    echo "skip $name: no $clf or $rel" >&2
    continue
  fi
  dir=$out/$name
  rm -rf "$dir" && mkdir -p "$dir"
  # shellcheck disable=SC2086  # the flags are words
  "$bin" import --format carmen "$clf" --out "$dir/dataset" ${import_flags[$name]} >"$dir/import.txt"
  # shellcheck disable=SC2086
  "$bin" match "$dir/dataset" --deskew none --trajectory "$dir/match.tum" \
    --json "$dir/match.json" ${MATCH_FLAGS:-} | tee "$dir/match.txt"
  "$bin" score relations "$rel" "$dir/match.tum" --json "$dir/score.json" >"$dir/score.txt"
done

# One row per log: relation error (translation, m) over all relations and those < 5 s apart,
# mean ± std (max); converged %, run time of `match`.
python3 - "$out" <<'PY'
import json, os, sys
out = sys.argv[1]
print("| log | relations (< 5 s) | all: trans [m] | < 5 s: trans [m] | all: rot [deg] | converged | match time |")
print("|---|---|---|---|---|---|---|")
for name in ("intel", "aces", "fr079", "fr-clinic", "mit-csail"):
    d = os.path.join(out, name)
    if not os.path.exists(os.path.join(d, "score.json")):
        continue
    s = json.load(open(os.path.join(d, "score.json")))
    m = json.load(open(os.path.join(d, "match.json")))
    a, b, r = s["all"]["translation_m"], s["short"]["translation_m"], s["all"]["rotation_deg"]
    print(f"| {name} | {s['scored']} ({s['short_scored']}) "
          f"| {a['mean']:.3f} ± {a['std']:.3f} ({a['max']:.3f}) "
          f"| {b['mean']:.4f} ± {b['std']:.4f} ({b['max']:.3f}) "
          f"| {r['mean']:.2f} ± {r['std']:.2f} ({r['max']:.1f}) "
          f"| {m['converged_percent']:.2f} % ({m['fallbacks']} fallbacks of {m['scans'] - 1}) "
          f"| {m['seconds']:.1f} s |")
PY
