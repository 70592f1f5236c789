#!/usr/bin/env python3
"""Writes the project's own OpenDRIVE maps (scenarios/maps/*.xodr) from their geometry.

  four_way_junction.xodr  a four-way junction with every turn (12 connecting roads), its arms
                          joined in pairs by loop roads so that every lane leads on (random
                          routes never end); arms and loops climb and fall (up to 6 m);
                          each arm has a stop line (DE 294 signal) and a zebra crossing
                          (crosswalk object) where it meets the junction, and a traffic
                          light (DE 1000001, dynamic) at the stop line beside the lane
                          towards the junction, run by a <controller> of its own: controller
                          id = the arm's id = the signal group (SignalGroupID) of MAPEM/SPATEM.
  motorway_merge.xodr     a two-lane dual carriageway round an oval (so that it never ends), an
                          exit ramp that leaves the eastbound lanes at a junction and comes
                          back at a second one into an acceleration lane, which tapers away.

Usage: generate.py [--out DIR] [--check]. --check compares with the files in DIR (default:
this folder) and exits 1 naming the first that differs, so that a test keeps them in step.
The geometry is worked out here (lines and arcs, cubic profiles); the files are OpenDRIVE 1.6.
"""

import argparse
import math
import sys
from pathlib import Path

LANE = 3.5  # m, urban lanes of the junction map
MOTORWAY_LANE = 3.75  # m


def fmt(v):
    """Numbers as the files carry them: 12 significant digits, no -0."""
    text = f"{v:.12g}"
    return "0" if text == "-0" else text


class PlanView:
    """Lines and arcs one after the other, each starting where the last ended."""

    def __init__(self, x, y, hdg):
        self.x, self.y, self.hdg, self.s = x, y, hdg, 0.0
        self.records = []

    def line(self, length):
        self.records.append((self.s, self.x, self.y, self.hdg, length, None))
        self.x += length * math.cos(self.hdg)
        self.y += length * math.sin(self.hdg)
        self.s += length
        return self

    def arc(self, curvature, length):
        self.records.append((self.s, self.x, self.y, self.hdg, length, curvature))
        h1 = self.hdg + curvature * length
        self.x += (math.sin(h1) - math.sin(self.hdg)) / curvature
        self.y -= (math.cos(h1) - math.cos(self.hdg)) / curvature
        self.hdg = h1
        self.s += length
        return self

    def xml(self):
        out = ["    <planView>"]
        for s, x, y, hdg, length, k in self.records:
            shape = "<line/>" if k is None else f'<arc curvature="{fmt(k)}"/>'
            out.append(f'      <geometry s="{fmt(s)}" x="{fmt(x)}" y="{fmt(y)}" hdg="{fmt(hdg)}" '
                       f'length="{fmt(length)}">{shape}</geometry>')
        out.append("    </planView>")
        return out


def smooth_rise(s0, length, z0, z1):
    """A cubic from z0 to z1 over length with zero slope at both ends."""
    dz = z1 - z0
    return (s0, z0, 0.0, 3 * dz / length ** 2, -2 * dz / length ** 3)


def profile_xml(tag, records):
    return [f'      <{tag} s="{fmt(s)}" a="{fmt(a)}" b="{fmt(b)}" c="{fmt(c)}" d="{fmt(d)}"/>'
            for s, a, b, c, d in records]


class Lane:
    def __init__(self, lid, kind="driving", width=LANE, mark="solid", colour="standard",
                 pred=None, succ=None, width_poly=None):
        self.id, self.kind, self.mark, self.colour = lid, kind, mark, colour
        self.width = width_poly or (0.0, width, 0.0, 0.0, 0.0)
        self.pred, self.succ = pred, succ

    def xml(self):
        out = [f'          <lane id="{self.id}" type="{self.kind}" level="false">']
        if self.pred is not None or self.succ is not None:
            out.append("            <link>")
            if self.pred is not None:
                out.append(f'              <predecessor id="{self.pred}"/>')
            if self.succ is not None:
                out.append(f'              <successor id="{self.succ}"/>')
            out.append("            </link>")
        so, a, b, c, d = self.width
        out.append(f'            <width sOffset="{fmt(so)}" a="{fmt(a)}" b="{fmt(b)}" '
                   f'c="{fmt(c)}" d="{fmt(d)}"/>')
        out.append(f'            <roadMark sOffset="0" type="{self.mark}" weight="standard" '
                   f'color="{self.colour}" width="0.15"/>')
        out.append("          </lane>")
        return out


class Section:
    def __init__(self, s, left, right, centre_mark="solid"):
        self.s, self.left, self.right, self.centre_mark = s, left, right, centre_mark

    def xml(self):
        out = [f'      <laneSection s="{fmt(self.s)}">']
        if self.left:
            out.append("        <left>")
            for lane in sorted(self.left, key=lambda l: -l.id):
                out += lane.xml()
            out.append("        </left>")
        out.append("        <center>")
        out.append('          <lane id="0" type="none" level="false">')
        out.append(f'            <roadMark sOffset="0" type="{self.centre_mark}" '
                   f'weight="standard" color="standard" width="0.15"/>')
        out.append("          </lane>")
        out.append("        </center>")
        if self.right:
            out.append("        <right>")
            for lane in sorted(self.right, key=lambda l: -l.id):
                out += lane.xml()
            out.append("        </right>")
        out.append("      </laneSection>")
        return out


def object_xml(oid, kind, s, t, length=0.0, width=0.0, height=0.0, hdg=0.0, radius=None,
               name="", z_offset=0.0, repeat=None):
    """An <object> (OpenDRIVE 1.7, 13); @p repeat: (s, length, distance, t_start, t_end)."""
    size = f'radius="{fmt(radius)}"' if radius is not None else \
        f'length="{fmt(length)}" width="{fmt(width)}"'
    head = (f'      <object id="{oid}" type="{kind}" name="{name}" s="{fmt(s)}" t="{fmt(t)}" '
            f'zOffset="{fmt(z_offset)}" hdg="{fmt(hdg)}" orientation="none" {size} '
            f'height="{fmt(height)}"')
    if repeat is None:
        return [head + "/>"]
    rs, rl, rd, t0, t1 = repeat
    return [head + ">",
            f'        <repeat s="{fmt(rs)}" length="{fmt(rl)}" distance="{fmt(rd)}" '
            f'tStart="{fmt(t0)}" tEnd="{fmt(t1)}" zOffsetStart="0" zOffsetEnd="0"/>',
            "      </object>"]


def signal_xml(sid, s, t, orientation, kind, width=0.0, height=0.0, z_offset=0.0, name="",
               subtype="-1", value=None, dynamic=False, validity=None):
    """A <signal> of the German catalogue (OpenDRIVE 1.7, 14): 294 stop line, 206 stop sign,
    1000001 traffic light (dynamic); @p validity: (fromLane, toLane) it is valid for (14.3)."""
    val = f' value="{fmt(value)}" unit="km/h"' if value is not None else ""
    head = (f'      <signal id="{sid}" name="{name}" s="{fmt(s)}" t="{fmt(t)}" '
            f'zOffset="{fmt(z_offset)}" hOffset="0" orientation="{orientation}" '
            f'dynamic="{"yes" if dynamic else "no"}" '
            f'country="DE" type="{kind}" subtype="{subtype}"{val} height="{fmt(height)}" '
            f'width="{fmt(width)}"')
    if validity is None:
        return [head + "/>"]
    return [head + ">",
            f'        <validity fromLane="{validity[0]}" toLane="{validity[1]}"/>',
            "      </signal>"]


def controller_xml(cid, name, signal_ids, sequence=None):
    """A top-level <controller> (OpenDRIVE 1.7, 14.7) switching @p signal_ids together."""
    seq = f' sequence="{sequence}"' if sequence is not None else ""
    out = [f'  <controller id="{cid}" name="{name}"{seq}>']
    out += [f'    <control signalId="{sid}"/>' for sid in signal_ids]
    out.append("  </controller>")
    return out


class Road:
    def __init__(self, rid, plan, sections, junction="-1", pred=None, succ=None, elevation=None,
                 speed=None, name="", objects=None, signals=None):
        self.id, self.plan, self.sections = rid, plan, sections
        self.junction, self.pred, self.succ = junction, pred, succ
        self.elevation = elevation or [(0.0, 0.0, 0.0, 0.0, 0.0)]
        self.speed, self.name = speed, name
        self.objects, self.signals = objects or [], signals or []

    def xml(self):
        length = self.plan.s
        out = [f'  <road name="{self.name}" id="{self.id}" junction="{self.junction}" '
               f'length="{fmt(length)}" rule="RHT">']
        out.append("    <link>")
        for tag, link in (("predecessor", self.pred), ("successor", self.succ)):
            if link is None:
                continue
            kind, eid, contact = link
            if kind == "junction":
                out.append(f'      <{tag} elementType="junction" elementId="{eid}"/>')
            else:
                out.append(f'      <{tag} elementType="road" elementId="{eid}" '
                           f'contactPoint="{contact}"/>')
        out.append("    </link>")
        if self.speed:
            out.append('    <type s="0" type="town">')
            out.append(f'      <speed max="{fmt(self.speed)}" unit="km/h"/>')
            out.append("    </type>")
        out += self.plan.xml()
        out.append("    <elevationProfile>")
        out += profile_xml("elevation", self.elevation)
        out.append("    </elevationProfile>")
        out.append("    <lanes>")
        for sec in self.sections:
            out += sec.xml()
        out.append("    </lanes>")
        for tag, items in (("objects", self.objects), ("signals", self.signals)):
            if items:
                out.append(f"    <{tag}>")
                out += items
                out.append(f"    </{tag}>")
        out.append("  </road>")
        return out


def document(name, roads, junctions, controllers=(), junction_controllers=None):
    """@p controllers: lines of top-level <controller>s (they come between the roads and the
    junctions in the schema); @p junction_controllers: junction id -> [(controller id, type,
    sequence)] that the junction names (OpenDRIVE 1.7, 10.9 / 14.7)."""
    out = ['<?xml version="1.0" encoding="UTF-8"?>',
           "<!-- Generated by scenarios/maps/generate.py; edit that, not this. -->",
           "<OpenDRIVE>",
           f'  <header revMajor="1" revMinor="6" name="{name}" version="1" '
           f'vendor="v2x-testbed"/>']
    for road in roads:
        out += road.xml()
    out += list(controllers)
    for jid, jname, connections in junctions:
        out.append(f'  <junction id="{jid}" name="{jname}">')
        for cid, (incoming, connecting, contact, links) in enumerate(connections):
            out.append(f'    <connection id="{cid}" incomingRoad="{incoming}" '
                       f'connectingRoad="{connecting}" contactPoint="{contact}">')
            for a, b in links:
                out.append(f'      <laneLink from="{a}" to="{b}"/>')
            out.append("    </connection>")
        for cid, kind, seq in (junction_controllers or {}).get(jid, []):
            out.append(f'    <controller id="{cid}" type="{kind}" sequence="{seq}"/>')
        out.append("  </junction>")
    out.append("</OpenDRIVE>")
    return "\n".join(out) + "\n"


# --------------------------------------------------------------------------------------------
# The four-way junction.

JUNCTION_HALF = 12.0  # m from the junction's centre to where each arm starts
ARM_END = 80.0        # m from the centre to where each arm ends
LOOP_RADIUS = 25.0    # m, the loops' corners
ARM_RISE = 3.0        # m, each arm climbs from the junction to its end
LOOP_CREST = 3.0      # m, each loop climbs further to its middle and back
STOP_LINE_S = 4.5     # m into each arm from the junction: the stop line (DE 294) across lane 1
CROSSWALK_S = 2.0     # m into each arm: the middle of a 3 m zebra crossing over both lanes
# The traffic light (DE 1000001, three lights) of each arm: on a pole in the middle of the
# sidewalk (lane 2, 2 m wide) right of the lane towards the junction, level with the stop line;
# the head's lower edge 2.1 m up, 0.9 m tall, 0.3 m wide (a 200 mm three-light head).
LIGHT_T = LANE + 1.0
LIGHT_Z, LIGHT_HEIGHT, LIGHT_WIDTH = 2.1, 0.9, 0.3


def four_way():
    # Arms east, north, west, south; lane -1 leads away from the junction, 1 towards it.
    angles = [0.0, math.pi / 2, math.pi, 3 * math.pi / 2]
    arm_ids = ["1", "2", "3", "4"]
    loop_of = {"1": "10", "2": "10", "3": "11", "4": "11"}  # east-north and west-south loops
    roads = []
    arm_length = ARM_END - JUNCTION_HALF
    for arm, phi in zip(arm_ids, angles):
        plan = PlanView(JUNCTION_HALF * math.cos(phi), JUNCTION_HALF * math.sin(phi), phi)
        plan.line(arm_length)
        # The loop starts at the first arm of its pair and ends at the second.
        first = arm in ("1", "3")
        loop_contact = "start" if first else "end"
        lanes = Section(0.0,
                        left=[Lane(1, pred=None, succ=1 if first else -1),
                              Lane(2, "sidewalk", 2.0, mark="none")],
                        right=[Lane(-1, succ=-1 if first else 1),
                               Lane(-2, "sidewalk", 2.0, mark="none")])
        # Junction marks: a stop line across the lane towards the junction (lane 1, against
        # s: orientation "-"), and a zebra crossing between it and the junction over both
        # lanes, from sidewalk to sidewalk.
        marks = signal_xml(f"{arm}94", STOP_LINE_S, LANE / 2, "-", "294", width=LANE,
                           name="stop line")
        # The light for lane 1 only (validity), switched by controller <arm>.
        marks += signal_xml(f"{arm}93", STOP_LINE_S, LIGHT_T, "-", "1000001", width=LIGHT_WIDTH,
                            height=LIGHT_HEIGHT, z_offset=LIGHT_Z, name="traffic light",
                            dynamic=True, validity=(1, 1))
        crossing = object_xml(f"{arm}90", "crosswalk", CROSSWALK_S, 0.0, length=3.0,
                              width=2 * LANE, name="zebra crossing")
        roads.append(Road(arm, plan, [lanes], pred=("junction", "100", None),
                          succ=("road", loop_of[arm], loop_contact),
                          elevation=[smooth_rise(0.0, arm_length, 0.0, ARM_RISE)],
                          speed=50, name=f"arm {arm}", objects=crossing, signals=marks))
    # Loops: from the end of the first arm of a pair round to the end of the second.
    side = ARM_END - LOOP_RADIUS
    for loop, (a, b), phi in (("10", ("1", "2"), 0.0), ("11", ("3", "4"), math.pi)):
        plan = PlanView(ARM_END * math.cos(phi), ARM_END * math.sin(phi), phi)
        k = 1.0 / LOOP_RADIUS
        quarter = math.pi / 2 * LOOP_RADIUS
        plan.arc(k, quarter).line(side).arc(k, quarter).line(side).arc(k, quarter)
        half = plan.s / 2
        lanes = Section(0.0,
                        left=[Lane(1, pred=1, succ=-1), Lane(2, "shoulder", 1.5, mark="none")],
                        right=[Lane(-1, pred=-1, succ=1), Lane(-2, "shoulder", 1.5, mark="none")],
                        centre_mark="broken")
        roads.append(Road(loop, plan, [lanes], pred=("road", a, "end"), succ=("road", b, "end"),
                          elevation=[smooth_rise(0.0, half, ARM_RISE, ARM_RISE + LOOP_CREST),
                                     smooth_rise(half, half, ARM_RISE + LOOP_CREST, ARM_RISE)],
                          speed=50, name=f"loop {a}-{b}"))
    # Connecting roads: from each arm's inbound lane (1) to every other arm's outbound lane
    # (-1), one lane (-1) right of a reference line on the arms' centre lines.
    connections = []
    cid = 100
    for i, arm in enumerate(arm_ids):
        phi = angles[i]
        for turn in (-1, 0, 1):  # right, straight, left
            j = (i + {-1: 1, 0: 2, 1: 3}[turn]) % 4
            plan = PlanView(JUNCTION_HALF * math.cos(phi), JUNCTION_HALF * math.sin(phi),
                            phi + math.pi)
            if turn == 0:
                plan.line(2 * JUNCTION_HALF)
                mark = "none"
            else:
                # A right turn curves clockwise (into the quadrant between the two arms).
                k = (1.0 if turn == 1 else -1.0) / JUNCTION_HALF
                plan.arc(k, math.pi / 2 * JUNCTION_HALF)
                mark = "none"
            rid = str(cid)
            cid += 1
            sec = Section(0.0, left=[], right=[Lane(-1, pred=1, succ=-1, mark=mark)],
                          centre_mark="none")
            roads.append(Road(rid, plan, [sec], junction="100",
                              pred=("road", arm, "start"), succ=("road", arm_ids[j], "start"),
                              speed=30, name=f"{arm} to {arm_ids[j]}"))
            connections.append((arm, rid, "start", [(1, -1)]))
    # One controller per arm: its id is the signal group (SignalGroupID) of every manoeuvre
    # from that arm in MAPEM/SPATEM. The sequence pairs opposite arms (1 with 3, 2 with 4), the
    # order a fixed-time plan serves them in; the plan itself is the scenario's.
    controllers = []
    for arm in arm_ids:
        controllers += controller_xml(arm, f"arm {arm}", [f"{arm}93"])
    refs = {"100": [(arm, "trafficLight", 1 if arm in ("1", "3") else 2) for arm in arm_ids]}
    return document("four-way junction", roads, [("100", "four-way", connections)],
                    controllers, refs)


# --------------------------------------------------------------------------------------------
# The motorway merge.

OVAL_RADIUS = 300.0   # m, the turns at both ends of the oval
STRAIGHT = 1400.0     # m, the oval's straights
J1_X, J1_LENGTH = 300.0, 80.0  # m: the exit junction, long enough for the exit to leave lane -2
J2_X, J2_LENGTH = 800.0, 20.0  # m: the entry junction
EXIT_TURN = 0.15      # rad the exit turns away within its junction
RAMP_RADIUS = 300.0   # m, the ramp's bends
RAMP_AWAY = 100.0     # m the ramp runs away from the motorway before turning parallel
RAMP_BACK = 0.1       # rad at which it comes back
ACCEL_FULL, ACCEL_TAPER = 200.0, 100.0  # m, the acceleration lane at full width, then tapering


def carriageway(s=0.0, entry=None):
    """Two lanes each way and a shoulder beyond the westbound ones; lanes continue by id.
    @p entry: an extra right lane -3 (the acceleration lane)."""
    w = MOTORWAY_LANE
    left = [Lane(1, width=w, mark="broken", pred=1, succ=1),
            Lane(2, width=w, pred=2, succ=2),
            Lane(3, "shoulder", 2.5, mark="none", pred=3, succ=3)]
    right = [Lane(-1, width=w, mark="broken", pred=-1, succ=-1),
             Lane(-2, width=w, mark="broken" if entry else "solid", pred=-2, succ=-2)]
    if entry:
        right.append(entry)
    return Section(s, left, right, centre_mark="solid solid")


def motorway():
    roads = []
    w = MOTORWAY_LANE

    def straight_road(rid, x0, x1, pred, succ, sections):
        plan = PlanView(x0, 0.0, 0.0).line(x1 - x0)
        return Road(rid, plan, sections, pred=pred, succ=succ, speed=120, name=f"motorway {rid}")

    # The oval, counter-clockwise for the eastbound (right) lanes: the bottom straight in three
    # roads around the two junctions, the east turn, the top straight, the west turn.
    j1_end, j2_end = J1_X + J1_LENGTH, J2_X + J2_LENGTH
    roads.append(straight_road("1", 0.0, J1_X, ("road", "6", "end"), ("junction", "100", None),
                               [carriageway()]))
    roads.append(straight_road("2", j1_end, J2_X, ("junction", "100", None),
                               ("junction", "200", None), [carriageway()]))
    # After the entry: the acceleration lane (type entry) at full width, then tapering away.
    taper = (0.0, w, 0.0, -3 * w / ACCEL_TAPER ** 2, 2 * w / ACCEL_TAPER ** 3)
    roads.append(straight_road("3", j2_end, STRAIGHT, ("junction", "200", None),
                               ("road", "4", "start"),
                               [carriageway(0.0, Lane(-3, "entry", w, mark="solid", succ=-3)),
                                carriageway(ACCEL_FULL, Lane(-3, "entry", mark="solid", pred=-3,
                                                             width_poly=taper)),
                                carriageway(ACCEL_FULL + ACCEL_TAPER)]))
    k = 1.0 / OVAL_RADIUS
    turn = math.pi * OVAL_RADIUS
    roads.append(Road("4", PlanView(STRAIGHT, 0.0, 0.0).arc(k, turn), [carriageway()],
                      pred=("road", "3", "end"), succ=("road", "5", "start"), speed=120,
                      name="motorway 4"))
    roads.append(Road("5", PlanView(STRAIGHT, 2 * OVAL_RADIUS, math.pi).line(STRAIGHT),
                      [carriageway()], pred=("road", "4", "end"), succ=("road", "6", "start"),
                      speed=120, name="motorway 5"))
    roads.append(Road("6", PlanView(0.0, 2 * OVAL_RADIUS, math.pi).arc(k, turn), [carriageway()],
                      pred=("road", "5", "end"), succ=("road", "1", "start"), speed=120,
                      name="motorway 6"))
    # Junction 100 (exit): the carriageway through it, and the exit, whose lane starts on lane
    # -2 and bends away to the right until it is clear of it.
    roads.append(Road("101", PlanView(J1_X, 0.0, 0.0).line(J1_LENGTH), [carriageway()],
                      junction="100", pred=("road", "1", "end"), succ=("road", "2", "start"),
                      speed=120, name="through exit junction"))
    exit_plan = PlanView(J1_X, -w, 0.0).arc(-EXIT_TURN / J1_LENGTH, J1_LENGTH)
    roads.append(Road("102", exit_plan,
                      [Section(0.0, [], [Lane(-1, "exit", w, pred=-2, succ=-1)],
                               centre_mark="none")],
                      junction="100", pred=("road", "1", "end"), succ=("road", "7", "start"),
                      speed=80, name="exit"))
    # The ramp: on away at the exit's heading, parallel, back at RAMP_BACK, and parallel again
    # beside lane -2 where the entry junction starts.
    r, h0, th = RAMP_RADIUS, exit_plan.hdg, RAMP_BACK
    x0, y0 = exit_plan.x, exit_plan.y
    y_end = -2 * w  # the entry's reference line: lane -2's outer border
    l1 = RAMP_AWAY
    l3 = (y_end - y0 - l1 * math.sin(h0) + r * (1 - math.cos(h0)) - 2 * r * (1 - math.cos(th))) \
        / math.sin(th)
    l2 = (J2_X - x0) - l1 * math.cos(h0) - r * math.sin(-h0) - 2 * r * math.sin(th) \
        - l3 * math.cos(th)
    if l2 <= 0 or l3 <= 0:
        raise SystemExit("motorway ramp does not fit: move the junctions apart")
    ramp = PlanView(x0, y0, h0)
    ramp.line(l1).arc(1 / r, -h0 * r).line(l2).arc(1 / r, th * r).line(l3).arc(-1 / r, th * r)
    roads.append(Road("7", ramp, [Section(0.0, [], [Lane(-1, "onRamp", w, pred=-1, succ=-1),
                                                    Lane(-2, "border", 1.0, mark="none")],
                                          centre_mark="solid")],
                      pred=("road", "102", "end"), succ=("road", "202", "start"), speed=80,
                      name="ramp"))
    # Junction 200 (entry): the carriageway through it, and the ramp into the acceleration lane.
    roads.append(Road("201", PlanView(J2_X, 0.0, 0.0).line(J2_LENGTH), [carriageway()],
                      junction="200", pred=("road", "2", "end"), succ=("road", "3", "start"),
                      speed=120, name="through entry junction"))
    roads.append(Road("202", PlanView(J2_X, y_end, 0.0).line(J2_LENGTH),
                      [Section(0.0, [], [Lane(-1, "onRamp", w, pred=-1, succ=-3)],
                               centre_mark="none")],
                      junction="200", pred=("road", "7", "end"), succ=("road", "3", "start"),
                      speed=80, name="entry"))
    junctions = [
        ("100", "exit", [("1", "101", "start", [(-1, -1), (-2, -2)]),
                         ("2", "101", "end", [(1, 1), (2, 2), (3, 3)]),
                         ("1", "102", "start", [(-2, -1)])]),
        ("200", "entry", [("2", "201", "start", [(-1, -1), (-2, -2)]),
                          ("3", "201", "end", [(1, 1), (2, 2), (3, 3)]),
                          ("7", "202", "start", [(-1, -1)])]),
    ]
    return document("motorway merge", roads, junctions)


MAPS = {"four_way_junction.xodr": four_way, "motorway_merge.xodr": motorway}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=str(Path(__file__).resolve().parent))
    ap.add_argument("--check", action="store_true")
    args = ap.parse_args()
    out = Path(args.out)
    for name, make in MAPS.items():
        text = make()
        if args.check:
            have = (out / name).read_text() if (out / name).exists() else None
            if have != text:
                print(f"{out / name}: differs from what generate.py makes; run it again",
                      file=sys.stderr)
                return 1
        else:
            (out / name).write_text(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
