#!/usr/bin/env python3
"""How far a benchmark log's relations sit from its own odometry, relation by relation.

    python3 scripts/relation_steps.py RELATIONS TRAJECTORY.tum [--max-dt 5]

TRAJECTORY is the log's odometry at its scan stamps (`slamprep import --format carmen LOG
--odometry laser --out D` then `slamprep export D --format tum --out T`: T/odom_nominal.tum).
For every relation shorter than --max-dt seconds whose two stamps are in the trajectory, the
translation difference |odometry motion - relation| is rounded to 0.1 mm and counted. A
relation file made by correcting the odometry on a grid shows as differences that are exactly
0 or the lengths of grid steps (results/real/README.md: ACES 5 cm, Intel 1 cm); a continuous
correction shows no such peaks (fr079).
"""
import argparse
import collections
import math


def read_tum(path):
    poses = {}
    with open(path) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            t, x, y, _z, _qx, _qy, qz, qw = map(float, line.split()[:8])
            poses[round(t, 6)] = (x, y, 2.0 * math.atan2(qz, qw))
    return poses


def motion(a, b):
    """b in the frame of a (translation only)."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    c, s = math.cos(a[2]), math.sin(a[2])
    return c * dx + s * dy, -s * dx + c * dy


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("relations")
    parser.add_argument("trajectory")
    parser.add_argument("--max-dt", type=float, default=5.0)
    args = parser.parse_args()
    poses = read_tum(args.trajectory)
    steps = collections.Counter()
    with open(args.relations) as f:
        for line in f:
            fields = line.split()
            if len(fields) < 8 or line.startswith("#"):
                continue
            t1, t2, rx, ry = map(float, fields[:4])
            a, b = poses.get(round(t1, 6)), poses.get(round(t2, 6))
            if abs(t2 - t1) >= args.max_dt or a is None or b is None:
                continue
            ex, ey = motion(a, b)
            steps[round(math.hypot(ex - rx, ey - ry), 4)] += 1
    total = sum(steps.values())
    print(f"{total} relations under {args.max_dt:g} s; most frequent |odometry - relation| [m]:")
    for d, n in steps.most_common(8):
        print(f"  {d:.4f}: {n}")
    for grid in (0.01, 0.05):
        on = sum(n for d, n in steps.items() if on_grid(d, grid))
        print(f"within 0.5 mm of 0 or of a {100 * grid:g} cm grid step "
              f"({grid:g} * sqrt(i^2 + j^2)): {on} ({100.0 * on / max(total, 1):.1f} %)")


def on_grid(d, grid, tolerance=5e-4):
    """d is the length of a step of whole grid cells, to the tolerance."""
    reach = int(d / grid) + 2
    return any(abs(d - grid * math.hypot(i, j)) <= tolerance
               for i in range(reach) for j in range(reach))

if __name__ == "__main__":
    main()
