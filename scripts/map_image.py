#!/usr/bin/env python3
"""A dataset's scans placed by a trajectory, drawn as a grey PNG: the map a matcher builds.

    python3 scripts/map_image.py DATASET TRAJECTORY.tum OUT.png [RESOLUTION_M]

Every scan whose first-beam stamp is in TRAJECTORY (e.g. `slamprep match --trajectory`) is put
at that base pose through the dataset's lidar mount; each return up to 25 m darkens its cell.
Walls that come out double or fanned are the matcher's drift. Standard library only.
"""
import json
import math
import struct
import sys
import zlib


def poses(tum):
    out = {}
    for line in open(tum):
        if line.startswith("#") or not line.strip():
            continue
        t, x, y, _, qx, qy, qz, qw = map(float, line.split())
        out[round(t, 6)] = (x, y, 2 * math.atan2(qz, qw))
    return out


def points(dataset, trajectory):
    mount = json.load(open(dataset + "/dataset.json"))["lidar_mount"]
    for line in open(dataset + "/scans.jsonl"):
        scan = json.loads(line)
        pose = trajectory.get(round(scan["stamp_s"], 6))
        if pose is None:
            continue
        x, y, th = pose
        lx = x + math.cos(th) * mount["x"] - math.sin(th) * mount["y"]
        ly = y + math.sin(th) * mount["x"] + math.cos(th) * mount["y"]
        for i, r in enumerate(scan["readings"]):
            if r is None or not 0.05 < r <= 25.0:
                continue
            a = th + mount["yaw"] + scan["angle_min"] + i * scan["angle_increment"]
            yield lx + r * math.cos(a), ly + r * math.sin(a)


def png(rows, width, height):
    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    raw = b"".join(b"\x00" + bytes(row) for row in rows)
    header = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)  # 8-bit grey
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw, 9))
            + chunk(b"IEND", b""))


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    dataset, tum, out = sys.argv[1:4]
    res = float(sys.argv[4]) if len(sys.argv) > 4 else 0.1
    pts = list(points(dataset, poses(tum)))
    x0, y0 = min(p[0] for p in pts), min(p[1] for p in pts)
    width = int((max(p[0] for p in pts) - x0) / res) + 1
    height = int((max(p[1] for p in pts) - y0) / res) + 1
    rows = [[255] * width for _ in range(height)]
    for x, y in pts:
        row, col = height - 1 - int((y - y0) / res), int((x - x0) / res)
        rows[row][col] = max(0, rows[row][col] - 60)
    open(out, "wb").write(png(rows, width, height))
    print(f"{out}: {width} x {height} cells of {res} m, {len(pts)} returns")


if __name__ == "__main__":
    main()
