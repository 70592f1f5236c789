#!/usr/bin/env python3
"""A scenario on an OpenDRIVE map through sim-server, a headless sim-client and the network
emulator (issue 17), as real processes on one host:

    tests/map/opendrive_chain_test.py --build DIR

The map (tests/map/hill-georeferenced.xodr) has an 8 m hill and a transverse Mercator
geoReference. One car climbs the hill, one stands on its top. Checks:
  * sim-server loads the map and places it by its geoReference;
  * the sim-client gets the map from the server's Welcome: the file is deleted before it starts;
  * the GPS agents' fixes (NMEA, received here in place of gpsd) are where the geoReference puts
    the cars, with the altitude of the road under them (the climber's rises over the hill);
  * nobody left the drivable lanes (the server's final status line).
Takes about 15 s. Exits 0 when the checks pass, 1 with the reasons.
"""
import argparse
import json
import math
import shutil
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
MAP = ROOT / "tests/map/hill-georeferenced.xodr"
LAT0, LON0 = 48.1, 11.5  # the map's +lat_0, +lon_0: its (0, 0)
DURATION = 10.0


def free_port(kind):
    with socket.socket(socket.AF_INET, kind) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def elevation(s):
    """The map's elevation profile (hill-georeferenced.xodr)."""
    if s < 100:
        return 0.0
    if s < 200:
        d = s - 100
        return 0.0024 * d * d - 0.000016 * d ** 3
    if s < 250:
        return 8.0
    if s < 350:
        d = s - 250
        return 8.0 - 0.0024 * d * d + 0.000016 * d ** 3
    return 0.0


def local_of(lat, lon):
    """x east, y north (m) of a WGS84 position near the map's origin: the tangent plane at the
    origin, which the transverse Mercator with k = 1 matches to a millimetre within 300 m."""
    a, f = 6378137.0, 1 / 298.257223563
    e2 = f * (2 - f)
    phi = math.radians(LAT0)
    w = math.sqrt(1 - e2 * math.sin(phi) ** 2)
    m = a * (1 - e2) / w ** 3  # meridian radius of curvature
    n = a / w                  # prime vertical
    return (math.radians(lon - LON0) * n * math.cos(phi), math.radians(lat - LAT0) * m)


def nmea_degrees(field, digits):
    return float(field[:digits]) + float(field[digits:]) / 60.0


def fixes(sock):
    """GGA fixes received so far: (lat, lon, alt)."""
    out = []
    sock.setblocking(False)
    while True:
        try:
            data = sock.recv(65536).decode(errors="replace")
        except BlockingIOError:
            return out
        for line in data.splitlines():
            f = line.split("*")[0].split(",")
            if f[0] == "$GPGGA" and f[6] == "1":
                lat = nmea_degrees(f[2], 2) * (1 if f[3] == "N" else -1)
                lon = nmea_degrees(f[4], 3) * (1 if f[5] == "E" else -1)
                out.append((lat, lon, float(f[9])))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", required=True)
    args = ap.parse_args()
    bin_dir = Path(args.build) / "bin"
    work = Path(tempfile.mkdtemp(prefix="opendrive-chain-"))
    (work / "maps").mkdir()
    shutil.copy(MAP, work / "maps/hill.xodr")
    scenario = work / "scenario.json"
    scenario.write_text(json.dumps({
        "name": "opendrive-chain",
        "map": {"type": "opendrive", "file": "maps/hill.xodr"},
        "start_time": "2025-06-02T09:00:00Z",
        "vehicles": [
            {"id": "climber", "station_id": 1001, "spawn": {"road": "1", "lane": -1, "s": 90},
             "driver": {"type": "timeline", "steps": [{"t": 0, "throttle": 0.5}]}},
            {"id": "parked", "station_id": 1002,
             "spawn": {"road": "1", "lane": 1, "s": 225},
             "driver": {"type": "timeline", "steps": [{"t": 0, "brake": 1.0}]}},
        ],
    }, indent=2))
    gnss = {}
    for station in (1001, 1002):
        s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        s.bind(("127.0.0.1", 0))
        gnss[station] = s
    stations = work / "stations.json"
    stations.write_text(json.dumps({"stations": [
        {"station_id": st, "address": "127.0.0.1", "gnss_port": s.getsockname()[1],
         "can_port": free_port(socket.SOCK_DGRAM)} for st, s in gnss.items()]}))
    server_port = free_port(socket.SOCK_STREAM)
    states_port = free_port(socket.SOCK_DGRAM)

    procs = {}
    logs = {}
    failures = []
    try:
        for name, cmd in (
                ("network-emulator", [bin_dir / "network-emulator", "--scenario", scenario,
                                      "--listen", f"127.0.0.1:{states_port}",
                                      "--stations", stations, "--can", "udp"]),
                ("sim-server", [bin_dir / "sim-server", "--scenario", scenario, "--bind",
                                "127.0.0.1", "--port", str(server_port), "--duration",
                                str(DURATION)])):
            logs[name] = open(work / f"{name}.log", "w+")
            procs[name] = subprocess.Popen([str(c) for c in cmd], stdout=logs[name],
                                           stderr=subprocess.STDOUT, cwd=ROOT)
        deadline = time.monotonic() + 20
        while b"listening on" not in (work / "sim-server.log").read_bytes():
            if time.monotonic() > deadline or procs["sim-server"].poll() is not None:
                raise SystemExit("sim-server did not come up:\n" +
                                 (work / "sim-server.log").read_text())
            time.sleep(0.05)
        # From here on only the server has the map: the client must get it from Welcome.
        (work / "maps/hill.xodr").unlink()
        logs["sim-client"] = open(work / "sim-client.log", "w+")
        procs["sim-client"] = subprocess.Popen(
            [str(bin_dir / "sim-client"), "--server", f"127.0.0.1:{server_port}", "--scripted",
             "--headless", "--emulator", f"127.0.0.1:{states_port}", "--duration",
             str(DURATION + 5)], stdout=logs["sim-client"], stderr=subprocess.STDOUT, cwd=ROOT)
        procs["sim-server"].wait(timeout=DURATION + 30)
        procs["sim-client"].wait(timeout=30)
    finally:
        for p in procs.values():
            if p.poll() is None:
                p.terminate()
                try:
                    p.wait(timeout=10)
                except subprocess.TimeoutExpired:
                    p.kill()
    text = {name: (work / f"{name}.log").read_text(errors="replace") for name in logs}
    for name, t in text.items():
        print(f"--- {name} (exit {procs[name].returncode})")
        print("\n".join(t.splitlines()[-12:]))

    if procs["sim-server"].returncode != 0:
        failures.append(f"sim-server exited with {procs['sim-server'].returncode}")
    if procs["sim-client"].returncode != 0:
        failures.append(f"sim-client exited with {procs['sim-client'].returncode}")
    if "placed by the geoReference" not in text["sim-server"]:
        failures.append("sim-server did not place the map by its geoReference")
    if "0 departure(s) from the drivable lanes" not in text["sim-server"]:
        failures.append("a car left the drivable lanes")

    got = {st: fixes(s) for st, s in gnss.items()}
    print(f"fixes: {', '.join(f'{st}: {len(f)}' for st, f in got.items())}")
    for st, f in got.items():
        if len(f) < 30:
            failures.append(f"station {st}: only {len(f)} fixes")
    # Each fix: the road under it, from the map's geometry (x = s - 200 along the road).
    worst = 0.0
    for st, f in got.items():
        for lat, lon, alt in f:
            x, y = local_of(lat, lon)
            lane_y = -1.75 if st == 1001 else 1.75
            if abs(y - lane_y) > 0.5:
                failures.append(f"station {st}: fix at y = {y:.2f} m, its lane's centre is at "
                                f"{lane_y}")
                break
            worst = max(worst, abs(alt - elevation(x + 200)))
    print(f"largest |altitude - road elevation|: {worst:.3f} m")
    if worst > 0.15:
        failures.append(f"a fix's altitude is {worst:.3f} m off the road's elevation")
    if got[1002]:
        x, y = local_of(got[1002][-1][0], got[1002][-1][1])
        print(f"parked: x {x:.2f} y {y:.2f} alt {got[1002][-1][2]:.3f}")
        if abs(x - 25.0) > 0.3 or abs(got[1002][-1][2] - 8.0) > 0.1:
            failures.append(f"parked car's fix at x = {x:.2f}, alt {got[1002][-1][2]}: "
                            "want x = 25, alt 8 (the hill's top)")
    if got[1001]:
        rise = got[1001][-1][2] - got[1001][0][2]
        print(f"climber: altitude {got[1001][0][2]:.2f} -> {got[1001][-1][2]:.2f} m")
        if rise < 2.0:
            failures.append(f"the climber's altitude rose by only {rise:.2f} m")

    for s in gnss.values():
        s.close()
    if failures:
        print("FAILED:\n  " + "\n  ".join(failures))
        print(f"logs in {work}")
        return 1
    shutil.rmtree(work, ignore_errors=True)
    print("ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())
