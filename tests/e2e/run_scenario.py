#!/usr/bin/env python3
"""End-to-end checks through the whole chain: scripted drivers, sim-server, network emulator
(GPS agents → real gpsd, CAN feeder), radio medium, the ITS stations, LCRW, a real Mosquitto.

    tests/e2e/run_scenario.py CASE --build DIR

CASE is one of:
  frontal          scenarios/lcrw-frontal.json: red is warned about black (case frontal) with
                   TTC < 3 s, and the warning is cleared once red has stopped
  forward          scenarios/lcrw-forward.json: red is warned about black (case forward)
  different-lanes  scenarios/lcrw-different-lanes.json: both stations receive each other's CAMs
                   and no warning is ever raised
  curve            scenarios/lcrw-curve.json (issue 22): on a 150 m ring red is warned about
                   black while the gap along the road is still >= 22 m (10 m/s closing), and
                   exactly once: one raise, one clear
  reversing        scenarios/lcrw-reversing.json (issue 22): red, reversing, is warned about the
                   parked black behind it before TTC 2 s
  latency          scenarios/lcrw-three-vehicles.json for 30 s with tracing and the warned
                   driver's HMI open in headless Chromium (?trace=1): scripts/report must find
                   records for every stage, and state → CAM on the air p99 ≤ 250 ms (the
                   thesis's ceiling)
  foreign-root     scenarios/lcrw-frontal.json signed, for 15 s, with the black car's station
                   from another test PKI ("station": {"pki": "foreign"}; issue 20): neither
                   station's LDM, MQTT CAM topics or LCRW ever hold the other, each counts the
                   other's packets as untrusted_root in its status and says so in its log
  scale            20 scripted vehicles on the ring of tests/e2e/gen_scale_scenario.py for 20 s
                   with tracing (issue 21): scripts/report must find records for every stage
                   from the client's input to the CAM received by the others' LDM and LCRW
                   (no HMI, no warnings on the ring), and state → CAM on the air p99 ≤ 250 ms

A run that fails while the virtual machine's host stole ≥ 10 % of the CPU (steal time,
/proc/stat) is run once more; each run prints the steal.

Runs `scripts/testbed run` (root: network namespaces), subscribes to the broker as the HMI user,
and checks what arrives. Exits 0 when the checks pass, 1 with the reasons otherwise.
"""
import argparse
import json
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

CASES = {
    "frontal": ("lcrw-frontal.json", 40),
    "forward": ("lcrw-forward.json", 30),
    "different-lanes": ("lcrw-different-lanes.json", 30),
    "latency": ("lcrw-three-vehicles.json", 30),
    "curve": ("lcrw-curve.json", 25),
    "reversing": ("lcrw-reversing.json", 25),
    "scale": (None, 20),  # the scenario is generated: SCALE_STATIONS on the ring
    "foreign-root": (None, 15),  # generated: lcrw-frontal with black from another PKI
}
FOREIGN_STATION = 1002
SCALE_STATIONS = 20
# The stages a run without an HMI and without warnings has (scripts/report's ORDER).
SCALE_STAGES = ("t1,t1.send,p1,fanout,t3.period,t2,p2,t3.gpsd,t3.uptake,t3.stack,p3,t4,p4.t5,air,"
                "rx.ldm,rx.lcrw,fix_state_to_cam,state_to_cam")


def wait_port(port, timeout):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        try:
            with socket.create_connection(("127.0.0.1", port), timeout=0.2):
                return True
        except OSError:
            time.sleep(0.1)
    return False


def cpu_times():
    """(total, steal) jiffies of the whole machine, from /proc/stat."""
    fields = [int(x) for x in open("/proc/stat").readline().split()[1:]]
    return sum(fields[:8]), fields[7] if len(fields) > 7 else 0


# A virtual machine's host may take the CPU away (steal time): at 46 % the three-vehicle run
# missed its latency bound and raised no warning at all. The checks are about the testbed, not
# the host: a run that failed while the host stole this much is run again once, and both runs
# are printed.
STEAL_RETRY_PERCENT = 10.0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("case", choices=sorted(CASES))
    ap.add_argument("--build", required=True)
    ap.add_argument("--security", choices=["none", "signed", "signed-permissive"],
                    help="run the case with this security mode (scripts/testbed --security)")
    args = ap.parse_args()
    rc, steal = run_case(args)
    if rc != 0 and steal >= STEAL_RETRY_PERCENT:
        print(f"e2e {args.case}: the host stole {steal:.0f} % of the CPU during the run "
              f"(≥ {STEAL_RETRY_PERCENT:.0f} %): running once more")
        rc, steal = run_case(args)
    return rc


def foreign_root_failures(out, messages):
    """The foreign-root case's checks: the stations of two PKIs ignore each other, and say so."""
    failures = []
    statuses = {}
    for status in sorted(out.glob("run-*/station-*.status.json")):
        st = json.loads(status.read_text())
        statuses[st["station_id"]] = st
        sec = st.get("security", {})
        print(f"e2e: {status.name}: security {sec.get('mode')} {sec.get('verify')}, "
              f"neighbours {[n['station_id'] for n in st.get('neighbours', [])]}")
    if set(statuses) != {1001, FOREIGN_STATION}:
        return [f"status files of stations {sorted(statuses)}, not 1001 and {FOREIGN_STATION}"]
    for sid, other in ((1001, FOREIGN_STATION), (FOREIGN_STATION, 1001)):
        st = statuses[sid]
        verify = st.get("security", {}).get("verify", {})
        if st.get("security", {}).get("mode") != "signed":
            failures.append(f"station {sid}: security mode {st.get('security', {}).get('mode')}")
        if any(n["station_id"] == other for n in st.get("neighbours", [])):
            failures.append(f"station {sid}'s LDM holds the station of the other PKI, {other}")
        if verify.get("ok", 0) != 0:
            failures.append(f"station {sid} verified {verify['ok']} packet(s) of the other PKI")
        if verify.get("untrusted_root", 0) == 0:
            failures.append(f"station {sid} never named the other's packets untrusted_root "
                            f"({verify})")
        logs = list(out.glob(f"run-*/its-station-{sid}.log"))
        said = logs and "dropping received packets: untrusted_root" in logs[0].read_text(
            errors="replace")
        if not said:
            failures.append(f"station {sid}'s log never says it drops untrusted_root packets")
        if any(t == f"its/{sid}/in/cam/{other}" for t, _ in messages):
            failures.append(f"station {sid} published a CAM of {other} on MQTT")
    if any(t.endswith("/app/lcrw") and m.get("event") == "raised" for t, m in messages):
        failures.append("an LCRW warning was raised about a station nobody may trust")
    return failures


def run_case(args):
    """One run of the case. Returns (exit status, % of CPU time the host stole meanwhile)."""
    scenario, duration = CASES[args.case]
    cpu0 = cpu_times()
    out = Path(tempfile.mkdtemp(prefix=f"e2e-{args.case}-"))
    out.chmod(0o755)  # the broker drops root and must reach its configuration in there
    if args.case == "foreign-root":
        scenario_file = out / "lcrw-frontal-foreign.json"
        doc = json.loads((ROOT / "scenarios/lcrw-frontal.json").read_text())
        doc["security"] = "signed"
        for v in doc["vehicles"]:
            if v["station_id"] == FOREIGN_STATION:
                v["station"] = {"pki": "foreign"}
        scenario_file.write_text(json.dumps(doc, indent=2))
        scenario_file.chmod(0o644)
    elif scenario is None:
        # Long enough to outlast the stations' start-up and the measured window.
        scenario_file = out / f"scale-{SCALE_STATIONS}.json"
        subprocess.run([sys.executable, str(ROOT / "tests/e2e/gen_scale_scenario.py"),
                        str(SCALE_STATIONS), "--out", str(scenario_file),
                        "--duration", str(duration + 60)], check=True)
        scenario_file.chmod(0o644)
    else:
        scenario_file = ROOT / "scenarios" / scenario
    testbed = subprocess.Popen(
        [sys.executable, str(ROOT / "scripts/testbed"), "run", str(scenario_file),
         "--build", args.build, "--duration", str(duration), "--out", str(out)] +
        (["--security", args.security] if args.security else []),
        stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True)
    messages = []
    sub = None
    hmi = None
    hmi_log = ""
    try:
        if not wait_port(1883, 60):
            if testbed.poll() is None:
                os.killpg(testbed.pid, signal.SIGINT)
            log, _ = testbed.communicate(timeout=60)
            print(log)
            raise SystemExit("e2e: the broker never listened on 1883")
        # Line-buffered: a block-buffered pipe would lose the last messages when it is stopped.
        # Into a file, read at the end: a pipe read only then fills within seconds of CAMs, and
        # the broker drops what a subscriber that stopped reading is sent at QoS 0.
        sub_out = open(out / "mqtt-messages.txt", "w")
        sub = subprocess.Popen(["stdbuf", "-oL", "mosquitto_sub", "-h", "127.0.0.1", "-u", "hmi", "-P", "hmi",
                                "-t", "its/+/app/lcrw", "-t", "its/+/in/cam/+", "-v"],
                               stdout=sub_out, text=True)
        if args.case == "latency":
            # The red car's driver looks at the HMI; its page reports each warning's receipt.
            hmi = subprocess.Popen(["node", str(ROOT / "hmi/tools/headless_hmi.mjs"), "--url",
                                    "http://127.0.0.1:9001/", "--station", "1001", "--trace"],
                                   stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        log, _ = testbed.communicate(timeout=duration + 120)
    except subprocess.TimeoutExpired:
        os.killpg(testbed.pid, signal.SIGINT)
        log, _ = testbed.communicate(timeout=30)
        print(log)
        raise SystemExit("e2e: the testbed did not stop after its duration")
    finally:
        if hmi is not None:
            hmi.terminate()
            try:
                hmi_log, _ = hmi.communicate(timeout=20)
            except subprocess.TimeoutExpired:
                hmi.kill()
                hmi_log, _ = hmi.communicate()
            print(hmi_log)
        if sub is not None:
            sub.terminate()
            sub.wait(timeout=10)
            sub_out.close()
            raw = (out / "mqtt-messages.txt").read_text(errors="replace")
            for line in raw.splitlines():
                topic, _, payload = line.partition(" ")
                try:
                    messages.append((topic, json.loads(payload)))
                except json.JSONDecodeError:
                    pass
    print(log)
    failures = []
    if testbed.returncode != 0:
        failures.append(f"scripts/testbed exited with {testbed.returncode}")

    if args.case == "foreign-root":
        failures += foreign_root_failures(out, messages)
    elif args.security in ("signed", "signed-permissive"):
        # Every station verified the others' signed CAMs and refused none.
        for status in sorted(out.glob("run-*/station-*.status.json")):
            sec = json.loads(status.read_text()).get("security", {})
            verify = sec.get("verify", {})
            print(f"e2e: {status.name}: security {sec.get('mode')} {verify}")
            if sec.get("mode") != args.security:
                failures.append(f"{status.name}: security mode {sec.get('mode')}")
            if verify.get("ok", 0) == 0:
                failures.append(f"{status.name}: no packet verified")
            # unknown_signer is normal at a start: a digest heard before the AT, held and
            # verified when the AT comes.
            refused = {k: v for k, v in verify.items() if k not in ("ok", "unknown_signer")}
            if refused:
                failures.append(f"{status.name}: verification failures {refused}")

    warnings = [(t, m["message"]) for t, m in messages if t.endswith("/app/lcrw")]
    cams = {t for t, _ in messages if "/in/cam/" in t}
    print(f"e2e: {len(warnings)} LCRW message(s), CAM topics seen: {sorted(cams)}")
    for t, w in warnings[:20]:
        print(f"  {t}: {w.get('event')} {w.get('collision_case')} other={w.get('other_station_id')} "
              f"ttc={w.get('ttc_s')} d={w.get('distance_m')}")

    if args.case in ("frontal", "forward"):
        want = args.case
        raised = [w for _, w in warnings if w.get("event") == "raised" and
                  w.get("station_id") == 1001 and w.get("other_station_id") == 1002 and
                  w.get("collision_case") == want]
        if not raised:
            failures.append(f"no {want} warning raised at station 1001 about 1002")
        elif not (raised[0].get("ttc_s") is not None and raised[0]["ttc_s"] < 3.0):
            failures.append(f"warning raised with TTC {raised[0].get('ttc_s')}, not < 3 s")
        if args.case == "frontal" and not any(w.get("event") == "cleared" for _, w in warnings):
            failures.append("the frontal warning was never cleared after red stopped")
    elif args.case == "curve":
        about = [w for _, w in warnings
                 if w.get("station_id") == 1001 and w.get("other_station_id") == 1002]
        raised = [w for w in about if w.get("event") == "raised"]
        cleared = [w for w in about if w.get("event") == "cleared"]
        if len(raised) != 1 or len(cleared) != 1:
            failures.append(f"{len(raised)} raise(s) and {len(cleared)} clear(s) at 1001 about "
                            "1002, not one each")
        if raised and not (raised[0].get("distance_m") or 0) >= 22.0:
            failures.append(f"first warning at a gap of {raised[0].get('distance_m')} m along the "
                            "road, not >= 22 m")
    elif args.case == "reversing":
        raised = [w for _, w in warnings if w.get("event") == "raised" and
                  w.get("station_id") == 1001 and w.get("other_station_id") == 1002]
        if not raised:
            failures.append("no warning raised at the reversing station 1001 about 1002")
        elif not (raised[0].get("ttc_s") is not None and 2.0 <= raised[0]["ttc_s"] < 3.0):
            failures.append(f"warning raised with TTC {raised[0].get('ttc_s')}, not in [2, 3) s")
    elif args.case == "different-lanes":
        if "its/1001/in/cam/1002" not in cams or "its/1002/in/cam/1001" not in cams:
            failures.append(f"stations did not receive each other's CAMs ({sorted(cams)})")
        if any(w.get("event") == "raised" for _, w in warnings):
            failures.append("a warning was raised for vehicles in different lanes")
    elif args.case in ("latency", "scale"):
        runs = sorted(out.glob("run-*"))
        if not runs:
            failures.append("no run folder")
        else:
            trace = runs[-1] / "trace"
            # Its own interpreter (Debian's, with matplotlib), not this test's.
            r = subprocess.run([str(ROOT / "scripts/report"), str(trace),
                                "--out", str(runs[-1] / "histograms"),
                                "--require", ("all" + (",security" if args.security in
                                                       ("signed", "signed-permissive") else "")
                                              if args.case == "latency" else SCALE_STAGES),
                                "--max-p99", "state_to_cam=250"], capture_output=True, text=True)
            print(r.stdout + r.stderr)
            if r.returncode != 0:
                failures.append("latency report failed its checks")
        if args.case == "scale":
            heard = {t.split("/")[1] for t in cams}
            if len(heard) < SCALE_STATIONS:
                failures.append(f"only {len(heard)} of {SCALE_STATIONS} stations received CAMs")
        elif "hmi: station 1001 connected" not in hmi_log:
            failures.append("the headless HMI of station 1001 never connected to the broker")
    cpu1 = cpu_times()
    steal = 100.0 * (cpu1[1] - cpu0[1]) / max(1, cpu1[0] - cpu0[0])
    print(f"e2e {args.case}: the host stole {steal:.1f} % of the CPU time during the run")
    for f in failures:
        print(f"e2e {args.case}: FAIL: {f}")
    if failures:
        print(f"e2e: logs in {out}")
        return 1, steal
    if args.case in ("latency", "scale"):
        print(f"e2e {args.case}: run folder {out} (tests/e2e/median_of_runs.py takes it)")
    print(f"e2e {args.case}: PASS")
    return 0, steal


if __name__ == "__main__":
    sys.exit(main())
