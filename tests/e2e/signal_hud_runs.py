#!/usr/bin/env python3
"""Issue 34's figure "light change in the sim → state at the driver's HUD": several runs of
scenarios/signals-junction-hud.json with HUDs watching, one table.

    tests/e2e/signal_hud_runs.py [--runs 3] [--duration 240] [--build build/release]
          [--watch wait1 --watch wait2 ...] [--width 640 --height 360] [--fps 60]
          [--hmi] [--json FILE] [--view-nice N] [--testbed-arg=ARG ...]

Each run is `scripts/testbed run` of the scenario (root: network namespaces) under
/tmp/testbed-heavy.lock (taken per run, released between runs), with its traces in one folder.
Once sim-server listens, a watching sim-client per --watch vehicle opens the 3D view on a
virtual X display (Xvfb, Mesa's llvmpipe) following that car (--follow: its HUD's signal panel),
reads the stations' messages from the broker (--mqtt) and forwards nothing; each traces the
frames that drew another light (client.signal). With --hmi the web HMI pages of the same
vehicles' stations are opened in headless Chromium with ?trace=1 (hmi.signal). Then
`scripts/report` joins the light changes (docs/tracing.md, "Signals"): per run n, median, p90,
p99 and max of every stage, what was missing along the way, the 1-minute load at start and end,
how busy the machine was and what the host stole (/proc/stat); then the median over the runs.
Exit status 0 (it measures; whoever reads the table checks the target, p99 ≤ 150 ms).
"""
import argparse
import fcntl
import json
import os
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCENARIO = ROOT / "scenarios/signals-junction-hud.json"
LOCK = "/tmp/testbed-heavy.lock"
STAGES = ["sig.client", "sig.emu", "sig.rsu_in", "sig.spatem", "sig.air", "sig.mqtt", "sig.hud",
          "sig.hmi", "light_to_air", "light_to_vehicle", "light_to_hud", "light_to_hmi"]


def machine_cpu():
    """Jiffies of the whole machine: user, nice, system, idle, iowait, irq, softirq, steal."""
    return [int(x) for x in open("/proc/stat").readline().split()[1:9]]


def loadavg():
    return float(open("/proc/loadavg").read().split()[0])


def wait_port(port, timeout, proc):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if proc.poll() is not None:
            return False
        with socket.socket() as s:
            s.settimeout(0.5)
            if s.connect_ex(("127.0.0.1", port)) == 0:
                return True
        time.sleep(0.2)
    return False


def free_display():
    for n in range(90, 200):
        if not Path(f"/tmp/.X{n}-lock").exists() and not Path(f"/tmp/.X11-unix/X{n}").exists():
            return n
    raise SystemExit("signal_hud_runs: no free X display number in :90-:199")


def stop(p, sig=signal.SIGTERM, timeout=15):
    if p is None or p.poll() is not None:
        return
    p.send_signal(sig)
    try:
        p.wait(timeout=timeout)
    except subprocess.TimeoutExpired:
        p.kill()
        p.wait()


def one_run(args, index, out):
    trace = out / f"trace-{index}"
    trace.mkdir(parents=True)
    trace.chmod(0o777)  # the launcher's processes drop root (the broker)
    display = free_display()
    xvfb = subprocess.Popen(["Xvfb", f":{display}", "-screen", "0", "1920x1080x24", "-nolisten",
                             "tcp"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    env = dict(os.environ, DISPLAY=f":{display}")
    watchers, hmi, testbed = [], None, None
    lock = open(LOCK, "w")
    fcntl.flock(lock, fcntl.LOCK_EX)
    try:
        testbed = subprocess.Popen(
            [sys.executable, str(ROOT / "scripts/testbed"), "run", str(SCENARIO), "--build",
             args.build, "--duration", str(args.duration), "--out", str(out),
             "--trace-dir", str(trace)] + args.testbed_arg,
            stdout=open(out / f"testbed-{index}.log", "w"), stderr=subprocess.STDOUT,
            start_new_session=True)
        if not wait_port(2000, 120, testbed):
            raise SystemExit(f"signal_hud_runs: sim-server never listened (see {out}/testbed-{index}.log)")
        for vid in args.watch:
            watchers.append(subprocess.Popen(
                ["nice", "-n", str(args.view_nice), str(Path(args.build) / "bin/sim-client"), "--server", "127.0.0.1:2000",
                 "--view", "3d", "--follow", vid, "--mqtt", "127.0.0.1:1883", "--no-forward",
                 "--name", f"hud-{vid}", "--width", str(args.width), "--height", str(args.height),
                 "--fps", str(args.fps), "--trace", str(trace / f"sim-client-hud-{vid}.jsonl")],
                env=env, stdout=open(out / f"hud-{vid}-{index}.log", "w"),
                stderr=subprocess.STDOUT))
        if args.hmi:
            stations = [str(v["station_id"]) for v in json.loads(SCENARIO.read_text())["vehicles"]
                        if v["id"] in args.watch]
            if wait_port(9001, 60, testbed):
                hmi = subprocess.Popen(
                    ["node", str(ROOT / "hmi/tools/headless_hmi.mjs"), "--url",
                     "http://127.0.0.1:9001/", "--trace"] +
                    [a for s in stations for a in ("--station", s)],
                    stdout=open(out / f"hmi-{index}.log", "w"), stderr=subprocess.STDOUT)
        load0, cpu0 = loadavg(), machine_cpu()
        testbed.wait(timeout=args.duration + 180)
        load1, cpu1 = loadavg(), machine_cpu()
    finally:
        stop(hmi)
        for w in watchers:
            stop(w)
        if testbed is not None and testbed.poll() is None:
            os.killpg(testbed.pid, signal.SIGINT)
            testbed.wait(timeout=60)
        fcntl.flock(lock, fcntl.LOCK_UN)
        lock.close()
        stop(xvfb)
    delta = [b - a for a, b in zip(cpu0, cpu1)]
    total = max(1, sum(delta))
    stats_file = out / f"report-{index}.json"
    r = subprocess.run([str(ROOT / "scripts/report"), str(trace), "--json", str(stats_file)],
                       capture_output=True, text=True)
    (out / f"report-{index}.txt").write_text(r.stdout + r.stderr)
    report = json.loads(stats_file.read_text()) if stats_file.exists() else {}
    return {"load": [load0, load1],
            "busy": 100 * (total - delta[3] - delta[4] - delta[7]) / total,
            "steal": 100 * delta[7] / total,
            "stages": {s: v for s, v in report.get("stages", {}).items() if s in STAGES},
            "signals": report.get("events", {}).get("signal_changes", {}),
            "report": str(out / f"report-{index}.txt")}


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--duration", type=float, default=240)
    ap.add_argument("--build", default=str(ROOT / "build/release"))
    ap.add_argument("--watch", action="append", help="vehicle whose HUD a watcher shows "
                    "(repeatable; default wait1 wait2 wait3)")
    ap.add_argument("--width", type=int, default=640)
    ap.add_argument("--height", type=int, default=360)
    ap.add_argument("--fps", type=float, default=60)
    ap.add_argument("--testbed-arg", action="append", default=[], metavar="ARG",
                    help="one more argument for scripts/testbed run (repeatable; write "
                         "--testbed-arg=--shared-nice=-5)")
    ap.add_argument("--view-nice", type=int, default=0,
                    help="nice value of the watching views (software GL is the CPU's main user)")
    ap.add_argument("--hmi", action="store_true", help="also open their stations' web HMI pages")
    ap.add_argument("--json", help="write the runs' figures here")
    args = ap.parse_args()
    args.watch = args.watch or ["wait1", "wait2", "wait3"]
    out = Path(tempfile.mkdtemp(prefix="signal-hud-runs-"))
    out.chmod(0o755)
    print(f"signal_hud_runs: {args.runs} run(s) of {args.duration:g} s, HUDs of "
          f"{', '.join(args.watch)} at {args.width}x{args.height}, {args.fps:g} fps; in {out}")
    runs = []
    for i in range(args.runs):
        r = one_run(args, i, out)
        runs.append(r)
        sig = r["signals"]
        print(f"run {i}: load {r['load'][0]:.2f}→{r['load'][1]:.2f}, machine {r['busy']:.0f} % "
              f"busy, steal {r['steal']:.2f} %; {sig.get('changes', 0)} light changes, "
              f"{sig.get('samples', 0)} at vehicles, missing {sig.get('missing', {}) or 'none'} "
              f"({r['report']})")
        for s in STAGES:
            t = r["stages"].get(s)
            if t:
                print(f"  {s:<18} n {t['n']:>5}  p50 {t['p50']:8.3f}  p90 {t['p90']:8.3f}  "
                      f"p99 {t['p99']:8.3f}  max {t['max']:8.3f}")
    print("\nmedian of the runs (ms):")
    for s in STAGES:
        have = [r["stages"][s] for r in runs if s in r["stages"]]
        if not have:
            continue
        med = {k: statistics.median(t[k] for t in have) for k in ("n", "p50", "p90", "p99", "max")}
        print(f"  {s:<18} n {med['n']:>7.0f}  p50 {med['p50']:8.3f}  p90 {med['p90']:8.3f}  "
              f"p99 {med['p99']:8.3f}  max {med['max']:8.3f}   (p99 per run: "
              + ", ".join(f"{t['p99']:.1f}" for t in have) + ")")
    if args.json:
        Path(args.json).write_text(json.dumps(runs, indent=2))
    print(f"(the runs' traces stay in {out}: scripts/report TRACE)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
