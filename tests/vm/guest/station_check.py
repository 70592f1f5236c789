#!/usr/bin/env python3
"""station_check.py RUN_DIR MQTT_LOG STATUS_DIR: the checks of the its-station stage
(test.sh), from what one run of the native launcher (scripts/testbed run
guest/scenario-lcrw.json) left behind:

  RUN_DIR/trace/*.jsonl         trace records (docs/tracing.md) of every program
  RUN_DIR/radio-stats.json, RUN_DIR/*.log
  MQTT_LOG                      `mosquitto_sub -v` output: "topic payload" lines
  STATUS_DIR/status-<id>.json   the last status file with a fix each station wrote during the run

Prints one line per check, "NAME<TAB>0|1<TAB>evidence" (0 = pass), for test.sh's check().
Station 1001 (red) closes in on 1002 (black) ahead on its lane: red must be warned about black
(forward case, TTC < 3 s); black, which has red behind it, never.
"""
import glob
import json
import os
import sys

RED, BLACK = 1001, 1002
# Both drive 8 m/s at the end of the scenario (red has slowed to black's speed).
END_SPEED = 8.0


def records(run_dir):
    out = []
    for path in glob.glob(os.path.join(run_dir, "trace", "*.jsonl")):
        with open(path, errors="replace") as f:
            for line in f:
                try:
                    out.append(json.loads(line))
                except ValueError:
                    pass  # a line cut by a kill
    return out


def read(path):
    try:
        with open(path, errors="replace") as f:
            return f.read()
    except OSError:
        return ""


def main():
    run_dir, mqtt_log, status_dir = sys.argv[1:4]
    res = []

    def check(name, ok, why):
        res.append(f"{name}\t{0 if ok else 1}\t({why})")

    recs = records(run_dir)
    ev = {}
    for r in recs:
        ev.setdefault(r.get("ev"), []).append(r)

    def of(name, **kw):
        return [r for r in ev.get(name, []) if all(r.get(k) == v for k, v in kw.items())]

    # CAN: both stations on SocketCAN (the launcher's --vcan), and the emulator too.
    logs = {s: read(os.path.join(run_dir, f"its-station-{s}.log")) for s in (RED, BLACK)}
    emu = read(os.path.join(run_dir, "network-emulator.log"))
    on_vcan = [s for s, t in logs.items() if "CAN: SocketCAN on vcan0" in t]
    check("stations.can_socketcan", len(on_vcan) == 2 and "CAN transport: SocketCAN" in emu,
          f"its-station on vcan0: {on_vcan}; emulator: "
          f"{'SocketCAN' if 'CAN transport: SocketCAN' in emu else 'not SocketCAN'}")
    bad = {s: sum(1 for line in t.splitlines() if "dropped frame" in line) for s, t in logs.items()}
    frames = sum(r.get("frames", 1) for r in ev.get("emu.can", []))
    check("stations.can_frames_accepted", frames > 0 and not any(bad.values()),
          f"{frames} CAN frames sent by the emulator; 'dropped frame' lines in the stations' "
          f"logs: {bad}")

    # CAMs: sent by each, carried by the medium over hwsim, received into the other's LDM.
    rm = read(os.path.join(run_dir, "radio-medium.log"))
    try:
        with open(os.path.join(run_dir, "radio-stats.json")) as f:
            links = {(l["from"], l["to"]): l for l in json.load(f)["links"]}
    except (OSError, ValueError, KeyError) as e:
        links = {}
        rm += f" (no stats: {e})"
    d12 = links.get((RED, BLACK), {}).get("delivered", 0)
    d21 = links.get((BLACK, RED), {}).get("delivered", 0)
    check("stations.medium_hwsim", "using mac80211_hwsim" in rm and d12 > 0 and d21 > 0,
          f"radio-medium {'on hwsim' if 'using mac80211_hwsim' in rm else 'NOT on hwsim'}; frames "
          f"delivered {RED}->{BLACK} {d12}, {BLACK}->{RED} {d21}")
    for me, other in ((RED, BLACK), (BLACK, RED)):
        tx = len(of("its.cam_tx", station=other))
        rx = len(of("its.cam_rx", station=me, **{"from": other}))
        ldm = len(of("its.ldm", station=me, **{"from": other}))
        try:
            with open(os.path.join(status_dir, f"status-{me}.json")) as f:
                st = json.load(f)
        except (OSError, ValueError):
            st = {}
        nb = {n["station_id"]: n for n in st.get("neighbours", [])}
        speed = nb.get(other, {}).get("speed_mps")
        ok = (rx > 0 and ldm > 0 and other in nb and speed is not None and
              abs(speed - END_SPEED) < 0.5 and set(nb) == {other})
        check(f"cam.ldm_{me}_has_{other}", ok,
              f"{other} sent {tx} CAMs, {me} received {rx}, LDM updates {ldm}; {me}'s status: "
              f"fix {st.get('fix')}, neighbours {sorted(nb)}, {other}'s speed {speed} "
              f"(want {END_SPEED} +- 0.5)")

    # LCRW: red warned about black, forward, TTC < 3 s; black never warned.
    warn_red = [r for r in of("its.lcrw", station=RED, **{"from": BLACK}) if r.get("warn")]
    ttcs = [r["ttc"] for r in warn_red if isinstance(r.get("ttc"), (int, float))]
    assessed = len(of("its.lcrw", station=RED, **{"from": BLACK}))
    check("lcrw.red_warned_about_black", bool(warn_red) and ttcs and min(ttcs) < 3.0,
          f"{len(warn_red)} of {assessed} its.lcrw records of {RED} about {BLACK} warn, lowest "
          f"TTC {min(ttcs) if ttcs else None} s")
    warn_black = [r for r in of("its.lcrw", station=BLACK) if r.get("warn")]
    check("lcrw.black_not_warned", not warn_black and len(of("its.lcrw", station=BLACK)) > 0,
          f"{len(warn_black)} warning records of {len(of('its.lcrw', station=BLACK))} at {BLACK}")

    # The same through the broker (the HMI's view).
    msgs = []
    for line in read(mqtt_log).splitlines():
        topic, _, payload = line.partition(" ")
        try:
            msgs.append((topic, json.loads(payload)))
        except ValueError:
            pass
    cams = sorted({t for t, _ in msgs if "/in/cam/" in t})
    raised = [m for t, m in msgs if t == f"its/{RED}/app/lcrw" and m.get("message", {}).get("event") == "raised"]
    w = raised[0]["message"] if raised else {}
    # Red's braking ends the risk: the warning is cleared again.
    cleared = [m for t, m in msgs if t == f"its/{RED}/app/lcrw" and m.get("message", {}).get("event") == "cleared"]
    c = cleared[-1]["message"] if cleared else {}
    ok = (f"its/{RED}/in/cam/{BLACK}" in cams and f"its/{BLACK}/in/cam/{RED}" in cams and
          w.get("collision_case") == "forward" and w.get("other_station_id") == BLACK and
          bool(cleared) and not any(t == f"its/{BLACK}/app/lcrw" for t, _ in msgs))
    check("lcrw.mqtt", ok,
          f"{len(msgs)} messages; CAM topics {cams}; first warning at {RED}: {w.get('event')} "
          f"{w.get('collision_case')} other={w.get('other_station_id')} ttc={w.get('ttc_s')} "
          f"d={w.get('distance_m')}; then {c.get('event', 'never cleared')} "
          f"({c.get('clear_reason', '-')})")

    # Did the stations keep up with real time? Lag of each station's fix behind the physics
    # step it describes. A fix is dated world start + sim time (docs/time.md); the client's
    # client.forward record of that station and sim time gives the step's wall time.
    starts = ev.get("server.world_start", [])
    world_start_ns = starts[-1]["world_start_ns"] if starts else None
    step_of = {(r["station"], r["sim_ns"]): r["step_ns"] for r in ev.get("client.forward", [])
               if "sim_ns" in r and r.get("step_ns")}
    lags = []
    if world_start_ns is not None:
        for r in ev.get("its.fix", []):
            step = step_of.get((r.get("station"), r["fix_ms"] * 1_000_000 - world_start_ns))
            if step is not None:
                lags.append((r["ts"] - step) / 1e6)
    if lags:
        lags.sort()
        p50, p95, mx = lags[len(lags) // 2], lags[int(len(lags) * 0.95)], lags[-1]
        why = (f"{len(lags)} fixes; fix behind its physics step: median {p50:.0f} ms, "
               f"p95 {p95:.0f} ms, max {mx:.0f} ms")
    else:
        why = "no fixes, no server.world_start or no client.forward records traced"
    res.append(f"info\t-\t{why}")
    # How early the stations were exchanging CAMs, in sim time (red's warning is due at 29.1 s;
    # sim time runs from minus the warm-up): the margin the scenario leaves for the launcher's
    # start under TCG.
    zero = [step for (_, sim_ns), step in step_of.items() if sim_ns == 0]
    if zero:
        t0_ns = min(zero)
        firsts = []
        for me in (RED, BLACK):
            ts = [r["ts"] for r in of("its.ldm", station=me)]
            firsts.append(f"{me}: {(min(ts) - t0_ns) / 1e9:.1f} s" if ts else f"{me}: never")
        res.append(f"info\t-\tfirst LDM update at sim time {', '.join(firsts)}")
    for line in res:
        print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
