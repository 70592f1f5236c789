#!/usr/bin/env python3
"""Writes the seed corpus of its_signal_app_fuzz (tests/fuzz/signal_app): intersections, SPAT
groups and approaches in the target's input format (signal_app_fuzz.cpp)."""
import math
import pathlib
import struct
import sys

OUT = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "tests/fuzz/signal_app")


def lane(lane_id, flags, width_dm, nodes, connections, limit=None):
    b = struct.pack("<BBB", lane_id, flags, width_dm)
    if flags & 4:
        b += struct.pack("<B", limit)
    b += struct.pack("<B", len(nodes))
    for x, y in nodes:
        b += struct.pack("<hh", int(round(x * 10)), int(round(y * 10)))
    b += struct.pack("<B", len(connections))
    for to, group in connections:
        b += struct.pack("<BB", to, group)
    return b


def header(lanes, intersection=1, revision=1, limit=0):
    return struct.pack("<HBBB", intersection, revision, limit, len(lanes)) + b"".join(lanes)


def groups(entries):
    """entries: [(group, [(state, {start, min, max, likely: ds})])]"""
    b = struct.pack("<B", len(entries))
    for group, events in entries:
        b += struct.pack("<BB", group, len(events) - 1)
        for state, times in events:
            which = sum(1 << i for i, k in enumerate(("start", "min", "max", "likely")) if k in times)
            b += struct.pack("<BB", state, which)
            for k in ("start", "min", "max", "likely"):
                if k in times:
                    b += struct.pack("<h", times[k])
    return b


def fixes(points):
    """points: [(x, y, heading_deg, speed_mps, age_ms, step_ms)]"""
    b = b""
    for x, y, h, v, age, step in points:
        b += struct.pack("<hhHBBB", int(round(x * 10)), int(round(y * 10)), int(h * 100) % 36000,
                         min(255, int(v * 4)), age // 10, step // 10)
    return b


def straight(x, y0, y1, n=6):
    return [(x, y0 + (y1 - y0) * i / (n - 1)) for i in range(n)]


def south_arm():
    return [lane(1, 1 | 4, 35, straight(1.75, -12, -212), [(23, 1), (33, 1)], limit=56),
            lane(2, 1, 35, straight(5.25, -12, -212), [(24, 1)]),
            lane(3, 2, 35, straight(-1.75, -12, -212), []),
            lane(23, 2, 35, straight(1.75, 12, 212), []),
            lane(33, 2, 35, [(-12, 1.75), (-212, 1.75)], [])]


def approach(v, d0, n, x=1.75, heading=0.0):
    return fixes([(x, -12 - (d0 - v * 0.1 * k), heading, v, 0, 100) for k in range(n)])


def main():
    OUT.mkdir(parents=True, exist_ok=True)
    amber_then_red = groups([(1, [(6, {"likely": 20, "min": 20, "max": 20}),
                                  (8, {"likely": 50}), (3, {"likely": 350})]),
                             (2, [(3, {})])])
    seeds = {
        "approach_60_turning_red": header(south_arm()) + amber_then_red + approach(16.7, 120, 80),
        "approach_30_red": header(south_arm()) + groups([(1, [(3, {"max": 80, "min": 40})])]) +
        approach(8.3, 60, 80),
        "glosa_green_window": header(south_arm(), limit=200) +
        groups([(1, [(3, {"likely": 100}), (6, {"likely": 300})])]) + approach(10, 200, 40),
        "lane_change": header(south_arm()) + groups([(1, [(6, {})])]) +
        fixes([(1.75 + 0.2 * k, -120 + k, 5, 10, 0, 100) for k in range(30)]),
        "curve": header([lane(1, 1, 35, [(-30 + 30 * math.cos(math.radians(a)),
                                          -30 * math.sin(math.radians(a))) for a in range(0, 91, 6)],
                              [(2, 7)]),
                         lane(2, 2, 35, [(0, 12), (0, 100)], [])]) +
        groups([(7, [(8, {"start": -10, "likely": 20})])]) +
        fixes([(-30 + 30 * math.cos(math.radians(a)), -30 * math.sin(math.radians(a)), a, 8, 50, 100)
               for a in range(88, -10, -3)]),
        "broken_lanes": header([lane(1, 1, 0, straight(0, 0, -50), [(2, 255)]),
                                lane(1, 1, 35, [(0, 0)], []),
                                lane(4, 1 | 0x40 | 0x80, 35, [(3100, 3100), (0, -20)], [])]) +
        groups([(1, [(11, {})])]) + approach(10, 30, 10),
        "reversed_and_standing": header(south_arm()) + groups([(1, [(3, {"likely": 30})])]) +
        fixes([(1.75, -40, 180, 5, 0, 100)] * 5 + [(1.75, -13, 0, 0, 0, 100)] * 5),
    }
    for name, data in seeds.items():
        (OUT / name).write_bytes(data)


if __name__ == "__main__":
    main()
