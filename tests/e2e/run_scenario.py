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
  latency          scenarios/lcrw-three-vehicles.json for 30 s with tracing: scripts/report must
                   find every stage, state → CAM on the air p99 ≤ 250 ms (the thesis's ceiling)

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
}


def wait_port(port, timeout):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        try:
            with socket.create_connection(("127.0.0.1", port), timeout=0.2):
                return True
        except OSError:
            time.sleep(0.1)
    return False


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("case", choices=sorted(CASES))
    ap.add_argument("--build", required=True)
    args = ap.parse_args()
    scenario, duration = CASES[args.case]
    out = Path(tempfile.mkdtemp(prefix=f"e2e-{args.case}-"))
    out.chmod(0o755)  # the broker drops root and must reach its configuration in there
    testbed = subprocess.Popen(
        [sys.executable, str(ROOT / "scripts/testbed"), "run", str(ROOT / "scenarios" / scenario),
         "--build", args.build, "--duration", str(duration), "--out", str(out)],
        stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True)
    messages = []
    sub = None
    try:
        if not wait_port(1883, 60):
            if testbed.poll() is None:
                os.killpg(testbed.pid, signal.SIGINT)
            log, _ = testbed.communicate(timeout=60)
            print(log)
            raise SystemExit("e2e: the broker never listened on 1883")
        # Line-buffered: a block-buffered pipe would lose the last messages when it is stopped.
        sub = subprocess.Popen(["stdbuf", "-oL", "mosquitto_sub", "-h", "127.0.0.1", "-u", "hmi", "-P", "hmi",
                                "-t", "its/+/app/lcrw", "-t", "its/+/in/cam/+", "-v"],
                               stdout=subprocess.PIPE, text=True)
        log, _ = testbed.communicate(timeout=duration + 120)
    except subprocess.TimeoutExpired:
        os.killpg(testbed.pid, signal.SIGINT)
        log, _ = testbed.communicate(timeout=30)
        print(log)
        raise SystemExit("e2e: the testbed did not stop after its duration")
    finally:
        if sub is not None:
            sub.terminate()
            raw, _ = sub.communicate(timeout=10)
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
    elif args.case == "different-lanes":
        if "its/1001/in/cam/1002" not in cams or "its/1002/in/cam/1001" not in cams:
            failures.append(f"stations did not receive each other's CAMs ({sorted(cams)})")
        if any(w.get("event") == "raised" for _, w in warnings):
            failures.append("a warning was raised for vehicles in different lanes")
    elif args.case == "latency":
        runs = sorted(out.glob("run-*"))
        if not runs:
            failures.append("no run folder")
        else:
            trace = runs[-1] / "trace"
            r = subprocess.run([sys.executable, str(ROOT / "scripts/report"), str(trace),
                                "--out", str(runs[-1] / "histograms"),
                                "--require", "t1,p1,t2,p2,t3.gpsd,t3.stack,p3,air,state_to_cam",
                                "--max-p99", "state_to_cam=250"], capture_output=True, text=True)
            print(r.stdout + r.stderr)
            if r.returncode != 0:
                failures.append("latency report failed its checks")
    for f in failures:
        print(f"e2e {args.case}: FAIL: {f}")
    if failures:
        print(f"e2e: logs in {out}")
        return 1
    print(f"e2e {args.case}: PASS")
    return 0


if __name__ == "__main__":
    sys.exit(main())
