#!/usr/bin/env python3
"""Seeds of its_signal_rx_fuzz (signal_rx_fuzz.cpp): the MAPEM and SPATEM corpora of the codec's
fuzzers (tests/fuzz/mapem, tests/fuzz/spatem) wrapped into the target's records, with a car's
fixes approaching the reference point from the south and the clock moving on between them.

Run from the repository root: its-station/apps/tests/signal_rx_fuzz_seeds.py
"""
import pathlib
import struct

root = pathlib.Path(".")
out = root / "tests/fuzz/signal_rx"
out.mkdir(parents=True, exist_ok=True)


def msg(kind, payload):
    return bytes([kind]) + struct.pack("<H", len(payload)) + payload


def fix(east_dm, north_dm, heading_cdeg, speed_q):
    return bytes([2]) + struct.pack("<hhHB", east_dm, north_dm, heading_cdeg, speed_q)


def tick(steps):
    return bytes([3, steps])


mapems = sorted((root / "tests/fuzz/mapem").glob("*.uper"))
spatems = sorted((root / "tests/fuzz/spatem").glob("*.uper"))
for m in mapems:
    for s in spatems:
        data = msg(0, m.read_bytes()) + msg(1, s.read_bytes())
        # 60 km/h (16.75 m/s as 67 quarters) northbound on the lane 1.75 m east of the centre
        for i in range(20):
            data += fix(17, -1500 + i * 17, 0, 67) + tick(10)
            if i % 5 == 0:
                data += msg(1, s.read_bytes())
        name = f"{m.stem}__{s.stem}"
        (out / name).write_bytes(data)
print(f"{len(mapems) * len(spatems)} seeds in {out}")
