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
import random
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


# Figures closer than this are one value (method pairs that de-skew alike, e.g. odom-icp falling
# back to odom-linear, differ by the summation order only).
TIE_M = 1e-9


def ranks(values):
    """Ranks from 0; values within TIE_M of their neighbour share their mean rank."""
    order = sorted(range(len(values)), key=lambda i: values[i])
    out = [0.0] * len(values)
    start = 0
    for end in range(1, len(order) + 1):
        if end == len(order) or values[order[end]] - values[order[end - 1]] > TIE_M:
            for i in order[start:end]:
                out[i] = (start + end - 1) / 2
            start = end
    return out


def spearman(a, b):
    """Rank correlation of two equally long lists: Pearson's r of their ranks (ties share)."""
    if len(a) < 3:
        return None
    ra, rb = ranks(a), ranks(b)
    ma, mb = statistics.mean(ra), statistics.mean(rb)
    cov = sum((x - ma) * (y - mb) for x, y in zip(ra, rb))
    var = math.sqrt(sum((x - ma) ** 2 for x in ra) * sum((y - mb) ** 2 for y in rb))
    return cov / var if var > 0 else None


# Which orderings the data resolve. Real: a moving-block bootstrap of the difference of two
# methods' per-scan residual medians over the scans both matched (consecutive scans' residuals
# are correlated, so blocks of BLOCK_SCANS scans are drawn, RESAMPLES times, with a fixed seed);
# resolved where the 95 % interval excludes 0. Twin: the per-seed differences of the truth
# errors, resolved where their mean exceeds T_975 standard errors (Student's t, n - 1 dof).
BLOCK_SCANS = 20
RESAMPLES = 1000
T_975 = {1: 12.71, 2: 4.30, 3: 3.18, 4: 2.78, 5: 2.57, 6: 2.45, 7: 2.36, 8: 2.31, 9: 2.26}


def scan_residuals(path):
    """{stamp: rms_m} of the accepted matches of `match --out` (None when not written)."""
    if not os.path.exists(path):
        return None
    out = {}
    for line in open(path):
        j = json.loads(line)
        if not j.get("fallback") and j.get("converged"):
            out[j["stamp_cur"]] = j["rms_m"]
    return out


def real_order(a, b, rng):
    """-1 / +1 where method a's residual median is resolved below / above b's, else 0."""
    stamps = sorted(set(a) & set(b))
    if len(stamps) < 2 * BLOCK_SCANS:
        return 0
    xa, xb = [a[t] for t in stamps], [b[t] for t in stamps]
    n, blocks = len(stamps), -(-len(stamps) // BLOCK_SCANS)
    diffs = []
    for _ in range(RESAMPLES):
        starts = [rng.randrange(n - BLOCK_SCANS + 1) for _ in range(blocks)]
        idx = [i for s0 in starts for i in range(s0, s0 + BLOCK_SCANS)]
        diffs.append(statistics.median(xa[i] for i in idx) - statistics.median(xb[i] for i in idx))
    diffs.sort()
    lo, hi = diffs[int(0.025 * RESAMPLES)], diffs[int(0.975 * RESAMPLES) - 1]
    return -1 if hi < 0 else 1 if lo > 0 else 0


def twin_order(ea, eb):
    """-1 / +1 where a's truth error is resolved below / above b's over the seeds, else 0."""
    d = [x - y for x, y in zip(ea, eb)]
    if len(d) < 2:
        return 0
    mean, se = statistics.mean(d), statistics.stdev(d) / math.sqrt(len(d))
    if abs(mean) <= T_975.get(len(d) - 1, 2.0) * se:
        return 0
    return -1 if mean < 0 else 1


def resolved_pairs(work, name, methods, twin_per_seed):
    """The method pairs the recording orders, and what the twin says of each."""
    real = {m: scan_residuals(os.path.join(work, f"{name}.match.{m}.jsonl")) for m in methods}
    if any(v is None for v in real.values()):
        return None
    rng = random.Random(0)
    out = {"pairs": 0, "real_resolved": 0, "agree": 0, "contradict": 0, "twin_unresolved": 0,
           "contradicted": []}
    for i, a in enumerate(methods):
        for b in methods[i + 1:]:
            out["pairs"] += 1
            r = real_order(real[a], real[b], rng)
            if r == 0:
                continue
            out["real_resolved"] += 1
            t = twin_order(twin_per_seed[a], twin_per_seed[b])
            if t == r:
                out["agree"] += 1
            elif t == 0:
                out["twin_unresolved"] += 1
            else:
                out["contradict"] += 1
                out["contradicted"].append(f"{a} {'<' if r < 0 else '>'} {b}")
    return out


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


def over_seeds(per_seed, seeds):
    """{method: [value per seed]} -> means and sds of the methods every seed has."""
    full = {m: v for m, v in per_seed.items() if len(v) == len(seeds)}
    return ({m: statistics.mean(v) for m, v in full.items()}, {m: sd(v) for m, v in full.items()})


def residual_median(path):
    """`match --deskew M --json`'s residual median; None when M refused every scan (matched as
    measured: no figure of its own) or nothing matched."""
    j = load(path)
    if j and j.get("residual_rms_m") and j["deskew_refused"] < j["scans"]:
        return j["residual_rms_m"]["median"]
    return None


def best_and_tied(methods, mean, spread):
    """The lowest, and the methods within its sd over the seeds (the twin cannot tell them)."""
    if not methods:
        return None, []
    best = min(methods, key=lambda m: mean[m])
    return best, [m for m in methods if m != best and
                  mean[m] - mean[best] <= (spread.get(best) or 0.0)]


def twin_figures(work, name, seeds):
    """Per method over the seeds: the truth error over the scans kept (mean_m), over every
    scan with the refused ones as measured (fallback_mean_m), and match's residual median;
    and the per-seed fallback_mean_m lists themselves."""
    kept, fallback, residual = {}, {}, {}
    for seed in seeds:
        for row in load(os.path.join(work, f"{name}.seed{seed}.deskew.json")) or []:
            m = row["method"]
            if (m in DESKEW or m == "oracle") and row.get("ok"):
                kept.setdefault(m, []).append(row["mean_m"])
                if row.get("fallback_mean_m") is not None:
                    fallback.setdefault(m, []).append(row["fallback_mean_m"])
        for m in DESKEW:
            r = residual_median(os.path.join(work, f"{name}.twin.{seed}.match.{m}.json"))
            if r is not None:
                residual.setdefault(m, []).append(r)
    return (over_seeds(kept, seeds), over_seeds(fallback, seeds), over_seeds(residual, seeds),
            {m: v for m, v in fallback.items() if len(v) == len(seeds)})


def deskew(work, name, seeds):
    real = {}
    for m in DESKEW:
        r = residual_median(os.path.join(work, f"{name}.match.{m}.json"))
        if r is not None:
            real[m] = r
    (kept, kept_sd), (twin, twin_sd), (resid, resid_sd), per_seed = twin_figures(work, name, seeds)
    # The oracle de-skews with the truth at the scans' stamps: what the twin's clock offset (the
    # recording's scan delay) alone costs. Not ranked (the recording has no truth).
    oracle = twin.pop("oracle", None)
    twin_sd.pop("oracle", None), kept.pop("oracle", None), kept_sd.pop("oracle", None)
    both = [m for m in DESKEW if m in real and m in twin]
    best_twin, tied = best_and_tied(both, twin, twin_sd)
    best_kept, tied_kept = best_and_tied([m for m in both if m in kept], kept, kept_sd)
    # Can the residual rank at all? On the twin, where the truth is known.
    on_twin = [m for m in DESKEW if m in resid and m in twin]
    best_resid, tied_resid = best_and_tied(on_twin, resid, resid_sd)
    best_truth, tied_truth = best_and_tied(on_twin, twin, twin_sd)
    same = [m for m in on_twin if m in real]
    return {"real_residual_median_m": real,
            "twin_truth_error_mean_m": twin, "twin_truth_error_sd_m": twin_sd,
            "twin_kept_scans_error_mean_m": kept, "twin_kept_scans_error_sd_m": kept_sd,
            "methods": both,
            "spearman": spearman([real[m] for m in both], [twin[m] for m in both]),
            "best_real": min(both, key=lambda m: real[m]) if both else None,
            "best_twin": best_twin, "tied_with_best_twin": tied,
            "spearman_kept_scans": spearman([real[m] for m in both if m in kept],
                                            [kept[m] for m in both if m in kept]),
            "best_twin_kept_scans": best_kept, "tied_with_best_twin_kept_scans": tied_kept,
            "twin_residual_median_m": resid, "twin_residual_median_sd_m": resid_sd,
            "twin_oracle_error_mean_m": oracle,
            "twin_residual_methods": on_twin,
            "twin_residual_seeds": len(seeds) if resid else 0,
            "best_twin_residual": best_resid, "tied_with_best_twin_residual": tied_resid,
            "best_twin_truth_of_residual_methods": best_truth,
            "tied_with_best_twin_truth_of_residual_methods": tied_truth,
            "spearman_twin_residual_vs_truth": spearman([resid[m] for m in on_twin],
                                                        [twin[m] for m in on_twin]),
            "spearman_twin_residual_vs_real_residual": spearman([resid[m] for m in same],
                                                                [real[m] for m in same]),
            "resolved_pairs": resolved_pairs(work, name, both, per_seed)}


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


def mm(v):
    return "-" if v is None else f"{1e3 * v:.1f}"


def with_ties(best, tied):
    if best is None:
        return "-"
    return best if not tied else f"{best} (tied: {', '.join(tied)})"


def per_method(methods, mean, spread):
    """"m 12.3 (0.4), ..." in mm: mean (sd over the seeds)."""
    return ", ".join(f"{m} {1e3 * mean[m]:.1f} ({1e3 * (spread.get(m) or 0.0):.1f})"
                     for m in methods if m in mean)


def residual_and_truth(d):
    """"m 25.3 (0.3) / 37.2, ..." in mm: the twin's residual (sd over the seeds) / its error."""
    res, res_sd, truth = (d["twin_residual_median_m"], d["twin_residual_median_sd_m"],
                          d["twin_truth_error_mean_m"])
    return ", ".join(f"{m} {1e3 * res[m]:.1f} ({1e3 * res_sd[m]:.1f}) / {1e3 * truth[m]:.1f}"
                     for m in d["twin_residual_methods"])


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
    out.append("Real: residual median of `match --deskew M --sync auto` (lower is better); twin: "
               "ground-truth error of `deskew --method M --sync auto` on the twin over every scan "
               "(the wheels moved onto the scans' clock where they lag), a scan M refused counted "
               "as measured as `match` keeps it (`fallback_mean_m`), mean (sd) over the seeds; "
               "twin best with the methods within the best's sd over the seeds (tied). Before: "
               "the same over the scans M kept (`mean_m`), which differ by method.\n")
    out.append("| recording | real best | twin best | Spearman rho (n methods) | before: twin "
               "best, rho | real residual [mm] per method | twin error [mm] per method, all "
               "scans | before: twin error [mm], scans kept |")
    out.append("|---|---|---|---|---|---|---|---|")
    for r in recs:
        d = r["deskew"]
        real = ", ".join(f"{m} {1e3 * d['real_residual_median_m'][m]:.1f}" for m in d["methods"])
        out.append(f"| {r['name']} | {d['best_real']} | "
                   f"{with_ties(d['best_twin'], d['tied_with_best_twin'])} | "
                   f"{fmt(d['spearman'], 2)} ({len(d['methods'])}) | "
                   f"{with_ties(d['best_twin_kept_scans'], d['tied_with_best_twin_kept_scans'])}, "
                   f"{fmt(d['spearman_kept_scans'], 2)} | {real} | "
                   f"{per_method(d['methods'], d['twin_truth_error_mean_m'], d['twin_truth_error_sd_m'])} | "
                   f"{per_method(d['methods'], d['twin_kept_scans_error_mean_m'], d['twin_kept_scans_error_sd_m'])} |")
    out.append("\nThe orderings the recording resolves: of the method pairs, those whose residual "
               "medians differ beyond a moving-block bootstrap's 95 % interval (blocks of "
               f"{BLOCK_SCANS} scans, {RESAMPLES} resamples, the scans both methods matched), and "
               "whether the twin orders them the same way (its per-seed truth errors differing "
               "beyond Student's t at 95 %), the other way, or cannot tell.\n")
    out.append("| recording | pairs | resolved by the recording | twin agrees | twin contradicts "
               "| twin cannot tell | contradicted |")
    out.append("|---|---|---|---|---|---|---|")
    for r in recs:
        p = r["deskew"].get("resolved_pairs")
        if not p:
            out.append(f"| {r['name']} | - | no per-scan residuals | | | | |")
            continue
        out.append(f"| {r['name']} | {p['pairs']} | {p['real_resolved']} | {p['agree']} | "
                   f"{p['contradict']} | {p['twin_unresolved']} | "
                   f"{'; '.join(p['contradicted']) or '-'} |")
    out.append("\n### Can the residual rank de-skew methods? (on the twins)\n")
    out.append("On each twin, `match --deskew M --sync auto` as on the recording: methods ranked "
               "by the same "
               "residual median, mean (sd) over the seeds, against the twin's ground-truth "
               "ranking (all scans, above). A rho near 1 says the residual finds the better "
               "de-skew where the truth is known; the last rho compares the twin's residual "
               "ranking with the recording's. Oracle: the error of de-skewing with the truth at "
               "the scans' stamps, what the twin's clock offset (the recording's scan delay "
               "behind the wheels) alone costs.\n")
    out.append("| recording | seeds | best by residual | best by truth | rho residual vs truth "
               "(n methods) | rho twin vs real residual | oracle error [mm] | twin residual (sd) "
               "/ error [mm] per method |")
    out.append("|---|---|---|---|---|---|---|---|")
    for r in recs:
        d = r["deskew"]
        on_twin = d["twin_residual_methods"]
        best_truth = with_ties(d["best_twin_truth_of_residual_methods"],
                               d["tied_with_best_twin_truth_of_residual_methods"])
        out.append(f"| {r['name']} | {d['twin_residual_seeds']} | "
                   f"{with_ties(d['best_twin_residual'], d['tied_with_best_twin_residual'])} | "
                   f"{best_truth} | {fmt(d['spearman_twin_residual_vs_truth'], 2)} "
                   f"({len(on_twin)}) | {fmt(d['spearman_twin_residual_vs_real_residual'], 2)} | "
                   f"{mm(d['twin_oracle_error_mean_m'])} | "
                   f"{residual_and_truth(d)} |")
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
