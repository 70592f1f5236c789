#!/usr/bin/env python3
"""The scale measurement of issue 21: N stations on the ring of gen_scale_scenario.py, several
runs, one table.

    flock /tmp/testbed-heavy.lock tests/e2e/scale_runs.py N [--runs 3] [--duration 30]
          [--build build/release] [--radio-forwarding auto|kernel|user] [--perf DIR]
          [--station-arg=ARG ...] [--json FILE] [--keep]
          [--full K [--hosts H]] [--gen-arg=ARG ...]

With --full K only the first K vehicles are full stations (a process and a gpsd each), the
others pooled in station-hosts (issue 33); --gen-arg passes the map and channel options on to
gen_scale_scenario.py.

Each run is `scripts/testbed run` of the generated scenario (root: network namespaces) for
--duration seconds once every station is up (the launcher's "running" line), then
`scripts/report` on its trace. Per run, over the measured window only:

* load: the 1-minute load average at the window's start and end; steal and the machine's CPU
  split (user, system, softirq, idle) from /proc/stat;
* CPU per station per second, by process kind (sim-server, sim-client, network-emulator,
  radio-medium, gpsd, its-station, station-host, mosquitto): utime + stime from /proc/PID/stat
  of the run's processes, in ms of CPU per second of wall time per station (10 = 1 % of a
  core): per full station for its-station and gpsd, per pooled station for station-host, per
  vehicle for the programs every vehicle shares;
* latency (ms, scripts/report): state change → CAM on the air (state_to_cam), p4.t5 (taken in
  by the medium → decoded at a neighbour), air, t2, t3.gpsd;
* CAMs lost: every CAM put on the air (its.cam_tx) in the window's middle (from 3 s after its
  start to 3 s before its end, so that every receiver was up) against the neighbours that
  decoded it (its.cam_rx): expected N − 1 each on an ideal channel; the same with the full
  stations alone as receivers (pooled stations trace what they send, not what they receive);
  the full stations' decoded CAMs against what the medium says it delivered to them (the
  measure on a channel that culls by range); and the radio medium's own statistics (dropped
  deliveries);
* the kernel's receive backlogs (/proc/net/softnet_stat): frames dropped because a CPU's
  backlog was full, at start-up, in the window and at the stop, which is where the kernel's
  forwarding loses frames that radio-stats counts as a station's full queue.

The latency figures come from the window's trace records only (start-up and stop left out).

Then the median over the runs of each figure. --perf DIR records `perf record -a -g` of the
whole machine during the first run's window and prints the top entries by process and those of
radio-medium, network-emulator and its-station.
Exit status 0 (it measures; the targets are checked by whoever reads the table).
"""
import argparse
import json
import os
import re
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
HZ = os.sysconf("SC_CLK_TCK")
# /proc/PID/comm is cut to 15 characters.
KINDS = {"sim-server": "sim", "sim-client": "client", "network-emulato": "emulator",
         "radio-medium": "medium", "gpsd": "gpsd", "its-station": "station",
         "station-host": "host", "mosquitto": "broker"}
KIND_ORDER = ["sim", "client", "emulator", "medium", "gpsd", "station", "host", "broker", "other"]
# What a kind's CPU is counted per: a full station's own processes per full station, a
# station-host's per pooled station, what every vehicle shares per vehicle.
PER_FULL = {"gpsd", "station"}
PER_POOLED = {"host"}
STAGES = ["state_to_cam", "p4.t5", "air", "t2", "t3.gpsd"]
EDGE_S = 3.0


def machine_cpu():
    """Jiffies of the whole machine: user, nice, system, idle, iowait, irq, softirq, steal."""
    return [int(x) for x in open("/proc/stat").readline().split()[1:9]]


def softnet():
    """The kernel's per-CPU receive backlogs, summed: (frames dropped because a CPU's backlog
    held net.core.netdev_max_backlog already, times net_rx_action ran out of budget). A veth
    hands each frame it sends to its peer through the sending CPU's backlog, so with the
    kernel's forwarding one CAM to 49 receivers is 49 frames in one backlog; a drop there is
    counted by the sending veth (radio-stats' kernel_dropped) as if the receiver's queue were
    full."""
    dropped = squeezed = 0
    for line in open("/proc/net/softnet_stat"):
        f = line.split()
        dropped += int(f[1], 16)
        squeezed += int(f[2], 16)
    return dropped, squeezed


def loadavg():
    return float(open("/proc/loadavg").read().split()[0])


def processes():
    """pid → (ppid, comm, utime + stime jiffies) of every process."""
    out = {}
    for d in os.listdir("/proc"):
        if not d.isdigit():
            continue
        try:
            raw = open(f"/proc/{d}/stat").read()
        except OSError:
            continue
        comm = raw[raw.index("(") + 1:raw.rindex(")")]
        rest = raw[raw.rindex(")") + 2:].split()
        out[int(d)] = (int(rest[1]), comm, int(rest[11]) + int(rest[12]))
    return out


def descendants(root, procs):
    children = defaultdict(list)
    for pid, (ppid, _, _) in procs.items():
        children[ppid].append(pid)
    seen, todo = set(), [root]
    while todo:
        p = todo.pop()
        for c in children.get(p, []):
            if c not in seen:
                seen.add(c)
                todo.append(c)
    return seen


def snapshot(root):
    procs = processes()
    mine = {p: procs[p] for p in descendants(root, procs)}
    return {"t": time.monotonic(), "load": loadavg(), "cpu": machine_cpu(), "procs": mine,
            "softnet": softnet()}


def window(a, b, counts):
    """@p counts: {"all": vehicles, "full": full stations, "pooled": pooled stations}."""
    wall = b["t"] - a["t"]
    per_kind = defaultdict(float)
    for pid, (_, comm, ticks) in b["procs"].items():
        before = a["procs"].get(pid)
        if before is None or before[1] != comm:
            continue  # started inside the window: not one of the run's long-lived programs
        per_kind[KINDS.get(comm, "other")] += (ticks - before[2]) / HZ
    cpu = [y - x for x, y in zip(a["cpu"], b["cpu"])]
    total = max(1, sum(cpu))
    return {
        "wall_s": wall,
        "load": (a["load"], b["load"]),
        "machine_pct": {"user": 100 * (cpu[0] + cpu[1]) / total, "system": 100 * cpu[2] / total,
                        "softirq": 100 * (cpu[5] + cpu[6]) / total, "idle": 100 * (cpu[3] + cpu[4]) / total,
                        "steal": 100 * cpu[7] / total},
        # ms of CPU per second per station: per full station for a full station's own
        # processes, per pooled station for the station-hosts, per vehicle for the rest
        "cpu_ms_per_station_s": {k: 1000 * v / wall / max(1, counts[
            "full" if k in PER_FULL else "pooled" if k in PER_POOLED else "all"])
            for k, v in per_kind.items()},
        "cpu_total_ms_per_s": 1000 * sum(per_kind.values()) / wall,
    }


def cam_loss(trace_dir, start_unix_ns, end_unix_ns, stations, full_ids):
    """(CAMs sent in the window's middle, deliveries expected, deliveries decoded), counting
    every receiver on an ideal channel; then the same for the full stations alone as receivers
    (pooled stations do not trace what they receive: hundreds of them would write a million
    records a second)."""
    tx, rx = {}, defaultdict(set)
    for f in Path(trace_dir).glob("*.jsonl"):
        with open(f, errors="replace") as fh:
            for line in fh:
                if '"its.cam_tx"' not in line and '"its.cam_rx"' not in line:
                    continue
                try:
                    r = json.loads(line)
                except json.JSONDecodeError:
                    continue
                if r.get("ev") == "its.cam_tx":
                    tx[(r["station"], r["gdt"])] = r["ts"]
                elif r.get("ev") == "its.cam_rx":
                    rx[(r["from"], r["gdt"])].add(r["station"])
    lo, hi = start_unix_ns + EDGE_S * 1e9, end_unix_ns - EDGE_S * 1e9
    sent = [k for k, ts in tx.items() if lo <= ts <= hi]
    got = sum(len(rx.get(k, ())) for k in sent)
    full_expected = sum(len(full_ids) - (k[0] in full_ids) for k in sent)
    full_got = sum(len(rx.get(k, set()) & full_ids) for k in sent)
    return len(sent), len(sent) * (stations - 1), got, full_expected, full_got


def full_rx_against_medium(trace_dir, stats, full_ids):
    """What the full stations decoded against what the medium delivered to them, over the whole
    run, from each sender: (delivered, decoded). This is the measure on a channel that does not
    deliver everything to everyone (range culling)."""
    delivered = defaultdict(int)
    for link in stats.get("links", []):
        if link["to"] in full_ids:
            delivered[(link["from"], link["to"])] += link["delivered"]
    decoded = defaultdict(int)
    for f in Path(trace_dir).glob("*.jsonl"):
        with open(f, errors="replace") as fh:
            for line in fh:
                if '"its.cam_rx"' not in line:
                    continue
                try:
                    r = json.loads(line)
                except json.JSONDecodeError:
                    continue
                if r.get("station") in full_ids:
                    decoded[(r["from"], r["station"])] += 1
    return (sum(delivered.values()),
            sum(min(decoded[k], n) for k, n in delivered.items()))


def perf_top(data, sort, comms=None, limit=15):
    """The top entries of `perf report` (self time, no call graph), one line each."""
    argv = ["perf", "report", "-i", str(data), "--stdio", "--no-children", "--sort", sort,
            "--percent-limit", "0.5", "-g", "none"]
    if comms:  # shares of that process's own samples
        argv += ["--comms", ",".join(comms), "--percentage", "relative"]
    r = subprocess.run(argv, capture_output=True, text=True)
    lines = [" ".join(l.split()[:-2] if l.rstrip().endswith("-") else l.split())
             for l in r.stdout.splitlines() if l.strip() and not l.startswith("#")]
    return lines[:limit]


def perf_report(data):
    """What the whole machine did in the window (by process), then the top symbols of the
    medium, the emulator and the stations."""
    out = ["by process:"] + perf_top(data, "comm", limit=12)
    for comm in ("radio-medium", "network-emulato", "its-station", "station-host"):
        out += [f"{comm}:"] + perf_top(data, "dso,symbol", [comm])
    return out


def windowed_trace(trace_dir, out_dir, start_ns, end_ns):
    """Copies the records of the measured window: the start-up of fifty stations and their stop
    are no steady state."""
    out_dir.mkdir(exist_ok=True)
    ts = re.compile(rb'"ts":(\d+)')
    for f in Path(trace_dir).glob("*.jsonl"):
        with open(f, "rb") as src, open(out_dir / f.name, "wb") as dst:
            for line in src:
                m = ts.search(line)
                if m and start_ns <= int(m.group(1)) <= end_ns:
                    dst.write(line)


def realtime_of(args, index):
    """The --realtime-priority of run @p index (from 0): the list's values in turn; None: the
    launcher's own default."""
    values = [int(v) for v in args.realtime_priority.split(",") if v.strip()]
    return values[index % len(values)] if values else None


def one_run(args, scenario, index):
    out = Path(tempfile.mkdtemp(prefix=f"scale-{args.stations}-"))
    out.chmod(0o755)
    softnet_before = softnet()
    # The window is timed here: the launcher stops its programs at once when its duration is up,
    # so its own end would cut the window short. Given a margin, it is stopped with SIGINT.
    proc = subprocess.Popen(
        [sys.executable, str(ROOT / "scripts/testbed"), "run", str(scenario), "--build", args.build,
         "--duration", str(args.duration + 60), "--out", str(out)] +
        (["--hosts", str(args.hosts)] if args.hosts else []) +
        (["--radio-forwarding", args.radio_forwarding] if args.radio_forwarding else []) +
        (["--shared-nice", str(args.shared_nice)] if args.shared_nice else []) +
        # 0 is passed too: it turns the launcher's default of 50 off.
        (["--realtime-priority", str(rt)] if (rt := realtime_of(args, index)) is not None
         else []) +
        [f"--station-arg={a}" for a in args.station_arg],
        stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True)
    a = b = None
    a_unix = b_unix = 0
    perf = None
    log = []
    try:
        for line in proc.stdout:
            log.append(line)
            if "running;" in line:
                break
        if proc.poll() is None and log and "running;" in log[-1]:
            a, a_unix = snapshot(proc.pid), time.time_ns()
            if args.perf and index == 0:
                # The whole machine: the stations do the kernel's forwarding in their own sends.
                Path(args.perf).mkdir(parents=True, exist_ok=True)
                perf = subprocess.Popen(
                    ["perf", "record", "-a", "-g", "-o", str(Path(args.perf) / "scale.data")],
                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            time.sleep(args.duration)
            b, b_unix = snapshot(proc.pid), time.time_ns()
            if perf is not None:
                perf.send_signal(signal.SIGINT)
            os.killpg(proc.pid, signal.SIGINT)
        for line in proc.stdout:
            log.append(line)
        proc.wait(timeout=120)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGINT)
            proc.wait(timeout=60)
        if perf is not None:
            perf.wait(timeout=120)
    if a is None or b is None:
        sys.stdout.write("".join(log[-40:]))
        raise SystemExit(f"scale_runs: run {index + 1} never reached its measured window")
    result = window(a, b, {"all": args.stations, "full": args.full_count,
                           "pooled": args.stations - args.full_count})
    after = softnet()
    # Where the backlogs dropped: the start-up (before the window), the window, the stop.
    result["backlog_dropped"] = {"start": a["softnet"][0] - softnet_before[0],
                                 "window": b["softnet"][0] - a["softnet"][0],
                                 "stop": after[0] - b["softnet"][0]}
    result["backlog_squeezed"] = {"start": a["softnet"][1] - softnet_before[1],
                                  "window": b["softnet"][1] - a["softnet"][1],
                                  "stop": after[1] - b["softnet"][1]}
    run_dir = sorted(out.glob("run-*"))[-1]
    windowed_trace(run_dir / "trace", run_dir / "trace-window", a_unix, b_unix)
    rep = subprocess.run([str(ROOT / "scripts/report"), str(run_dir / "trace-window"), "--json",
                          str(run_dir / "report.json")], capture_output=True, text=True)
    if rep.returncode != 0 or not (run_dir / "report.json").exists():
        sys.stdout.write(rep.stdout + rep.stderr)
        raise SystemExit(f"scale_runs: scripts/report failed on {run_dir / 'trace-window'}")
    stages = json.loads((run_dir / "report.json").read_text())["stages"]
    result["stages"] = {s: stages[s] for s in STAGES if s in stages}
    sent, expected, got, full_expected, full_got = cam_loss(
        run_dir / "trace", a_unix, b_unix, args.stations, args.full_ids)
    result["cams"] = {"sent": sent, "expected": expected, "decoded": got,
                      "full_expected": full_expected, "full_decoded": full_got}
    stats_file = run_dir / "radio-stats.json"
    if stats_file.exists():
        stats = json.loads(stats_file.read_text())
        totals = stats["totals"]
        # With the kernel's forwarding, a receiver's full queue drops in the kernel.
        result["medium"] = {"sent": totals["sent"], "delivered": totals["delivered"],
                            "dropped": sum(totals["dropped"].values()) +
                            sum(stats.get("kernel_dropped", {}).values()),
                            "tap_missed": stats.get("tap_missed", 0)}
        if stats.get("links"):
            delivered, decoded = full_rx_against_medium(run_dir / "trace", stats, args.full_ids)
            result["cams"]["full_medium_delivered"] = delivered
            result["cams"]["full_medium_decoded"] = decoded
    if perf is not None:
        result["perf_top"] = perf_report(Path(args.perf) / "scale.data")
    result["dir"] = str(out)
    if not args.keep:
        subprocess.run(["rm", "-rf", str(out)])
    return result


def fmt_run(i, r):
    st = r["stages"]
    m = r["machine_pct"]
    c = r["cpu_ms_per_station_s"]
    s2c, med = st.get("state_to_cam", {}), st.get("p4.t5", {})
    cams = r["cams"]
    # Pooled stations trace no receptions: their deliveries cannot be counted as decoded.
    lost = (cams["expected"] - cams["decoded"] if not cams.get("full_expected") or
            cams["full_expected"] == cams["expected"] else "n/a (pooled receivers)")
    full = ""
    if cams.get("full_expected"):
        full = (f"\n  full stations decoded {100 * cams['full_decoded'] / cams['full_expected']:.2f} % "
                f"of the window's CAMs ({cams['full_decoded']} of {cams['full_expected']}; "
                "all of them on an ideal channel)")
    if cams.get("full_medium_delivered"):
        full += (f"; {100 * cams['full_medium_decoded'] / cams['full_medium_delivered']:.2f} % of "
                 f"what the medium delivered to them ({cams['full_medium_decoded']} of "
                 f"{cams['full_medium_delivered']}, whole run)")
    rt = f" [--realtime-priority {r['realtime']}]" if r.get("realtime") is not None else ""
    return (f"run {i}{rt}: load {r['load'][0]:.1f}→{r['load'][1]:.1f}, steal {m['steal']:.1f} %, "
            f"CPU user {m['user']:.0f} / sys {m['system']:.0f} / softirq {m['softirq']:.0f} / "
            f"idle {m['idle']:.0f} %\n"
            f"  state→CAM mean {s2c.get('mean', float('nan')):.1f} p50 {s2c.get('p50', float('nan')):.1f} "
            f"p99 {s2c.get('p99', float('nan')):.1f} ms (n {s2c.get('n', 0)}); medium p4.t5 "
            f"p50 {med.get('p50', float('nan')):.2f} p99 {med.get('p99', float('nan')):.2f} ms; "
            f"CAM deliveries lost {lost} of {r['cams']['expected']}"
            + (f"; medium dropped {r['medium']['dropped']}" if "medium" in r else "") + full + "\n"
            "  kernel backlogs dropped (start-up / window / stop): "
            + " / ".join(str(r["backlog_dropped"][k]) for k in ("start", "window", "stop"))
            + "; squeezed " + " / ".join(str(r["backlog_squeezed"][k]) for k in ("start", "window", "stop"))
            + "\n"
            f"  CPU ms per station per s: " +
            ", ".join(f"{k} {c[k]:.2f}" for k in KIND_ORDER if k in c) +
            f"; all {r['cpu_total_ms_per_s'] / 10:.0f} % of a core")


def median(xs):
    xs = [x for x in xs if x is not None]
    return statistics.median(xs) if xs else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("stations", type=int)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--duration", type=float, default=30.0, help="measured seconds per run")
    ap.add_argument("--build", default=str(ROOT / "build/release"))
    ap.add_argument("--radio-forwarding", choices=["auto", "kernel", "user"],
                    help="passed on to scripts/testbed run (default: its own, auto)")
    ap.add_argument("--shared-nice", type=int, default=0,
                    help="passed on to scripts/testbed run")
    ap.add_argument("--realtime-priority", default="",
                    help="P[,P...]: passed on to scripts/testbed run (default: the launcher's "
                         "own, 50); run k takes the k-th value, cycling (0,50 alternates for a "
                         "comparison side by side)")
    ap.add_argument("--perf", help="perf record -a -g of the first run's window into this folder "
                                   "(scale.data); prints the top entries")
    ap.add_argument("--station-arg", action="append", default=[], metavar="ARG",
                    help="passed to every its-station (scripts/testbed run --station-arg)")
    ap.add_argument("--full", type=int, metavar="K",
                    help="only the first K vehicles are full stations, the others pooled in "
                         "station-hosts (gen_scale_scenario.py --full; default: all full)")
    ap.add_argument("--hosts", type=int, default=0,
                    help="station-hosts for the pooled stations (scripts/testbed run --hosts)")
    ap.add_argument("--gen-arg", action="append", default=[], metavar="ARG",
                    help="one more argument for gen_scale_scenario.py (repeatable; write "
                         "--gen-arg=--radius=600)")
    ap.add_argument("--json", help="write every run's figures here")
    ap.add_argument("--keep", action="store_true", help="keep each run's folder (logs, trace)")
    args = ap.parse_args()
    if os.geteuid() != 0:
        raise SystemExit("scale_runs: needs root (scripts/testbed makes network namespaces)")
    work = Path(tempfile.mkdtemp(prefix="scale-scenario-"))
    work.chmod(0o755)
    scenario = work / f"scale-{args.stations}.json"
    # Long enough to outlast the start-up of every station and the measured window.
    subprocess.run([sys.executable, str(ROOT / "tests/e2e/gen_scale_scenario.py"),
                    str(args.stations), "--out", str(scenario),
                    "--duration", str(args.duration + 30 + args.stations)] +
                   (["--full", str(args.full)] if args.full is not None else []) + args.gen_arg,
                   check=True)
    scenario.chmod(0o644)
    vehicles = json.loads(scenario.read_text())["vehicles"]
    args.full_ids = {v["station_id"] for v in vehicles
                     if v.get("station", {}).get("kind", "full") != "pooled"}
    args.full_count = len(args.full_ids)
    runs = []
    for i in range(args.runs):
        r = one_run(args, scenario, i)
        if args.realtime_priority:
            r["realtime"] = realtime_of(args, i)
        runs.append(r)
        print(fmt_run(i + 1, r), flush=True)
        for line in r.get("perf_top", []):
            print("   perf " + line)
    if args.json:
        Path(args.json).write_text(json.dumps(runs, indent=1))

    def col(f):
        return median([f(r) for r in runs])
    kinds = (f" ({args.full_count} full, {args.stations - args.full_count} pooled)"
             if args.full_count != args.stations else "")
    print(f"\n{args.stations} stations{kinds}, {args.runs} runs of {args.duration:.0f} s, medians of the runs:")
    print("| figure | median | runs |")
    print("|---|---|---|")
    rows = [("load 1 min (start→end)", None,
             ", ".join(f"{r['load'][0]:.1f}→{r['load'][1]:.1f}" for r in runs)),
            ("steal %", lambda r: r["machine_pct"]["steal"], None),
            ("machine CPU busy %", lambda r: 100 - r["machine_pct"]["idle"] - r["machine_pct"]["steal"], None),
            ("  of which softirq %", lambda r: r["machine_pct"]["softirq"], None)]
    for s in ("state_to_cam", "p4.t5"):
        for q in ("mean", "p50", "p99"):
            rows.append((f"{s} {q} (ms)", lambda r, s=s, q=q: r["stages"].get(s, {}).get(q), None))
    for s in ("t2", "t3.gpsd", "air"):
        rows.append((f"{s} p99 (ms)", lambda r, s=s: r["stages"].get(s, {}).get("p99"), None))
    rows.append(("kernel backlogs dropped, start-up / window / stop", None,
                 ", ".join("/".join(str(r["backlog_dropped"][k]) for k in ("start", "window", "stop"))
                           for r in runs)))
    rows.append(("CAM deliveries lost (every station traces its receptions)",
                 lambda r: r["cams"]["expected"] - r["cams"]["decoded"]
                 if args.full_count == args.stations else None, None))
    rows.append(("full stations: % of the window's CAMs decoded (ideal channel)",
                 lambda r: 100 * r["cams"]["full_decoded"] / r["cams"]["full_expected"]
                 if r["cams"].get("full_expected") else None, None))
    rows.append(("full stations: % of the medium's deliveries decoded",
                 lambda r: 100 * r["cams"]["full_medium_decoded"] / r["cams"]["full_medium_delivered"]
                 if r["cams"].get("full_medium_delivered") else None, None))
    for k in KIND_ORDER:
        rows.append((f"CPU {k}, ms per station per s",
                     lambda r, k=k: r["cpu_ms_per_station_s"].get(k, 0.0), None))
    rows.append(("CPU of all the run's processes, % of a core", lambda r: r["cpu_total_ms_per_s"] / 10, None))
    for name, f, text in rows:
        if f is not None:
            vals = [f(r) for r in runs]
            text = ", ".join("-" if v is None else f"{v:.2f}" for v in vals)
            print(f"| {name} | {col(f):.2f} | {text} |")
        else:
            print(f"| {name} | | {text} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
