#!/usr/bin/env python3
"""Real ROS 2 recordings through slamprep (results/real/README.md, "Real ROS 2 recordings").

    python3 scripts/real_rosbag2.py LIST DATA_DIR OUT_DIR [SLAMPREP]

LIST (results/real/rosbag2_recordings.tsv) names each bag folder under DATA_DIR, its robot, its
nominal geometry and import flags. For every recording: import --format rosbag2, then match with
the scans as measured and with each de-skew method (residual of the accepted matches, all scans
and the turning ones: |yaw rate| > 0.3 rad/s from the odometry). For every robot (model): calibrate
all its recordings together with the protocol's settings (CALIBRATE_FLAGS), with a held-out
validation; then per unit (one physical robot, LIST's third column) with two or more recordings,
which is what the consistency across recordings is about, with joint and with the wheels alone
(model with the mount from tf); and per unit, every recording scored whole with the other
recordings' estimate (--leave-one-out).
Prints the tables of the README. The bags are not in the repository (their sources are in LIST).
"""
import json
import math
import os
import subprocess
import sys

DESKEW = ["none", "const-velocity", "odom-linear", "odom-quadratic", "vicp", "odom-icp"]
PROTOCOL = ["--motion", "map", "--keyframe-cm", "20", "--validate-fraction", "0.3"]
CALIBRATE_FLAGS = ["--method", "joint", *PROTOCOL]
# The wheels alone, the mount taken from the bag's tf (docs/calibration.md, --lidar-mount).
WHEELS_FLAGS = ["--method", "model", "--lidar-mount", "dataset", *PROTOCOL]
# Leave one recording out: each recording calibrated whole, scored with the others' combination.
LOO_PROTOCOL = ["--motion", "map", "--keyframe-cm", "20", "--leave-one-out"]
LOO_METHODS = (("model, tf mount", ["--method", "model", "--lidar-mount", "dataset"]),
               ("joint", ["--method", "joint"]))
TURNING_RADPS = 0.3


def run(cmd):
    return subprocess.run(cmd, capture_output=True, text=True)


def recordings(path):
    for line in open(path):
        if line.startswith("#") or not line.strip():
            continue
        name, robot, unit, rel, source, nominal, flags = line.rstrip("\n").split("\t")
        yield dict(name=name, robot=robot, unit=unit, rel=rel, source=source, nominal=nominal,
                   flags=flags.split())


def yaw_rate(odometry):
    """Yaw rate (rad/s) between consecutive odometry samples, by the later stamp."""
    rows = [list(map(float, l.split())) for l in open(odometry) if not l.startswith("#")]
    out = []
    for a, b in zip(rows, rows[1:]):
        ya, yb = 2 * math.atan2(a[6], a[7]), 2 * math.atan2(b[6], b[7])
        d = (yb - ya + math.pi) % (2 * math.pi) - math.pi
        out.append((b[0], d / (b[0] - a[0])))
    return out


def rate_at(rates, t):
    lo, hi = 0, len(rates) - 1
    while lo < hi:
        mid = (lo + hi) // 2
        if rates[mid][0] < t:
            lo = mid + 1
        else:
            hi = mid
    return rates[lo][1] if rates else 0.0


def median(v):
    v = sorted(v)
    return v[len(v) // 2] if v else float("nan")


def match_all(bin_, dataset, out, rates):
    row = {}
    for method in DESKEW:
        lines, summary = f"{out}.{method}.jsonl", f"{out}.{method}.json"
        r = run([bin_, "match", dataset, "--deskew", method, "--out", lines, "--json", summary,
                 "--force", "-q"])
        if r.returncode not in (0, 3):
            row[method] = None
            continue
        scans = [json.loads(l) for l in open(lines)]
        ok = [s for s in scans if not s["fallback"]]
        turning = [s["rms_m"] for s in ok if abs(rate_at(rates, s["stamp_cur"])) > TURNING_RADPS]
        row[method] = dict(all=median([s["rms_m"] for s in ok]), turning=median(turning),
                           n_turning=len(turning), summary=json.load(open(summary)))
    return row


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    listing, data, out = sys.argv[1:4]
    bin_ = sys.argv[4] if len(sys.argv) > 4 else "build/slamprep"
    os.makedirs(out, exist_ok=True)
    by_robot, by_unit, rows = {}, {}, []
    for rec in recordings(listing):
        dataset = os.path.join(out, rec["name"])
        r = run([bin_, "import", "--format", "rosbag2", os.path.join(data, rec["rel"]), "--out",
                 dataset, "--force", "--nominal", rec["nominal"], "--json", dataset + ".import.json",
                 *rec["flags"]])
        if r.returncode != 0:
            rows.append((rec, None, r.stderr.strip().splitlines()[-1]))
            continue
        rates = yaw_rate(os.path.join(dataset, "odom_nominal.tum"))
        rows.append((rec, match_all(bin_, dataset, dataset, rates), ""))
        by_robot.setdefault((rec["robot"], rec["nominal"]), []).append(dataset)
        by_unit.setdefault((rec["unit"], rec["nominal"]), []).append(dataset)
    print_recordings(rows)
    for (robot, nominal), datasets in by_robot.items():
        print_calibration(robot, datasets, calibrate(bin_, robot, nominal, datasets, out))
    print("\n### Per unit (one physical robot, assumed)\n")
    print("| unit | method | recordings (ok) | r_L mm | r_R mm | b mm | chi2/dof r_L, r_R, b; "
          "r_L/b, r_R/b | "
          "held-out raw m / deg | calibrated m / deg | calibrated wheels m | held-out wins: "
          "trans, rot (of scored) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for (unit, nominal), datasets in by_unit.items():
        if len(datasets) < 2:
            continue
        for label, flags in (("joint", CALIBRATE_FLAGS), ("model, tf mount", WHEELS_FLAGS)):
            name = unit + "." + flags[1]
            print_unit(unit, label, datasets, calibrate(bin_, name, nominal, datasets, out, flags))
    print_leave_one_out(bin_, by_unit, out)


def print_leave_one_out(bin_, by_unit, out):
    print("\n### Leave one recording out (" + " ".join(LOO_PROTOCOL) + ")\n")
    print("| unit | method | beats raw: trans, rot (of scored) | raw / calibrated m per recording "
          "| whole recordings: chi2/dof r_L, r_R, b; r_L/b, r_R/b (n) |")
    print("|---|---|---|---|---|")
    for (unit, nominal), datasets in by_unit.items():
        if len(datasets) < 2:
            continue
        for label, method in LOO_METHODS:
            name = unit + ".loo." + method[1]
            code, j, error = calibrate(bin_, name, nominal, datasets, out, [*method, *LOO_PROTOCOL])
            loo = (j or {}).get("leave_one_out", {}).get(method[1])
            if loo is None:
                print(f"| {unit} | {label} | calibrate exit {code}: {error.strip()[:80]} | |")
                continue
            b = loo["beats_raw"]
            cells = ", ".join(f"{r['raw']['trans_m']:.3f}/{r['calibrated']['trans_m']:.3f}"
                              if "raw" in r else "-" for r in loo["recordings"])
            c = j["consistency"].get(method[1], {})
            print(f"| {unit} | {label} | {b['trans']}, {b['rot']} (of {b['scored']}) | {cells} | "
                  f"{chi2_cells(c, ('r_L', 'r_R', 'b'))}; {chi2_cells(c, ('r_L/b', 'r_R/b'))} "
                  f"({c.get('b', {}).get('n', '-')}) |")


def chi2_cells(consistency, keys):
    """chi2/dof of the keys, "-" where there is none (fewer than two recordings ok)."""
    return ", ".join("-" if consistency.get(k, {}).get("chi2_dof") is None
                     else f"{consistency[k]['chi2_dof']:.2f}" for k in keys)


def print_recordings(rows):
    print("| recording | scans | converged | wheels vs scans: lag s, scale | residual median [mm], "
          "all / turning (n): " + ", ".join(DESKEW) + " |")
    print("|---|---|---|---|---|")
    for rec, row, error in rows:
        if row is None:
            print(f"| {rec['name']} | import refused: {error} | | | |")
            continue
        s = row["none"]["summary"]
        pair = next((p for p in s["sensor_agreement"]["pairs"] if p["b"] == "scans"), None)
        agreement = f"{pair['lag_s']:.2f}, {pair['scale']:.3f}" if pair else "-"
        cells = []
        for m in DESKEW:
            x = row[m]
            cells.append("-" if x is None else
                         f"{1e3 * x['all']:.1f} / {1e3 * x['turning']:.1f} ({x['n_turning']})")
        print(f"| {rec['name']} | {s['scans']} | {s['converged_percent']:.1f} % | {agreement} | "
              + " ; ".join(cells) + " |")


def calibrate(bin_, name, nominal, datasets, out, flags=CALIBRATE_FLAGS):
    """calibrate the datasets together; (exit code, the JSON as for several DATASETs, stderr)."""
    result = os.path.join(out, name + ".calibration.json")
    r = run([bin_, "calibrate", *datasets, *flags, "--nominal", nominal, "--json",
             result, "--force", "-q"])
    if r.returncode not in (0, 3):
        return r.returncode, None, r.stderr
    j = json.load(open(result))
    if "recordings" not in j:  # one recording: the list
        j = {"recordings": [{"dataset": datasets[0], "methods": j}], "combined": j,
             "consistency": {}}
    return r.returncode, j, ""


def validation_cells(m):
    v = m.get("validation")
    if not v:
        return "-", "-", "-"
    wheels = v.get("calibrated_wheels")
    return (f"{v['raw']['trans_m']:.3f} / {v['raw']['rot_deg']:.2f}",
            f"{v['calibrated']['trans_m']:.3f} / {v['calibrated']['rot_deg']:.2f}",
            f"{wheels['trans_m']:.3f}" if wheels else "-")


def held_out_wins(j):
    """Recordings whose calibrated odometry beats raw on the held-out part: (trans, rot, scored)."""
    trans = rot = scored = 0
    for rec in j["recordings"]:
        v = rec["methods"][0].get("validation") if rec["methods"][0]["ok"] else None
        if v:
            scored += 1
            trans += v["calibrated"]["trans_m"] < v["raw"]["trans_m"]
            rot += v["calibrated"]["rot_deg"] < v["raw"]["rot_deg"]
    return trans, rot, scored


def print_unit(unit, label, datasets, result):
    code, j, error = result
    if j is None:
        print(f"| {unit} | {label} | {len(datasets)}: calibrate exit {code} | "
              f"{error.strip()[:80]} |")
        return
    m = j["combined"][0]
    ok = sum(1 for rec in j["recordings"] if rec["methods"][0]["ok"])
    if not m["ok"]:
        print(f"| {unit} | {label} | {len(datasets)} ({ok}) | refused: {m['reason'][:80]} "
              "| | | | | | | |")
        return
    c = j["consistency"].get(m["method"], {})
    chi2 = chi2_cells(c, ("r_L", "r_R", "b")) + "; " + chi2_cells(c, ("r_L/b", "r_R/b"))
    sig = m["sigma"]
    raw, cal, wheels = validation_cells(m)
    trans, rot, scored = held_out_wins(j)
    print(f"| {unit} | {label} | {len(datasets)} ({ok}) | {1e3 * m['r_L']:.1f} ± "
          f"{1e3 * sig['r_L']:.1f} | {1e3 * m['r_R']:.1f} ± {1e3 * sig['r_R']:.1f} | "
          f"{1e3 * m['b']:.1f} ± {1e3 * sig['b']:.1f} | {chi2} | {raw} | {cal} | {wheels} | "
          f"{trans}, {rot} (of {scored}) |")


def print_calibration(robot, datasets, result):
    code, j, error = result
    print(f"\n### {robot}: {len(datasets)} recordings, calibrate {' '.join(CALIBRATE_FLAGS)} "
          f"(exit {code})\n")
    if j is None:
        print(error)
        return
    print("| recording | r_L mm | r_R mm | b mm | lidar x, y mm, yaw deg | held-out raw m / deg | "
          "calibrated m / deg | calibrated wheels m |")
    print("|---|---|---|---|---|---|---|---|")
    for rec in j["recordings"] + [{"dataset": "combined", "methods": j["combined"]}]:
        m = rec["methods"][0]
        name = os.path.basename(rec["dataset"])
        if not m["ok"]:
            print(f"| {name} | refused: {m['reason'][:90]} | | | | | | |")
            continue
        raw, cal, wheels = validation_cells(m)
        sig = m["sigma"]
        print(f"| {name} | {1e3 * m['r_L']:.1f} ± {1e3 * sig['r_L']:.1f} | "
              f"{1e3 * m['r_R']:.1f} ± {1e3 * sig['r_R']:.1f} | "
              f"{1e3 * m['b']:.1f} ± {1e3 * sig['b']:.1f} | "
              f"{1e3 * m['lidar_x']:.0f}, {1e3 * m['lidar_y']:.0f}, "
              f"{math.degrees(m['lidar_yaw']):.1f} | {raw} | {cal} | {wheels} |")
    for method, params in j.get("consistency", {}).items():
        print(f"\nchi2/dof over the recordings ({method}): " + ", ".join(
            f"{k} {v['chi2_dof']:.2f} (n {v['n']})" for k, v in params.items()
            if v["chi2_dof"] is not None))


if __name__ == "__main__":
    main()
