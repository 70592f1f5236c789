#!/usr/bin/env python3
"""Writes a scenario with N scripted vehicles for the latency scale runs (issues 11, 21, 33).

    tests/e2e/gen_scale_scenario.py N [--out FILE] [--duration S] [--full K]
                                      [--radius R] [--lanes L] [--channel ideal|range --range M]
    sudo scripts/testbed run FILE --duration 30     # then scripts/report on the run's trace

A ring road (default radius 200 m, three lanes, all one way) with the vehicles spread evenly
around it, vehicle i at angle 2π·i/N in lane i mod L. Each lane has its own speeds, and every
vehicle in a lane follows the same speed profile (so nobody runs into the car ahead: the gaps
in a lane never change): it alternates between two speeds every 6 s, which gives the CA service
all three kinds of dynamic trigger (position, speed while the speed changes, heading on the
curve) and time-triggered CAMs in between. (Where N vehicles' profiles over a long --duration
would not fit the 1 MiB sim-server passes to its clients, the period grows: 200 vehicles
alternate every 6 s for 16 minutes; 1000 every 6 s for 2 minutes, every 45 s over 18 minutes.) Lane l runs 11 + 3·l ↔ 14 + 3·l m/s, capped where
the curve's lateral acceleration would pass 3 m/s². Station ids are 3001, 3002, …;
scenario-check validates the result (docs/scenario.md). Up to 1000 vehicles; a lane whose
vehicles would stand closer than 10 m (front to front) is refused with the numbers.

`--full K`: the first K vehicles get full stations, the others `"station": {"kind": "pooled"}`
(station-host, issue 33). Default: all full, as before.
`--channel range --range M` writes `"channel": {"model": "range", "range_m": M}`; the default
writes no channel (ideal: everyone hears everyone).

Presets (issue 33):

* 300 vehicles all within range of each other — 10 full, 290 pooled on the default ring:
      gen_scale_scenario.py 300 --full 10 --lanes 4
  (radius 200 m: at most ≈ 413 m apart; ideal channel, or add `--channel range --range 1000`).
  75 vehicles a lane, 16.8 m apart in the inner lane.
* 1000 vehicles where range culling leaves about 100 within range — 10 full, 990 pooled:
      gen_scale_scenario.py 1000 --full 10 --radius 960 --lanes 4 --channel range --range 300
  For ring radius R and range r the share of the ring within range is about 2·asin(r/2R)/π:
  2·asin(300/1920)/π = 0.0999, so each station has ≈ 100 neighbours in range. 250 vehicles a
  lane, 24 m apart.
"""
import argparse
import json
import math
import sys
from pathlib import Path

RADIUS = 200.0
LANES = 3
LANE_WIDTH = 3.5
PERIOD = 6.0
MAX_LATERAL = 3.0   # m/s², the lane speeds' cap on the curve
MIN_SPACING = 10.0  # m, front to front within a lane: a car is 4.6 m long
MAX_VEHICLES = 1000
# sim-server hands the scenario text to every client in its Welcome, at most 1 MiB
# (common/wire/sim_protocol.hpp, kMaxScenarioText). The speed profiles are most of it.
MAX_TEXT = 1 << 20
PROFILE_BUDGET = 900_000  # bytes for all vehicles, leaving room for the rest


def lane_radius(radius, lanes, lane):
    # Lane 0 is the outermost (docs/scenario.md, ring).
    return radius + ((lanes - 1) / 2 - lane) * LANE_WIDTH


def lane_speeds(radius, lanes, lane):
    """(slow, fast) m/s of a lane: 11/14, 14/17, 17/20, … as before, capped on a tight curve."""
    cap = math.sqrt(MAX_LATERAL * lane_radius(radius, lanes, lane))
    lo, hi = 11.0 + 3.0 * lane, 14.0 + 3.0 * lane
    return (min(lo, cap - 3.0), min(hi, cap)) if hi > cap else (lo, hi)


def profile_period(n, duration):
    """PERIOD, or longer where N vehicles' profiles of a long run would not fit the budget: a
    vehicle's fixed keys take about 250 bytes, each profile point about 25."""
    points = max(4, (PROFILE_BUDGET // n - 250) // 25)
    return max(PERIOD, math.ceil(10 * duration / (points - 2)) / 10)


def scenario(n, duration, full, radius, lanes, channel):
    lane_length = [2 * math.pi * lane_radius(radius, lanes, lane) for lane in range(lanes)]
    per_lane = math.ceil(n / lanes)
    spacing = min(lane_length) / per_lane
    if spacing < MIN_SPACING:
        sys.exit(f"gen_scale_scenario: {n} vehicles in {lanes} lanes of a {radius} m ring stand "
                 f"{spacing:.1f} m apart (front to front; at least {MIN_SPACING} m): give a larger "
                 "--radius or more --lanes")
    period = profile_period(n, duration)
    vehicles = []
    for i in range(n):
        # Vehicle i at angle 2π i / n, in lane i mod lanes: neighbours are 25 m apart along the
        # ring at n = 50 (75 m within a lane), never side by side.
        lane = i % lanes
        lo, hi = lane_speeds(radius, lanes, lane)
        profile = []
        t = 0.0
        while t <= duration + period:
            profile.append({"t": round(t, 1), "speed": lo if int(t / period) % 2 == 0 else hi})
            t += period
        sid = 3001 + i
        v = {
            "id": f"v{sid}", "station_id": sid,
            "color": "#%02x%02x%02x" % (40 + (sid * 37) % 200, 40 + (sid * 71) % 200,
                                        40 + (sid * 13) % 200),
            "spawn": {"lane": lane, "s": round(i / n * lane_length[lane], 2), "speed": lo},
            "driver": {"type": "lane_follow", "speed_profile": profile},
        }
        if i >= full:
            v["station"] = {"kind": "pooled"}
        vehicles.append(v)
    pooled = n - min(full, n)
    what = f"{n} scripted vehicles" + (f" ({n - pooled} full, {pooled} pooled stations)"
                                       if pooled else "")
    doc = {
        "name": f"scale-{n}",
        "description": f"{what} on a {lanes}-lane ring of radius {radius:g} m for the latency "
                       "scale runs (tests/e2e/gen_scale_scenario.py).",
        "map": {"type": "ring", "lanes": lanes, "lane_width": LANE_WIDTH, "radius": radius},
        "origin": {"lat": 41.10500, "lon": 29.02300, "alt": 60},
        "duration_s": duration,
    }
    if channel:
        doc["channel"] = channel
    doc["vehicles"] = vehicles
    return doc


def dump(doc):
    """The head indented, one vehicle per line: readable, and small enough for 1000."""
    doc = dict(doc)
    vehicles = doc.pop("vehicles")
    head = json.dumps(doc, indent=1)
    lines = ",\n  ".join(json.dumps(v, separators=(",", ":")) for v in vehicles)
    return head[:-2] + ',\n "vehicles": [\n  ' + lines + "\n ]\n}\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("n", type=int)
    ap.add_argument("--out", help="file to write (default: stdout)")
    # The simulation runs from the launcher's second step, while the stations are still being
    # started (≈ 25 s for 50): the scenario must outlast start-up plus the measured window
    # (--duration of scripts/testbed), or the stations see the start-up and the stop only.
    ap.add_argument("--duration", type=float, default=120.0, help="scenario duration_s")
    ap.add_argument("--full", type=int, default=None,
                    help="the first K vehicles get full stations, the rest pooled ones "
                         "(default: all full)")
    ap.add_argument("--radius", type=float, default=RADIUS, help="ring radius, m (default 200)")
    ap.add_argument("--lanes", type=int, default=LANES, help="lanes, 1–8 (default 3)")
    ap.add_argument("--channel", choices=["ideal", "range"], default=None,
                    help="write a channel block (default: none, which is ideal)")
    ap.add_argument("--range", type=float, default=None, dest="range_m",
                    help="range_m of --channel range")
    args = ap.parse_args()
    if not 1 <= args.n <= MAX_VEHICLES:
        sys.exit(f"gen_scale_scenario: N must be 1…{MAX_VEHICLES}")
    full = args.n if args.full is None else args.full
    if not 0 <= full <= args.n:
        sys.exit(f"gen_scale_scenario: --full {args.full} must be 0…N ({args.n})")
    if not 1 <= args.lanes <= 8:
        sys.exit(f"gen_scale_scenario: --lanes {args.lanes} must be 1…8")
    if args.radius < args.lanes * LANE_WIDTH / 2 + 5:
        sys.exit(f"gen_scale_scenario: --radius {args.radius} m is too tight for "
                 f"{args.lanes} lanes (at least {args.lanes * LANE_WIDTH / 2 + 5} m)")
    channel = None
    if args.channel == "range":
        if args.range_m is None or args.range_m <= 0:
            sys.exit("gen_scale_scenario: --channel range needs --range M (metres, > 0)")
        channel = {"model": "range", "range_m": args.range_m}
    elif args.range_m is not None:
        sys.exit("gen_scale_scenario: --range goes with --channel range")
    elif args.channel == "ideal":
        channel = {"model": "ideal"}
    text = dump(scenario(args.n, args.duration, full, args.radius, args.lanes, channel))
    if len(text.encode()) > MAX_TEXT:
        sys.exit(f"gen_scale_scenario: the scenario would be {len(text.encode())} bytes, more than "
                 f"sim-server's {MAX_TEXT} (kMaxScenarioText): fewer vehicles or a shorter "
                 "--duration")
    if args.out:
        Path(args.out).write_text(text)
    else:
        sys.stdout.write(text)


if __name__ == "__main__":
    main()
