#!/usr/bin/env python3
"""Writes a scenario with N scripted vehicles for the latency scale runs (issue 11).

    tests/e2e/gen_scale_scenario.py N [--out FILE] [--duration S]
    sudo scripts/testbed run FILE --duration 30     # then scripts/report on the run's trace

A ring road (radius 200 m, three lanes, all one way) with the vehicles spread evenly over the
lanes. Each lane has its own speed, and every vehicle in a lane follows the same speed profile
(so nobody runs into the car ahead): it alternates between two speeds every 6 s, which gives the
CA service all three kinds of dynamic trigger (position, speed while the speed changes, heading
on the curve) and time-triggered CAMs in between. Station ids are 3001, 3002, …; scenario-check
validates the result (docs/scenario.md).
"""
import argparse
import json
import math
import sys
from pathlib import Path

RADIUS = 200.0
LANES = 3
LANE_SPEEDS = [(11.0, 14.0), (14.0, 17.0), (17.0, 20.0)]  # m/s, alternating every PERIOD
PERIOD = 6.0


def scenario(n, duration):
    lane_length = [2 * math.pi * (RADIUS + (1 - lane) * 3.5) for lane in range(LANES)]
    vehicles = []
    for i in range(n):
        # Vehicle i at angle 2π i / n, in lane i mod 3: neighbours are 25 m apart along the ring
        # at n = 50 (75 m within a lane), never side by side.
        lane = i % LANES
        lo, hi = LANE_SPEEDS[lane]
        profile = []
        t = 0.0
        while t <= duration + PERIOD:
            profile.append({"t": round(t, 1), "speed": lo if int(t / PERIOD) % 2 == 0 else hi})
            t += PERIOD
        sid = 3001 + i
        vehicles.append({
            "id": f"v{sid}", "station_id": sid,
            "color": "#%02x%02x%02x" % (40 + (sid * 37) % 200, 40 + (sid * 71) % 200,
                                        40 + (sid * 13) % 200),
            "spawn": {"lane": lane, "s": round(i / n * lane_length[lane], 2), "speed": lo},
            "driver": {"type": "lane_follow", "speed_profile": profile},
        })
    return {
        "name": f"scale-{n}",
        "description": f"{n} scripted vehicles on a three-lane ring for the latency scale runs "
                       "(tests/e2e/gen_scale_scenario.py).",
        "map": {"type": "ring", "lanes": LANES, "lane_width": 3.5, "radius": RADIUS},
        "origin": {"lat": 41.10500, "lon": 29.02300, "alt": 60},
        "duration_s": duration,
        "vehicles": vehicles,
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("n", type=int)
    ap.add_argument("--out", help="file to write (default: stdout)")
    # The simulation runs from the launcher's second step, while the stations are still being
    # started (≈ 25 s for 50): the scenario must outlast start-up plus the measured window
    # (--duration of scripts/testbed), or the stations see the start-up and the stop only.
    ap.add_argument("--duration", type=float, default=120.0, help="scenario duration_s")
    args = ap.parse_args()
    if not 1 <= args.n <= 200:
        sys.exit("gen_scale_scenario: N must be 1…200")
    text = json.dumps(scenario(args.n, args.duration), indent=1) + "\n"
    if args.out:
        Path(args.out).write_text(text)
    else:
        sys.stdout.write(text)


if __name__ == "__main__":
    main()
