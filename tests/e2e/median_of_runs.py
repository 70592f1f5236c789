#!/usr/bin/env python3
"""The latency table of docs/latency.md from several runs: scripts/report on each run's trace,
then, per stage, the median over the runs of each statistic (n is per run).

    tests/e2e/median_of_runs.py RUN_FOLDER... [--stages S,S,...]

RUN_FOLDER: what tests/e2e/run_scenario.py latency prints as its run folder (or a launcher
--out folder): its newest run-*/trace is reported. Prints a Markdown table (ms) and, for signing
runs, the median signed CAM sizes. Exit 1 when a folder has no trace.
"""
import argparse
import json
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
COLUMNS = ("mean", "p50", "p90", "p99", "max")


def report(folder):
    traces = sorted(Path(folder).glob("run-*/trace")) or \
        ([Path(folder) / "trace"] if (Path(folder) / "trace").is_dir() else [])
    if not traces:
        sys.exit(f"median_of_runs: {folder}: no run-*/trace folder")
    with tempfile.NamedTemporaryFile(suffix=".json") as f:
        subprocess.run([str(ROOT / "scripts/report"), str(traces[-1]), "--json", f.name],
                       check=True, capture_output=True)
        return json.loads(Path(f.name).read_text())


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--stages", help="comma-separated stages (default: every stage with records)")
    args = ap.parse_args()
    reports = [report(r) for r in args.runs]
    stages = args.stages.split(",") if args.stages else \
        [s for s in reports[0]["stages"] if all(s in r["stages"] for r in reports)]
    print(f"| stage | n/run | {' | '.join(COLUMNS)} |")
    print("|---|---|" + "---|" * len(COLUMNS))
    for s in stages:
        rows = [r["stages"][s] for r in reports if s in r["stages"]]
        if not rows:
            print(f"| {s} | - |" + " |" * len(COLUMNS))
            continue
        n = int(statistics.median(r["n"] for r in rows))
        cells = [f"{statistics.median(r[c] for r in rows):.3g}" for c in COLUMNS]
        print(f"| {s} | {n} | {' | '.join(cells)} |")
    sizes = [r["events"].get("signed_cam_bytes") for r in reports if "signed_cam_bytes" in r["events"]]
    if sizes:
        for kind in sorted({k for s in sizes for k in s}):
            packet = statistics.median(s[kind]["packet_p50"] for s in sizes if kind in s)
            security = statistics.median(s[kind]["security_p50"] for s in sizes if kind in s)
            print(f"\nsigned CAM, {kind} signer: GN packet {packet:.0f} octets, of it "
                  f"{security:.0f} of security (medians)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
