#!/usr/bin/env python3
"""Unit test of scripts/report's joins on hand-made trace records (no programs, no clocks):
which steps count as state changes, the CAM and warning stages, the HMI's receipts, the DENM
stages, --require, and a light change's way to the HUD (issue 34).

    python3 tests/report/report_test.py
"""
import json
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
MS = 1_000_000
T0 = 1_750_000_000_000 * MS  # wall clock of tick 0, ns
START_MS = 1_748_854_800_000  # the scenario's start time (fix_ms of sim time 0)
ITS_EPOCH_MS = 1_072_915_200_000


def step_ns(tick):
    return T0 + tick * 10 * MS


def gdt(unix_ms):
    return (unix_ms - ITS_EPOCH_MS) % 65536


class Trace:
    def __init__(self):
        self.records = []

    def add(self, ts, ev, **fields):
        self.records.append({"ts": ts, "proc": "test", "ev": ev, **fields})

    def write(self, folder):
        with open(Path(folder) / "all.jsonl", "w") as f:
            for r in self.records:
                f.write(json.dumps(r) + "\n")


def vehicle(trace, station, ticks, moving, warmup=None):
    """Steps, forwards, a GNSS epoch every 10 ticks and a CAM from each epoch's fix 30 ms after
    the step it describes. With @p warmup, the first that many ticks are the warm-up (sim time
    ≤ 0 in client.forward's sim_ns). Returns {tick of the epoch: CAM tx time}."""
    cams = {}
    for tick in ticks:
        x = tick * 0.1 if moving else 5.0
        sim = {} if warmup is None else {"sim_ns": (tick - warmup) * 10 * MS}
        trace.add(step_ns(tick) + 200_000, "client.forward", station=station, tick=tick,
                  step_ns=step_ns(tick), x=x, y=-1.75, v=10.0 if moving else 0.0, yaw=0.0, **sim)
        trace.add(step_ns(tick) + 300_000, "emu.state", station=station, tick=tick)
        if tick % 10 == 0:
            fix_ms = START_MS + (tick - (warmup or 0)) * 10
            trace.add(step_ns(tick) + 350_000, "emu.nmea", station=station, tick=tick, fix_ms=fix_ms)
            trace.add(step_ns(tick) + 1 * MS, "its.fix", station=station, fix_ms=fix_ms,
                      read_ns=step_ns(tick) + 1 * MS - 20_000)
            g = gdt(fix_ms)
            trace.add(step_ns(tick) + 29 * MS, "its.cam_build", station=station, fix_ms=fix_ms, gdt=g,
                      trigger="time")
            cams[tick] = step_ns(tick) + 30 * MS
            trace.add(cams[tick], "its.cam_tx", station=station, fix_ms=fix_ms, gdt=g, bytes=50,
                      encode_ns=cams[tick] - 300_000, sent_ns=cams[tick] + 40_000)
    return cams


def run_report(trace, *args):
    with tempfile.TemporaryDirectory() as d:
        trace.write(d)
        out = Path(d) / "stats.json"
        r = subprocess.run([sys.executable, str(ROOT / "scripts/report"), d, "--json", str(out), *args],
                           capture_output=True, text=True)
        stats = json.loads(out.read_text())["stages"] if out.exists() else {}
        return r, stats


class ReportTest(unittest.TestCase):
    def setUp(self):
        self.trace = Trace()
        for tick in range(1, 31):
            self.trace.add(step_ns(tick), "server.step", tick=tick, dur_ns=100_000)
        # Station 1 drives, station 2 stands; the epoch at tick 30 is each one's last fix.
        self.moving = vehicle(self.trace, 1, range(1, 31), True)
        self.standing = vehicle(self.trace, 2, range(1, 31), False)

    def test_standing_steps_are_no_state_change(self):
        _, st = run_report(self.trace)
        # Station 1: the first epoch's CAM carries its own step (no epoch before it), the second
        # one ticks 11-20, each 30 ms after the epoch's step plus the step's distance before it
        # (epoch 30 is the last fix: left out). Station 2 stands: its only change, the first
        # step, comes before its first epoch, which carries no change.
        want = [30] + [30 + 10 * (20 - k) for k in range(11, 21)]
        self.assertEqual(st["state_to_cam"]["n"], len(want))
        self.assertAlmostEqual(st["state_to_cam"]["mean"], sum(want) / len(want), places=6)
        self.assertAlmostEqual(st["state_to_cam"]["max"], 120.0, places=6)
        self.assertEqual(st["fix_state_to_cam"]["n"], 4)  # per CAM, whether it carries a change
        # The receiver's period wait of the same changes: the epoch's step minus theirs.
        self.assertEqual(st["t3.period"]["n"], len(want))
        self.assertAlmostEqual(st["t3.period"]["mean"], st["state_to_cam"]["mean"] - 30, places=6)
        self.assertAlmostEqual(st["t3.uptake"]["mean"], 0.02, places=6)
        self.assertAlmostEqual(st["t3.gpsd"]["mean"], 0.65, places=6)
        # p3 (1 ms from cam_build to cam_tx) splits at encode_ns: build 0.7, encode 0.3.
        self.assertAlmostEqual(st["p3"]["mean"], 1.0, places=6)
        self.assertAlmostEqual(st["p3.build"]["mean"], 0.7, places=6)
        self.assertAlmostEqual(st["p3.encode"]["mean"], 0.3, places=6)

    def test_air_splits_at_the_medium(self):
        # Station 1's CAM of epoch 20 is on the interface 0.04 ms after it was handed to the
        # network (every CAM, vehicle()), at the medium 0.2 ms after, and station 2 decodes it
        # 0.5 ms after that.
        fix_ms = START_MS + 200
        self.trace.add(self.moving[20] + 200_000, "medium.rx", src=1, station=1, gdt=gdt(fix_ms), bytes=120)
        self.trace.add(self.moving[20] + 210_000, "medium.rx", src=1, bytes=60)  # no CAM: ignored
        self.trace.add(self.moving[20] + 700_000, "its.cam_rx", station=2, **{"from": 1}, gdt=gdt(fix_ms))
        r, st = run_report(self.trace, "--require", "t4,p4.t5,air")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertAlmostEqual(st["t4"]["mean"], 0.04, places=6)
        self.assertEqual(st["t4"]["n"], 4)
        self.assertAlmostEqual(st["p4.t5"]["mean"], 0.5, places=6)
        self.assertAlmostEqual(st["air"]["mean"], 0.7, places=6)

    def test_security_stages_of_a_signing_run(self):
        # Station 1's CAM of epoch 20: signed 10 µs after the hand-over (25 µs, with the AT),
        # received by station 2, whose CAM verification ends 0.6 ms after the CAM's hand-over
        # and the decoded CAM 0.1 ms after that. A beacon (psid 141) signed and verified meanwhile
        # is no CAM's: left out of both.
        fix_ms = START_MS + 200
        t = self.moving[20]
        self.trace.add(t + 10_000, "its.sign", station=1, psid=36, bytes=316, certificate=True,
                       end_ns=t + 35_000)
        self.trace.add(t + 50_000, "its.sign", station=1, psid=141, bytes=150, end_ns=t + 90_000)
        self.trace.add(self.moving[10] + 10_000, "its.sign", station=1, psid=36, bytes=174,
                       certificate=False, end_ns=self.moving[10] + 30_000)
        self.trace.add(t + 540_000, "its.verify", station=2, psid=36, result="ok",
                       end_ns=t + 600_000)
        self.trace.add(t + 650_000, "its.verify", station=2, psid=141, result="ok",
                       end_ns=t + 690_000)
        self.trace.add(t + 700_000, "its.cam_rx", station=2, **{"from": 1}, gdt=gdt(fix_ms))
        r, st = run_report(self.trace, "--require", "security")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(st["t4.sign"]["n"], 2)
        self.assertAlmostEqual(st["t4.sign"]["max"], 0.025, places=6)
        self.assertEqual(st["rx.verify"]["n"], 1)
        self.assertAlmostEqual(st["rx.verify"]["mean"], 0.06, places=6)
        # The decoded CAM follows the CAM's verification, not the beacon's after it.
        self.assertEqual(st["rx.decode"]["n"], 1)
        self.assertAlmostEqual(st["rx.decode"]["mean"], 0.1, places=6)
        # Sizes: the CAMs are 50 octets (vehicle()), so 316 - 40 - 50 of security with the AT.
        self.assertIn("certificate signer: GN packet 320, of it security 226 (n=1); "
                      "digest signer: GN packet 178, of it security 84 (n=1)", r.stdout)

    def test_old_traces_count_every_step(self):
        for r in self.trace.records:
            if r["ev"] == "client.forward":
                del r["x"]
        _, st = run_report(self.trace)
        self.assertEqual(st["state_to_cam"]["n"], 22)

    def test_warning_to_hmi(self):
        # Station 1 warns about station 2 on the CAM of its epoch 20, decided 0.5 ms after the
        # own fix of epoch 20 arrived; published 0.1 ms later; the HMI receives it 2 ms later
        # and shows it 1 ms after that. A second receipt names no publication (other own_ms).
        cam_fix = START_MS + 200
        own_fix = START_MS + 200
        decided = step_ns(20) + 31 * MS
        self.trace.add(decided, "its.lcrw", station=1, **{"from": 2}, gdt=gdt(cam_fix), warn=True, ttc=2.0)
        self.trace.add(decided + 100_000, "its.mqtt", station=1, topic="its/1/app/lcrw", **{"from": 2},
                       gdt=gdt(cam_fix), own_ms=own_fix, event="raised")
        self.trace.add(decided + 2_100_000, "hmi.lcrw", station=1, **{"from": 2}, gdt=gdt(cam_fix),
                       own_ms=own_fix, event="raised", shown_ns=decided + 3_100_000)
        self.trace.add(decided + 2_200_000, "hmi.lcrw", station=1, **{"from": 2}, gdt=gdt(cam_fix),
                       own_ms=own_fix + 100, event="updated", shown_ns=decided + 3_200_000)
        r, st = run_report(self.trace, "--require", "mqtt,hmi,hmi.show,state_to_hmi")
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertAlmostEqual(st["mqtt"]["mean"], 0.1, places=6)
        self.assertEqual(st["hmi"]["n"], 1)
        self.assertAlmostEqual(st["hmi"]["mean"], 2.0, places=6)
        self.assertAlmostEqual(st["hmi.show"]["mean"], 1.0, places=6)
        # The evaluation ran on the own fix of epoch 20, which arrived after the neighbour's CAM
        # (ticks 11-20 moved the car): 10 changes.
        self.assertEqual(st["state_to_warning"]["n"], 10)
        self.assertEqual(st["state_to_hmi"]["n"], 10)
        self.assertAlmostEqual(st["state_to_hmi"]["mean"] - st["state_to_warning"]["mean"], 2.0, places=6)

    def test_a_standing_cars_warning_answers_no_state_change(self):
        # Station 2 stands and warns on its own fix of epoch 20 about station 1's CAM of epoch
        # 10, which arrived before that fix: the fix brought no change, so no samples. The same
        # warning made on the CAM's arrival answers the CAM's changes.
        cam_fix = START_MS + 100
        self.trace.add(self.moving[10] + 500_000, "its.cam_rx", station=2, **{"from": 1}, gdt=gdt(cam_fix))
        decided = step_ns(20) + 2 * MS
        self.trace.add(decided, "its.lcrw", station=2, **{"from": 1}, gdt=gdt(cam_fix), warn=True, ttc=2.0)
        self.trace.add(decided + 100_000, "its.mqtt", station=2, topic="its/2/app/lcrw", **{"from": 1},
                       gdt=gdt(cam_fix), own_ms=START_MS + 200, event="raised")
        _, st = run_report(self.trace)
        self.assertNotIn("state_to_warning", st)
        self.assertEqual(st["cam_state_to_warning"]["n"], 1)  # the CAM of epoch 10: its own step
        self.trace.add(self.moving[10] + 600_000, "its.mqtt", station=2, topic="its/2/app/lcrw",
                       **{"from": 1}, gdt=gdt(cam_fix), own_ms=START_MS + 100, event="raised")
        _, st = run_report(self.trace)
        self.assertEqual(st["state_to_warning"]["n"], 1)
        self.assertAlmostEqual(st["state_to_warning"]["mean"], 30.6, places=6)

    def test_a_warning_made_on_a_third_stations_cam_answers_no_state_change(self):
        # Station 1 clears its warning about station 2 in an evaluation made on a CAM of
        # another station, 59 ms after its own last fix: no new input of the pair, no samples.
        cam_fix = START_MS + 200
        cleared = step_ns(20) + 60 * MS
        self.trace.add(cleared, "its.lcrw", station=1, **{"from": 2}, gdt=gdt(cam_fix), warn=False, ttc=None)
        self.trace.add(cleared + 50_000, "its.mqtt", station=1, topic="its/1/app/lcrw", **{"from": 2},
                       gdt=gdt(cam_fix), own_ms=START_MS + 200, event="cleared")
        _, st = run_report(self.trace)
        self.assertNotIn("state_to_warning", st)
        self.assertAlmostEqual(st["mqtt"]["mean"], 0.05, places=6)

    def test_denm_stages(self):
        # Station 1's LCRW evaluation at D warns about station 2 (and not about 3, in the same
        # evaluation): its DEN service hands the new event (seq 0) to the network 0.3 ms later.
        # Station 2 accepts it 1.5 ms after D; station 3, outside the relevance area then,
        # accepts the repetition of D + 100.3 ms (same referenceTime) 1.0 ms after it. An update
        # (new referenceTime) made in the evaluation of D + 150 ms leaves 0.2 ms after it and is
        # accepted at 2 after 0.8 ms. Station 2's page receives the acceptances 2.0 and 3.0 ms
        # after them.
        D = step_ns(20) + 31 * MS
        t = self.trace

        def lcrw(at, about, warn):
            t.add(at, "its.lcrw", station=1, **{"from": about}, gdt=1, warn=warn, ttc=2.0 if warn else None)

        def tx(at, seq, ref, term=False):
            t.add(at, "its.denm_tx", station=1, origin=1, seq=seq, ref=ref, term=term)

        def rx(at, station, seq, outcome):
            t.add(at, "its.denm_rx", station=station, origin=1, seq=seq, outcome=outcome)

        def page(at, station, seq, direction="in", term=False):
            t.add(at, "hmi.denm", station=station, origin=1, seq=seq, dir=direction, term=term,
                  shown_ns=at + 100_000)

        lcrw(D - 100 * MS, 2, False)
        lcrw(D, 2, True)
        lcrw(D, 3, False)
        tx(D + 300_000, 0, 5000)
        rx(D + 1_500_000, 2, 0, "new")
        page(D + 3_500_000, 2, 0)
        page(D + 3_600_000, 1, 0, direction="out")  # the originator's own page: not a neighbour's
        lcrw(D + 50 * MS, 2, True)
        tx(D + 100_300_000, 0, 5000)  # a repetition: no decision of its own
        rx(D + 101_000_000, 2, 0, "repetition")
        rx(D + 101_300_000, 3, 0, "new")
        lcrw(D + 150 * MS, 2, True)
        tx(D + 150_200_000, 0, 5150)  # the update
        rx(D + 151_000_000, 2, 0, "update")
        page(D + 154_000_000, 2, 0)
        page(D + 154_500_000, 2, 0)  # the same publication on a second page: one sample
        # Station 2 forwards the event (keep-alive) and station 4 accepts it: no join to the tx.
        t.add(D + 200 * MS, "its.denm_fwd", station=2, origin=1, seq=0, ref=5150)
        rx(D + 201 * MS, 4, 0, "new")
        # The cancellation is no decision's DENM and no acceptance.
        lcrw(D + 300 * MS, 2, False)
        tx(D + 300_100_000, 0, 5300, term=True)
        rx(D + 301 * MS, 2, 0, "cancelled")
        page(D + 303 * MS, 2, 0, term=True)
        # A DENM sent after an evaluation that did not warn (another application's, say): on the
        # air, but no decision.
        lcrw(D + 399_900_000, 2, False)
        tx(D + 400 * MS, 1, 5400)
        rx(D + 401 * MS, 2, 1, "new")
        r, st = run_report(t, "--require", "denm.tx,denm.air,denm.accept,denm.hmi")
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertEqual(st["denm.tx"]["n"], 2)
        self.assertAlmostEqual(st["denm.tx"]["min"], 0.2, places=6)
        self.assertAlmostEqual(st["denm.tx"]["max"], 0.3, places=6)
        # Air: 1.2 (2, new), 1.0 (3, the repetition), 0.8 (2, update), 1.0 (2, seq 1).
        self.assertEqual(st["denm.air"]["n"], 4)
        self.assertAlmostEqual(st["denm.air"]["mean"], 1.0, places=6)
        self.assertAlmostEqual(st["denm.air"]["max"], 1.2, places=6)
        self.assertAlmostEqual(st["denm.air"]["min"], 0.8, places=6)
        # Decision → accepted: 1.5 (the new event at 2) and 1.0 (the update at 2).
        self.assertEqual(st["denm.accept"]["n"], 2)
        self.assertAlmostEqual(st["denm.accept"]["max"], 1.5, places=6)
        self.assertAlmostEqual(st["denm.accept"]["min"], 1.0, places=6)
        self.assertEqual(st["denm.hmi"]["n"], 2)
        self.assertAlmostEqual(st["denm.hmi"]["min"], 2.0, places=6)
        self.assertAlmostEqual(st["denm.hmi"]["max"], 3.0, places=6)

    def test_a_denm_transmission_long_after_the_last_evaluation_has_no_decision(self):
        D = step_ns(20) + 31 * MS
        self.trace.add(D, "its.lcrw", station=1, **{"from": 2}, gdt=1, warn=True, ttc=2.0)
        self.trace.add(D + 1_500 * MS, "its.denm_tx", station=1, origin=1, seq=0, ref=1, term=False)
        self.trace.add(D + 1_501 * MS, "its.denm_rx", station=2, origin=1, seq=0, outcome="new")
        # An acceptance long after the last transmission joins none.
        self.trace.add(D + 2_600 * MS, "its.denm_rx", station=3, origin=1, seq=0, outcome="new")
        r, st = run_report(self.trace, "--require", "denm.accept")
        self.assertEqual(r.returncode, 1)
        self.assertIn("stage denm.accept has no records", r.stderr)
        self.assertNotIn("denm.tx", st)
        self.assertEqual(st["denm.air"]["n"], 1)
        self.assertAlmostEqual(st["denm.air"]["mean"], 1.0, places=6)

    def test_require_all_names_the_missing_stages(self):
        r, _ = run_report(self.trace, "--require", "all")
        self.assertEqual(r.returncode, 1)
        for stage in ("t1", "air", "hmi", "state_to_hmi", "denm.tx", "denm.accept", "denm.hmi"):
            self.assertIn(f"stage {stage} has no records", r.stderr)
        self.assertNotIn("stage state_to_cam has no records", r.stderr)
        # An unsigned run has no security stages: "all" leaves them out, naming one asks for it.
        self.assertNotIn("stage t4.sign has no records", r.stderr)
        r, _ = run_report(self.trace, "--require", "all,security")
        for stage in ("t4.sign", "rx.verify", "rx.decode"):
            self.assertIn(f"stage {stage} has no records", r.stderr)

    def test_the_warm_up_is_left_out(self):
        # Ticks 1-10 are the warm-up (sim time -90 ms … 0: no server.step), 11-30 the physics.
        # Station 1 moves on its run-up and on; station 2 stands.
        t = Trace()
        for tick in range(11, 31):
            t.add(step_ns(tick), "server.step", tick=tick, dur_ns=100_000)
        moving = vehicle(t, 1, range(1, 31), True, warmup=10)
        vehicle(t, 2, range(1, 31), False, warmup=10)
        # Station 2 decodes station 1's CAM of the warm-up's last epoch and of epoch 20.
        for tick in (10, 20):
            t.add(moving[tick] + 700_000, "its.cam_rx", station=2, **{"from": 1},
                  gdt=gdt(START_MS + (tick - 10) * 10))
        t.add(step_ns(5), "its.sign", end_ns=step_ns(5) + 30_000)  # before sim time 0
        r, st = run_report(t)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("of the warm-up (sim time ≤ 0) left out", r.stdout)
        self.assertEqual(st["p1"]["n"], 20)
        self.assertEqual(st["t2"]["n"], 40)  # the physics' ticks of both stations
        # The CAM of epoch 20 carries station 1's physics steps 11-20 (the warm-up's epoch 10 is
        # the one before it); station 2 changed nothing against its last warm-up state.
        want = [30 + 10 * (20 - k) for k in range(11, 21)]
        self.assertEqual(st["state_to_cam"]["n"], len(want))
        self.assertAlmostEqual(st["state_to_cam"]["mean"], sum(want) / len(want), places=6)
        self.assertEqual(st["fix_state_to_cam"]["n"], 2)  # epoch 20 of each; 30 is the last
        self.assertEqual(st["t3.gpsd"]["n"], 4)  # epochs 20 and 30 of each
        self.assertEqual(st["air"]["n"], 1)
        self.assertNotIn("t4.sign", st)

    def test_bounds(self):
        r, _ = run_report(self.trace, "--max-p99", "state_to_cam=100")
        self.assertEqual(r.returncode, 1)
        self.assertIn("state_to_cam p99", r.stderr)
        r, _ = run_report(self.trace, "--max-p99", "state_to_cam=250")
        self.assertEqual(r.returncode, 0, r.stderr)


def signal_path(trace, t0, world_ms, intersection=100, group=1, state=6, rsu=5001, skip=()):
    """One light change's way from sim-server to the RSU's SPATEM at the medium, each hop a
    fixed time after the one before (ms after the change at @p t0): client 0.2, emulator 0.5,
    the RSU's read 0.6, the SPATEM at the medium 0.7, the RSU's send returned 0.75. Records named
    in @p skip are left out (a missing stage)."""
    hops = [("server.signal", 0.0, dict(intersection=intersection, group=group, state=state,
                                        world_ms=world_ms, next_change_ms=world_ms + 3000)),
            ("client.signals", 0.2, dict(world_ms=world_ms, groups=4)),
            ("emu.signals", 0.5, dict(station=rsu, world_ms=world_ms, groups=4)),
            ("its.signal_feed_rx", 0.6, dict(station=rsu, bytes=98)),
            ("medium.rx", 0.7, dict(src=rsu, bytes=107)),
            ("its.spatem_tx", 0.75, dict(station=rsu, on_change=True, bytes=49))]
    for ev, at, fields in hops:
        if ev not in skip:
            trace.add(t0 + int(at * MS), ev, **fields)


def on_lane(trace, station, t_from, t_to, state, group=1, intersection=100, lane=1):
    """The station's signal application evaluating its group every 100 ms in [t_from, t_to)."""
    for t in range(t_from, t_to, 100 * MS):
        trace.add(t, "its.signal", station=station, intersection=intersection, lane=lane,
                  group=group, state=state, spat_ms=0, dist=20.0, speed=0.0, warn=False)


class SignalJoinTest(unittest.TestCase):
    """The light change → HUD join (issue 34): hand-made records of one RSU and two vehicles on
    the lane of signal group 1, one of them with a HUD and an HMI page."""

    T = T0 + 5_000 * MS  # the light change: group 1 goes green (6)
    WORLD_MS = START_MS + 5_000

    def setUp(self):
        self.trace = Trace()
        t = self.T
        # Both show red (3) before the change, at their fixes.
        on_lane(self.trace, 11, t - 900 * MS, t, 3)
        on_lane(self.trace, 12, t - 950 * MS, t, 3)
        # Vehicle 11 has a HUD and a page, up before the change (they drew red).
        self.trace.add(t - 800 * MS, "client.signal", station=11, intersection_id=100,
                       signal_group=1, light="red", frame=10)
        self.trace.add(t - 700 * MS, "hmi.signal", station=11, intersection_id=100,
                       signal_group=1, light="red", shown_ns=t - 699 * MS)

    def green_at(self, station, decoded_ms, published_ms, hud_ms=None, hmi_ms=None):
        t = self.T
        self.trace.add(t + int(decoded_ms * MS), "its.signal", station=station, intersection=100,
                       lane=1, group=1, state=6, spat_ms=0, dist=20.0, speed=0.0, warn=False)
        self.trace.add(t + int(published_ms * MS), "its.mqtt", station=station,
                       topic=f"its/{station}/app/signal", intersection=100, lane=1, state=6,
                       own_ms=0)
        if hud_ms is not None:
            self.trace.add(t + int(hud_ms * MS), "client.signal", station=station,
                           intersection_id=100, signal_group=1, light="green", frame=20)
        if hmi_ms is not None:
            self.trace.add(t + int(hmi_ms * MS), "hmi.signal", station=station,
                           intersection_id=100, signal_group=1, light="green",
                           shown_ns=t + int((hmi_ms + 0.4) * MS))
        # It stays on the lane, green, at its next fixes.
        on_lane(self.trace, station, t + 100 * MS, t + 400 * MS, 6)

    def test_two_vehicles_every_stage(self):
        signal_path(self.trace, self.T, self.WORLD_MS)
        self.green_at(11, 1.0, 1.1, hud_ms=40.0, hmi_ms=5.0)
        self.green_at(12, 1.5, 1.6)  # no HUD, no page
        r, st = run_report(self.trace, "--require", "signals,hud,hmi.signal")
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        want = {"sig.client": 0.2, "sig.emu": 0.3, "sig.rsu_in": 0.1, "sig.spatem": 0.1,
                "light_to_air": 0.7, "sig.hud": 38.9, "light_to_hud": 40.0, "sig.hmi": 3.9,
                "sig.hmi.show": 0.4, "light_to_hmi": 5.0}
        for stage, ms in want.items():
            self.assertEqual(st[stage]["n"], 1, stage)
            self.assertAlmostEqual(st[stage]["p50"], ms, places=6, msg=stage)
        # One sample per vehicle for the legs every vehicle has.
        self.assertEqual(st["light_to_vehicle"]["n"], 2)
        self.assertAlmostEqual(st["light_to_vehicle"]["min"], 1.0, places=6)
        self.assertAlmostEqual(st["light_to_vehicle"]["max"], 1.5, places=6)
        self.assertAlmostEqual(st["sig.air"]["max"], 0.8, places=6)  # 0.7 → 1.5
        self.assertAlmostEqual(st["sig.mqtt"]["mean"], 0.1, places=6)
        self.assertIn("missing along the way: none", r.stdout)

    def test_records_out_of_order_and_written_twice(self):
        signal_path(self.trace, self.T, self.WORLD_MS)
        # The change written twice, and a second forwarding client's later copy.
        self.trace.add(self.T, "server.signal", intersection=100, group=1, state=6,
                       world_ms=self.WORLD_MS, next_change_ms=self.WORLD_MS + 3000)
        self.trace.add(self.T + 3 * MS, "client.signals", world_ms=self.WORLD_MS, groups=4)
        self.green_at(11, 1.0, 1.1, hud_ms=40.0, hmi_ms=5.0)
        # A HUD frame drawing green again later (another group's panel in between) is not
        # the change's: the first one after it counts.
        self.trace.add(self.T + 90 * MS, "client.signal", station=11, intersection_id=100,
                       signal_group=1, light="green", frame=30)
        self.trace.records.reverse()  # files are joined whatever their order
        r, st = run_report(self.trace)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("light changes (issue 34): 1 in sim-server", r.stdout)
        self.assertEqual(st["sig.client"]["n"], 1)
        self.assertAlmostEqual(st["sig.client"]["p50"], 0.2, places=6)
        self.assertEqual(st["light_to_hud"]["n"], 1)
        self.assertAlmostEqual(st["light_to_hud"]["p50"], 40.0, places=6)

    def test_a_missing_stage_is_counted(self):
        # The medium did not see the SPATEM, vehicle 11's HUD never drew green and its page
        # never got it; vehicle 12 never showed green while still on the lane.
        signal_path(self.trace, self.T, self.WORLD_MS, skip=("medium.rx",))
        self.green_at(11, 1.0, 1.1)
        on_lane(self.trace, 12, self.T + 50 * MS, self.T + 400 * MS, 3)
        r, st = run_report(self.trace, "--require", "hud")
        self.assertEqual(r.returncode, 1)
        self.assertIn("stage sig.hud has no records", r.stderr)
        self.assertIn("client.signal 1", r.stdout)
        self.assertIn("hmi.signal 1", r.stdout)
        self.assertIn("its.signal 1", r.stdout)
        self.assertIn("medium.rx (SPATEM) 1", r.stdout)
        self.assertNotIn("sig.air", st)
        self.assertEqual(st["light_to_vehicle"]["n"], 1)  # vehicle 11's
        self.assertEqual(st["sig.rsu_in"]["n"], 1)

    def test_a_vehicle_gone_or_on_another_lane_is_no_sample(self):
        signal_path(self.trace, self.T, self.WORLD_MS)
        self.green_at(11, 1.0, 1.1, hud_ms=40.0, hmi_ms=5.0)
        # Vehicle 12 crossed the stop line before the change: no evaluation of group 1 after.
        # Vehicle 13 waits at group 2 (red), which does not change.
        on_lane(self.trace, 13, self.T - 500 * MS, self.T + 400 * MS, 3, group=2, lane=2)
        r, st = run_report(self.trace)
        self.assertEqual(st["light_to_vehicle"]["n"], 1)
        self.assertIn("1 vehicles had left the lane", r.stdout)
        self.assertIn("missing along the way: none", r.stdout)

    def test_an_rsu_of_another_junction_sends_nothing_on_it(self):
        # RSU 5002 reads the same states (its junction's did not change): no SPATEM on change.
        signal_path(self.trace, self.T, self.WORLD_MS)
        self.trace.add(self.T + int(0.4 * MS), "emu.signals", station=5002,
                       world_ms=self.WORLD_MS, groups=4)
        self.trace.add(self.T + int(0.45 * MS), "its.signal_feed_rx", station=5002, bytes=98)
        self.trace.add(self.T + int(0.5 * MS), "medium.rx", src=5002, bytes=90)
        self.green_at(11, 1.0, 1.1)
        _, st = run_report(self.trace)
        self.assertEqual(st["sig.rsu_in"]["n"], 1)
        self.assertAlmostEqual(st["sig.rsu_in"]["p50"], 0.1, places=6)
        self.assertAlmostEqual(st["light_to_air"]["p50"], 0.7, places=6)

    def test_an_rsu_that_was_behind_reads_the_older_datagram_first(self):
        # The RSU's station stalled from before the emulator's previous (periodic) datagram to
        # 358 ms after the change: it reads that one first (no change: only its overdue periodic
        # SPATEM), then the change's, and sends the SPATEM on change.
        t = self.T
        signal_path(self.trace, t, self.WORLD_MS,
                    skip=("its.signal_feed_rx", "medium.rx", "its.spatem_tx"))
        self.trace.add(t - 998 * MS, "client.signals", world_ms=self.WORLD_MS - 1000, groups=4)
        self.trace.add(t - 997 * MS, "emu.signals", station=5001, world_ms=self.WORLD_MS - 1000,
                       groups=4)
        self.trace.add(t + 358 * MS, "its.signal_feed_rx", station=5001, bytes=98)
        self.trace.add(t + 358 * MS + 50_000, "medium.rx", src=5001, bytes=107)
        self.trace.add(t + 358 * MS + 60_000, "its.spatem_tx", station=5001, on_change=False,
                       bytes=49)
        self.trace.add(t + 358 * MS + 300_000, "its.signal_feed_rx", station=5001, bytes=98)
        self.trace.add(t + 358 * MS + 400_000, "medium.rx", src=5001, bytes=107)
        self.trace.add(t + 358 * MS + 450_000, "its.spatem_tx", station=5001, on_change=True,
                       bytes=49)
        self.green_at(11, 359.0, 359.1)
        _, st = run_report(self.trace)
        self.assertAlmostEqual(st["sig.rsu_in"]["p50"], 358.3 - 0.5, places=6)
        self.assertAlmostEqual(st["sig.spatem"]["p50"], 0.1, places=6)
        self.assertAlmostEqual(st["light_to_air"]["p50"], 358.4, places=6)

    def test_all_does_not_ask_for_signals(self):
        # A run without lights has no signal stages and prints no signal table.
        r, _ = run_report(self.trace, "--require", "signals")
        self.assertEqual(r.returncode, 1)
        self.assertIn("stage light_to_vehicle has no records", r.stderr)
        self.assertNotIn("light changes", r.stdout)


if __name__ == "__main__":
    unittest.main()
