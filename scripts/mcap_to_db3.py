#!/usr/bin/env python3
"""Rewrite an MCAP file (uncompressed chunks: `slamprep export --format mcap --compression none`)
as a rosbag2 sqlite3 bag folder, stdlib only: the tables and metadata.yaml rosbag2 (Humble) writes.
Used to measure `slamprep import` on .db3 bags (docs/export.md).

usage: mcap_to_db3.py IN.mcap OUT_DIR
"""
import os
import sqlite3
import struct
import sys


def records(buf, pos, end):
    while pos + 9 <= end:
        op = buf[pos]
        (n,) = struct.unpack_from("<Q", buf, pos + 1)
        yield op, pos + 9, pos + 9 + n
        pos += 9 + n


def string(buf, pos):
    (n,) = struct.unpack_from("<I", buf, pos)
    return buf[pos + 4 : pos + 4 + n].decode(), pos + 4 + n


def main(src, out):
    buf = open(src, "rb").read()
    os.makedirs(out)
    name = os.path.basename(os.path.normpath(out))
    db = sqlite3.connect(os.path.join(out, name + "_0.db3"))
    db.executescript(
        "PRAGMA journal_mode=WAL;"
        "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,"
        " serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);"
        "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL,"
        " timestamp INTEGER NOT NULL, data BLOB NOT NULL);"
        "CREATE INDEX timestamp_idx ON messages (timestamp ASC);"
    )
    schemas, counts = {}, {}
    rows = []

    def visit(op, a, b):
        if op == 0x03:
            (sid,) = struct.unpack_from("<H", buf, a)
            schemas[sid], _ = string(buf, a + 2)
        elif op == 0x04:
            cid, sid = struct.unpack_from("<HH", buf, a)
            topic, p = string(buf, a + 4)
            enc, _ = string(buf, p)
            if cid not in counts:
                db.execute("INSERT INTO topics VALUES (?,?,?,?,'')", (cid, topic, schemas[sid], enc))
                counts[cid] = [topic, schemas[sid], 0]
        elif op == 0x05:
            cid, _, log = struct.unpack_from("<HIQ", buf, a)
            rows.append((cid, log, buf[a + 22 : b]))
            counts[cid][2] += 1
            if len(rows) >= 10000:
                db.executemany("INSERT INTO messages (topic_id, timestamp, data) VALUES (?,?,?)", rows)
                rows.clear()
        elif op == 0x06:
            (comp,), p = struct.unpack_from("<Q", buf, a + 16), a + 28
            compression, p = string(buf, p)
            assert compression == "", "export with --compression none"
            (n,) = struct.unpack_from("<Q", buf, p)
            for r in records(buf, p + 8, p + 8 + n):
                visit(*r)

    for r in records(buf, 8, len(buf) - 8):
        if r[0] == 0x0F:  # DataEnd
            break
        visit(*r)
    db.executemany("INSERT INTO messages (topic_id, timestamp, data) VALUES (?,?,?)", rows)
    db.commit()
    db.close()
    topics = "".join(
        "    - topic_metadata:\n        name: %s\n        type: %s\n        serialization_format: cdr\n"
        '        offered_qos_profiles: ""\n      message_count: %d\n' % (t, ty, n)
        for t, ty, n in counts.values()
    )
    with open(os.path.join(out, "metadata.yaml"), "w") as f:
        f.write(
            "rosbag2_bagfile_information:\n  version: 4\n  storage_identifier: sqlite3\n"
            "  relative_file_paths:\n    - %s_0.db3\n  topics_with_message_count:\n%s"
            '  compression_format: ""\n  compression_mode: ""\n' % (name, topics)
        )


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
