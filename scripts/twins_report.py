#!/usr/bin/env python3
"""The tables of the `twins` suite (scripts/twins.sh), from what it left in WORK and RESULTS.

    python3 scripts/twins_report.py WORK RESULTS "SEEDS"

Writes RESULTS/summary.json and RESULTS/README.md. README.md keeps what an earlier one said
after its "## Where the twin and the robot disagree" heading (written by hand from the tables).
Standard library only.
"""
import json
import math
import os
import re
import statistics
import sys

DESKEW = ["none", "const-velocity", "odom-linear", "odom-quadratic", "vicp", "odom-icp"]
ANALYSIS = "## Where the twin and the robot disagree"
TOLERANCE = 0.25


def load(path):
    return json.load(open(path)) if os.path.exists(path) else None


def sd(values):
    return statistics.stdev(values) if len(values) > 1 else 0.0


def ranks(values):
    order = sorted(range(len(values)), key=lambda i: values[i])
    out = [0.0] * len(values)
    for r, i in enumerate(order):
        out[i] = float(r)
    return out


def spearman(a, b):
    """Rank correlation of two equally long lists (no ties expected)."""
    if len(a) < 3:
        return None
    ra, rb = ranks(a), ranks(b)
    n = len(a)
    return 1 - 6 * sum((x - y) ** 2 for x, y in zip(ra, rb)) / (n * (n * n - 1))


def recording(work, results, name, robot, seeds):
    rec = {"name": name, "robot": robot, "seeds": seeds, "statistics": {}, "twin_seconds": []}
    for seed in seeds:
        log = open(os.path.join(work, f"{name}.twin.{seed}.log")).read()
        rec["twin_seconds"].append(float(re.search(r" in ([0-9.]+) s:", log).group(1)))
        twin = load(os.path.join(work, f"{name}.seed{seed}.twin.json"))
        rec.setdefault("drive_mode", []).append(twin["drive"].get("mode"))
        for key, row in load(os.path.join(results, f"{name}.seed{seed}.json"))["statistics"].items():
            s = rec["statistics"].setdefault(key, {"real": row["real"], "twin": []})
            s["twin"].append(row["twin"])
    for s in rec["statistics"].values():
        twins = [v for v in s["twin"] if v is not None]
        s["twin_mean"] = statistics.mean(twins) if twins else None
        s["twin_sd"] = sd(twins) if twins else None
        s["ratio"] = s["twin_mean"] / s["real"] if twins and s["real"] else None
    rec["deskew"] = deskew(work, name, seeds)
    return rec


def deskew(work, name, seeds):
    real = {}
    for m in DESKEW:
        j = load(os.path.join(work, f"{name}.match.{m}.json"))
        # A method that refused every scan matched them as measured: no figure of its own.
        if j and j.get("residual_rms_m") and j["deskew_refused"] < j["scans"]:
            real[m] = j["residual_rms_m"]["median"]
    twin = {}
    for seed in seeds:
        for row in load(os.path.join(work, f"{name}.seed{seed}.deskew.json")) or []:
            if row["method"] in DESKEW and row.get("ok"):
                twin.setdefault(row["method"], []).append(row["mean_m"])
    twin_sd = {m: sd(v) for m, v in twin.items() if len(v) == len(seeds)}
    twin = {m: statistics.mean(v) for m, v in twin.items() if len(v) == len(seeds)}
    both = [m for m in DESKEW if m in real and m in twin]
    best_twin = min(both, key=lambda m: twin[m]) if both else None
    # Methods the twin cannot tell from its best: within the best's spread over the seeds.
    tied = [m for m in both if m != best_twin and
            twin[m] - twin[best_twin] <= (twin_sd.get(best_twin) or 0.0)] if both else []
    return {"real_residual_median_m": real, "twin_truth_error_mean_m": twin,
            "twin_truth_error_sd_m": twin_sd, "methods": both,
            "spearman": spearman([real[m] for m in both], [twin[m] for m in both]),
            "best_real": min(both, key=lambda m: real[m]) if both else None,
            "best_twin": best_twin, "tied_with_best_twin": tied}


def judge(recs):
    """Per statistic: within +-25 %, or inside the real spread of the robot's recordings."""
    by_robot = {}
    for r in recs:
        by_robot.setdefault(r["robot"], []).append(r)
    for r in recs:
        peers = by_robot[r["robot"]]
        for key, s in r["statistics"].items():
            reals = [p["statistics"][key]["real"] for p in peers
                     if p["statistics"][key]["real"] is not None]
            s["real_spread"] = [min(reals), max(reals)] if len(reals) > 1 else None
            t = s["twin_mean"]
            s["within_25_percent"] = (t is not None and s["real"] is not None and
                                      abs(t - s["real"]) <= TOLERANCE * abs(s["real"]))
            s["inside_real_spread"] = (t is not None and s["real_spread"] is not None and
                                       s["real_spread"][0] <= t <= s["real_spread"][1])
            s["ok"] = s["within_25_percent"] or s["inside_real_spread"]
    return by_robot


def calibration_spread(by_robot):
    out = {}
    for robot, recs in by_robot.items():
        reals = [r["statistics"]["calibration_b_m"]["real"] for r in recs
                 if r["statistics"]["calibration_b_m"]["real"] is not None]
        seeds = {r["name"]: r["statistics"]["calibration_b_m"]["twin_sd"] for r in recs
                 if r["statistics"]["calibration_b_m"]["twin_sd"] is not None}
        real_sd = sd(reals) if len(reals) > 1 else None
        out[robot] = {"real_b_m": reals, "real_sd_m": real_sd, "twin_seed_sd_m": seeds,
                      "ratio_twin_over_real": {k: v / real_sd for k, v in seeds.items()}
                      if real_sd else None}
    return out


def fmt(v, digits=4):
    if v is None:
        return "-"
    if isinstance(v, bool):
        return "yes" if v else "no"
    return f"{v:.{digits}g}"


def tables(recs, spread, seeds):
    out = []
    for r in recs:
        mode = ", ".join(sorted(set(str(m) for m in r["drive_mode"])))
        out.append(f"### {r['name']} ({r['robot']})\n")
        out.append(f"Twin: {len(seeds)} seeds ({' '.join(seeds)}), drive mode {mode}, `twin` "
                   f"{min(r['twin_seconds']):.1f}-{max(r['twin_seconds']):.1f} s. "
                   f"Plot (seed {seeds[0]}): [{r['name']}.png]({r['name']}.png).\n")
        out.append("| statistic | real | twin mean (sd over seeds) | twin / real | real spread "
                   "(robot's recordings) | ok |")
        out.append("|---|---|---|---|---|---|")
        for key, s in r["statistics"].items():
            spread_cell = (f"{fmt(s['real_spread'][0])} .. {fmt(s['real_spread'][1])}"
                           if s["real_spread"] else "-")
            ok = "yes" if s["ok"] else "**no**"
            out.append(f"| {key} | {fmt(s['real'])} | {fmt(s['twin_mean'])} ({fmt(s['twin_sd'], 2)}) "
                       f"| {fmt(s['ratio'], 3)} | {spread_cell} | {ok} |")
        out.append("")
    out.append("### De-skew ranking\n")
    out.append("Real: residual median of `match --deskew M` (lower is better); twin: mean "
               "ground-truth error of `deskew --method M` on the twin, mean (sd) over the seeds; "
               "twin best with the methods within the best's sd over the seeds (tied).\n")
    out.append("| recording | real best | twin best | Spearman rho (n methods) | real residual "
               "[mm] per method | twin error [mm] per method |")
    out.append("|---|---|---|---|---|---|")
    for r in recs:
        d = r["deskew"]
        real = ", ".join(f"{m} {1e3 * d['real_residual_median_m'][m]:.1f}" for m in d["methods"])
        twin = ", ".join(f"{m} {1e3 * d['twin_truth_error_mean_m'][m]:.1f} "
                         f"({1e3 * (d['twin_truth_error_sd_m'].get(m) or 0.0):.1f})"
                         for m in d["methods"])
        best = d["best_twin"] if not d["tied_with_best_twin"] else \
            f"{d['best_twin']} (tied: {', '.join(d['tied_with_best_twin'])})"
        out.append(f"| {r['name']} | {d['best_real']} | {best} | "
                   f"{fmt(d['spearman'], 2)} ({len(d['methods'])}) | {real} | {twin} |")
    out.append("\n### Spread of the calibrated wheel base\n")
    out.append("| robot | b over its real recordings [mm] | sd real (n) | sd over twin seeds per "
               "recording [mm] | twin sd / real sd |")
    out.append("|---|---|---|---|---|")
    for robot, c in spread.items():
        reals = ", ".join(f"{1e3 * b:.1f}" for b in c["real_b_m"])
        real_sd = f"{1e3 * c['real_sd_m']:.1f} ({len(c['real_b_m'])})" if c["real_sd_m"] else \
            f"- ({len(c['real_b_m'])})"
        seeds_sd = ", ".join(f"{1e3 * v:.2f}" for v in c["twin_seed_sd_m"].values())
        ratio = ", ".join(f"{v:.2f}" for v in c["ratio_twin_over_real"].values()) \
            if c["ratio_twin_over_real"] else "-"
        out.append(f"| {robot} | {reals} | {real_sd} | {seeds_sd} | {ratio} |")
    return "\n".join(out) + "\n"


def relative_to_work(results, work):
    """The commands wrote WORK's absolute path into the JSON kept in RESULTS: name it WORK_DIR."""
    escaped = json.dumps(os.path.abspath(work).rstrip("/") + "/")[1:-1]
    for name in sorted(os.listdir(results)):
        path = os.path.join(results, name)
        if not name.endswith(".json"):
            continue
        text = open(path).read()
        if escaped in text:
            with open(path, "w") as f:
                f.write(text.replace(escaped, "WORK_DIR/"))


def main():
    work, results, seeds = sys.argv[1], sys.argv[2], sys.argv[3].split()
    relative_to_work(results, work)
    recs = []
    for line in open(os.path.join(results, "recordings.tsv")):
        name, robot = line.split("\t")[:2]
        recs.append(recording(work, results, name, robot, seeds))
    by_robot = judge(recs)
    spread = calibration_spread(by_robot)
    with open(os.path.join(results, "summary.json"), "w") as f:
        json.dump({"seeds": seeds, "recordings": recs, "calibration_spread": spread}, f, indent=1)
        f.write("\n")
    readme = os.path.join(results, "README.md")
    kept = ""
    if os.path.exists(readme):
        text = open(readme).read()
        if ANALYSIS in text:
            kept = text[text.index(ANALYSIS):]
    head = ("# twins: real recordings and their simulated twins\n\n"
            "Made by `scripts/twins.sh DATA_DIR WORK_DIR results/twins` (docs/twin.md, \"The "
            "twins suite\"); the recordings and their sources are in `recordings.tsv` and "
            "DATA_DIR/MANIFEST.md (not in the repository; paths in the JSON files are "
            "relative to WORK_DIR). Per recording and seed: "
            "`NAME.seedS.json` (`twin --compare --json`); per recording: `NAME.png` "
            "(`--plot`, first seed), `NAME.twin.json` (the first seed's twin.json); all of it "
            "in `summary.json`. A statistic is ok when the twin's mean over the seeds is within "
            "+-25 % of the real value, or inside the spread of the real values over the robot's "
            "recordings.\n\n## Tables\n\n")
    with open(readme, "w") as f:
        f.write(head + tables(recs, spread, seeds) + "\n" + (kept or ANALYSIS + "\n\n(to be "
                                                               "written from the tables)\n"))


if __name__ == "__main__":
    main()
