#!/usr/bin/env python3
"""Writes town.xodr: a town-sized map for the 3D view's figures and town-wide scenarios.

A 5 x 5 grid of junctions 120 m apart (25 junctions: 9 crossroads, 12 T-junctions, 4 corners,
each with every turn its arms allow), joined by two-lane streets with sidewalks (40 streets and
188 connecting roads, 228 roads in all). Every lane leads on, so random routes never end. Along
the streets: street lamps, trees, houses (boxes with length, width and height), a park with a
hedge in the middle block, speed-limit signs; at every junction arm a stop line (DE 294 signal)
across the lane towards the junction and a zebra crossing (crosswalk object).

Usage: generate_town.py [--out DIR] [--check]. --check compares with DIR/town.xodr (default:
this folder) and exits 1 if it differs, so that a test keeps it in step. The street geometry
and the file format come from generate.py; the objects' sizes and places from a fixed seed.
"""

import argparse
import math
import random
import sys
from pathlib import Path

sys.dont_write_bytecode = True  # no __pycache__ beside the maps when a test runs this
from generate import (LANE, Lane, PlanView, Road, Section, document, object_xml,  # noqa: E402
                      signal_xml)

GRID = 5             # junctions per side
BLOCK = 120.0        # m between junction centres
HALF = 12.0          # m from a junction's centre to where its arms start
SIDEWALK = 2.0       # m
STOP_LINE_S = 4.5    # m from the junction: stop line across the lane towards it
CROSSWALK_S = 2.0    # m from the junction: the middle of a 3 m zebra crossing
SEED = 32

# Directions of a junction's arms: east, north, west, south.
DIRS = [(1, 0), (0, 1), (-1, 0), (0, -1)]


def junction_id(i, j):
    return str(1000 + 10 * i + j)


def centre(i, j):
    return i * BLOCK, j * BLOCK


def street_items(rid, length, rng, park):
    """Objects and signals of one street (from junction A at s = 0 to junction B at its end):
    lamps both sides, trees or a hedge on one, houses behind the sidewalks, speed limits, and at
    both ends a stop line and a zebra crossing."""
    edge = LANE + SIDEWALK  # the outer edge of the sidewalk
    objects, signals = [], []
    objects += object_xml(f"{rid}01", "pole", 0.0, 0.0, radius=0.12, height=6.0,
                          name="street lamp", repeat=(8.0, length - 16.0, 20.0, edge + 0.5,
                                                      edge + 0.5))
    objects += object_xml(f"{rid}02", "pole", 0.0, 0.0, radius=0.12, height=6.0,
                          name="street lamp", repeat=(18.0, length - 36.0, 20.0, -edge - 0.5,
                                                      -edge - 0.5))
    if park:
        objects += object_xml(f"{rid}03", "vegetation", 0.0, 0.0, width=1.0, height=1.4,
                              name="hedge", repeat=(10.0, length - 20.0, 0.0, -edge - 1.5,
                                                    -edge - 1.5))
        for k in range(6):
            s = 14.0 + k * (length - 28.0) / 5
            objects += object_xml(f"{rid}{10 + k}", "tree", s, -edge - 8.0 - 4.0 * (k % 2),
                                  radius=2.5 + rng.random(), height=7.0 + 3.0 * rng.random(),
                                  name="tree")
    else:
        objects += object_xml(f"{rid}03", "tree", 0.0, 0.0, radius=1.8, height=7.0,
                              name="tree", repeat=(12.0, length - 24.0, 24.0, -edge - 2.0,
                                                   -edge - 2.0))
    # Houses behind both sidewalks, 12 m deep, 9 to 11 m apart along the street; none in the
    # park (right side of a park street).
    for side in (1, -1):
        if park and side == -1:
            continue
        s, k = 10.0, 0
        while True:
            size = 12.0 + 8.0 * rng.random()
            if s + size > length - 10.0:
                break
            depth = 12.0
            t = side * (edge + 3.5 + depth / 2)
            objects += object_xml(f"{rid}{30 + k + (0 if side > 0 else 20)}", "building",
                                  s + size / 2, t, length=size, width=depth,
                                  height=6.0 + 18.0 * rng.random() ** 2, name="house")
            s += size + 2.0 + 3.0 * rng.random()
            k += 1
    # Speed limit (DE 274-55, 50 km/h) for both directions near the start of each.
    signals += signal_xml(f"{rid}74", 15.0, -edge - 0.3, "+", "274", width=0.6, height=0.6,
                          z_offset=2.0, name="speed limit", subtype="55", value=50)
    signals += signal_xml(f"{rid}75", length - 15.0, edge + 0.3, "-", "274", width=0.6,
                          height=0.6, z_offset=2.0, name="speed limit", subtype="55", value=50)
    # Junction marks at both ends: lane 1 drives towards the start, lane -1 towards the end.
    signals += signal_xml(f"{rid}91", STOP_LINE_S, LANE / 2, "-", "294", width=LANE,
                          name="stop line")
    signals += signal_xml(f"{rid}92", length - STOP_LINE_S, -LANE / 2, "+", "294", width=LANE,
                          name="stop line")
    objects += object_xml(f"{rid}93", "crosswalk", CROSSWALK_S, 0.0, length=3.0,
                          width=2 * LANE, name="zebra crossing")
    objects += object_xml(f"{rid}94", "crosswalk", length - CROSSWALK_S, 0.0, length=3.0,
                          width=2 * LANE, name="zebra crossing")
    return objects, signals


def town():
    rng = random.Random(SEED)
    roads = []
    # arms[(i, j)][d] = (street id, contact at this junction: "start" or "end")
    arms = {(i, j): {} for i in range(GRID) for j in range(GRID)}
    rid = 1
    for i in range(GRID):
        for j in range(GRID):
            for d in (0, 1):  # east and north: each street once, from (i, j) to its neighbour
                dx, dy = DIRS[d]
                ni, nj = i + dx, j + dy
                if ni >= GRID or nj >= GRID:
                    continue
                cx, cy = centre(i, j)
                phi = math.atan2(dy, dx)
                plan = PlanView(cx + HALF * dx, cy + HALF * dy, phi).line(BLOCK - 2 * HALF)
                sid = str(rid)
                rid += 1
                lanes = Section(0.0,
                                left=[Lane(1), Lane(2, "sidewalk", SIDEWALK, mark="none")],
                                right=[Lane(-1), Lane(-2, "sidewalk", SIDEWALK, mark="none")],
                                centre_mark="broken")
                park = (i, j, d) == (2, 2, 0)  # the street along the middle block's south side
                objects, signals = street_items(sid, plan.s, rng, park)
                roads.append(Road(sid, plan, [lanes], pred=("junction", junction_id(i, j), None),
                                  succ=("junction", junction_id(ni, nj), None), speed=50,
                                  name=f"street {sid}", objects=objects, signals=signals))
                arms[(i, j)][d] = (sid, "start")
                arms[(ni, nj)][(d + 2) % 4] = (sid, "end")
    junctions = []
    cid = 2000
    for (i, j), here in sorted(arms.items()):
        cx, cy = centre(i, j)
        connections = []
        for d_in, (street_in, end_in) in sorted(here.items()):
            # The lane towards this junction: lane 1 if the street starts here, else -1.
            lane_in = 1 if end_in == "start" else -1
            phi = math.atan2(DIRS[d_in][1], DIRS[d_in][0])
            for turn, d_out in ((-1, (d_in + 1) % 4), (0, (d_in + 2) % 4), (1, (d_in + 3) % 4)):
                if d_out not in here:
                    continue
                street_out, end_out = here[d_out]
                lane_out = -1 if end_out == "start" else 1
                plan = PlanView(cx + HALF * math.cos(phi), cy + HALF * math.sin(phi),
                                phi + math.pi)
                if turn == 0:
                    plan.line(2 * HALF)
                else:
                    plan.arc((1.0 if turn == 1 else -1.0) / HALF, math.pi / 2 * HALF)
                # d_out is counted from d_in the other way round from generate.py's arms:
                # right of an arm pointing at d_in is d_in + 1 when looking in (turn -1).
                sec = Section(0.0, left=[], right=[Lane(-1, pred=lane_in, succ=lane_out,
                                                        mark="none")], centre_mark="none")
                c = str(cid)
                cid += 1
                roads.append(Road(c, plan, [sec], junction=junction_id(i, j),
                                  pred=("road", street_in, end_in),
                                  succ=("road", street_out, end_out), speed=30,
                                  name=f"{street_in} to {street_out}"))
                connections.append((street_in, c, "start", [(lane_in, -1)]))
        junctions.append((junction_id(i, j), f"junction {i},{j}", connections))
    return document("town", roads, junctions)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=str(Path(__file__).resolve().parent))
    ap.add_argument("--check", action="store_true")
    args = ap.parse_args()
    path = Path(args.out) / "town.xodr"
    text = town().replace("scenarios/maps/generate.py", "scenarios/maps/generate_town.py")
    if args.check:
        if not path.exists() or path.read_text() != text:
            print(f"{path}: differs from what generate_town.py makes; run it again",
                  file=sys.stderr)
            return 1
    else:
        path.write_text(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
