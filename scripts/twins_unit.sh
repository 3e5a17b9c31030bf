#!/bin/bash
# Twins of one robot's recordings, each given the robot's combined calibration as its truth: how
# far calibration spreads over those drives on a robot whose geometry is one, against how far it
# spreads over the real recordings (docs/twin.md, "One robot's recordings").
#
#   scripts/twins_unit.sh WORK_DIR DATASET [DATASET ...]
#
# DATASETs are imported recordings of one robot (slamprep import). WORK_DIR gets unit.json (the
# recordings calibrated together: the twins' truth), per recording and seed the twin and its
# comparison (twin --compare --json), and summary.txt, the table this prints. SEEDS (default
# "1 2 3 4 5 6 7 8") sets the seeds; SLAMPREP the binary (default build/slamprep).
set -euo pipefail
work=${1:?usage: $0 WORK_DIR DATASET [DATASET ...]}
shift
[ $# -ge 2 ] || { echo "$0: give two or more DATASETs of one robot" >&2; exit 2; }
slamprep=$(realpath "${SLAMPREP:-build/slamprep}")
seeds=${SEEDS:-1 2 3 4 5 6 7 8}
mkdir -p "$work"
# The calibration twin --compare runs on both sides (docs/twin.md), on all recordings together.
"$slamprep" calibrate "$@" --method joint --motion map --keyframe-cm 20 \
  --json "$work/unit.json" --force >/dev/null 2>&1 || true
[ -s "$work/unit.json" ] || { echo "$0: the recordings do not calibrate together" >&2; exit 3; }
names=()
for dataset in "$@"; do
  name=$(basename "$dataset")
  names+=("$name")
  for seed in $seeds; do
    twin="$work/$name.twin.$seed"
    "$slamprep" twin "$dataset" --calibration "$work/unit.json" --out "$twin" --seed "$seed" \
      --force -q >"$twin.log" 2>&1 || { echo "$name seed $seed: twin failed ($twin.log)"; continue; }
    "$slamprep" twin --compare "$dataset" "$twin" --json "$work/$name.seed$seed.json" --force -q \
      >/dev/null 2>&1 || echo "$name seed $seed: compare failed"
  done
  echo "$name: $(echo $seeds | wc -w) twins" >&2
done
python3 - "$work" "$seeds" "${names[@]}" <<'EOF' | tee "$work/summary.txt"
import json, os, statistics as st, sys
work, seeds, names = sys.argv[1], sys.argv[2].split(), sys.argv[3:]
combined = json.load(open(os.path.join(work, "unit.json")))["combined"][0]
print("truth of every twin: b = %.1f mm (the recordings calibrated together)" % (combined["b"] * 1e3))
print("| recording | real b mm | real sigma mm | twin b mean (sd over seeds) mm | twin sigma mm |")
print("|---|---|---|---|---|")
real, twin_by_seed = {}, {s: {} for s in seeds}
for name in names:
    bs, sigmas, row = [], [], None
    for seed in seeds:
        path = os.path.join(work, "%s.seed%s.json" % (name, seed))
        if not os.path.exists(path):
            continue
        stat = json.load(open(path))["statistics"]
        row = stat
        if stat["calibration_b_m"]["twin"] is not None:
            bs.append(stat["calibration_b_m"]["twin"] * 1e3)
            sigmas.append(stat["calibration_sigma_b"]["twin"] * 1e3)
            twin_by_seed[seed][name] = bs[-1]
    if row and row["calibration_b_m"]["real"] is not None:
        real[name] = (row["calibration_b_m"]["real"] * 1e3, row["calibration_sigma_b"]["real"] * 1e3)
    r = real.get(name)
    print("| %s | %s | %s | %s | %s |" % (
        name, "%.1f" % r[0] if r else "refused", "%.1f" % r[1] if r else "-",
        "%.1f (%.1f), %d seeds" % (st.mean(bs), st.stdev(bs) if len(bs) > 1 else 0.0, len(bs))
        if bs else "refused", "%.1f" % st.mean(sigmas) if sigmas else "-"))
# Over the recordings that calibrate on the robot, per seed: what one robot's drives spread.
spreads = []
for seed in seeds:
    b = [twin_by_seed[seed][n] for n in real if n in twin_by_seed[seed]]
    if len(b) >= 2:
        spreads.append(st.stdev(b))
if len(real) >= 2 and spreads:
    real_sd = st.stdev([b for b, _ in real.values()])
    med = st.median(spreads)
    print("spread of b over the %d recordings that calibrate: real %.1f mm; twins, per seed, median "
          "%.1f mm (%.1f-%.1f over %d seeds): %.2fx" % (len(real), real_sd, med, min(spreads),
                                                     max(spreads), len(spreads), med / real_sd))
EOF
