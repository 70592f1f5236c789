#!/usr/bin/env python3
"""Frame senders and independent decoders for the VM test (tests/vm/guest/test.sh).

Written apart from the project's C++ on purpose: the checks decode what the programs put on
the kernel's interfaces with a second, independent reading of the formats (docs/wire.md,
common/can/vehicle.dbc, 802.11 radiotap), so a bug shared by encoder and decoder cannot pass.

  vmtool.py state  --to 127.0.0.1:4700 --station 11 [--x 10 --y 0 --speed 12.5 ...]
  vmtool.py can-read --iface vcan0 --seconds 4 --expect-speed-kmh 45 ...
  vmtool.py raw-send --iface wlan0 --count 20 --tag A
  vmtool.py raw-recv --iface wlan0 --seconds 6 --ready FILE --out FILE
  vmtool.py mon-recv --iface tbvmmon --seconds 6 --ready FILE --out FILE
  vmtool.py mon-count --iface tbrmmon --seconds 60 --ready FILE --stop FILE --out FILE

Every command prints one JSON line and exits 0 when it did its job, 1 when a check failed,
2 on a usage or system error.
"""
import argparse
import json
import math
import os
import select
import socket
import struct
import sys
import time

ETH_P_ALL = 0x0003
ETH_P_GEONET = 0x8947  # ETSI EN 302 636-4-1 GeoNetworking over ITS-G5
MARKER = b"TBVM-PROBE"

# docs/wire.md: vehicle-state batch datagram (version 3) of one state: magic, version 3,
# count 1, the world's start time (Unix ns, 0 = unknown: the emulator takes the scenario's
# start_time), then the 156-byte record body; 168 bytes little-endian.
STATE_FMT = "<2sBBqIQqqq3d3f3f3f3ffff4ffffBbHf"
assert struct.calcsize(STATE_FMT) == 168

LIGHT_BITS = {"left": 0, "right": 1, "hazard": 2, "low": 3, "high": 4, "brake": 5,
              "reverse": 6, "fog": 7}


def emit(obj, ok):
    print(json.dumps(obj, sort_keys=True), flush=True)
    sys.exit(0 if ok else 1)


def cmd_state(a):
    host, port = a.to.rsplit(":", 1)
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    lights = 0
    for name in filter(None, a.lights.split(",")):
        if name not in LIGHT_BITS:
            print(f"vmtool state: unknown light '{name}'", file=sys.stderr)
            sys.exit(2)
        lights |= 1 << LIGHT_BITS[name]
    yaw = math.radians(90.0 - a.heading_deg)  # heading clockwise from north -> ENU yaw
    step_ns = int(a.interval * 1e9)
    for i in range(a.count):
        tick = a.tick0 + i
        now = time.time_ns()
        # With --start-unix, sim time follows the wall clock from the scenario's start_time, as
        # in a live run; otherwise it advances one --interval per state.
        sim_ns = now - a.start_unix * 10**9 if a.start_unix is not None else tick * step_ns
        v = (a.speed * math.cos(yaw), a.speed * math.sin(yaw), 0.0)
        flags = (1 if a.speed < 0 else 0)
        data = struct.pack(
            STATE_FMT, b"VS", 3, 1,
            a.start_unix * 10**9 if a.start_unix is not None else 0,
            a.station, tick, sim_ns, now, now,
            a.x, a.y, 0.0, 0.0, 0.0, yaw, *v, 0.0, 0.0, 0.0, a.accel, 0.0, 0.0,
            a.speed, 0.0, a.steer_rad, *([a.speed] * 4), a.throttle, a.brake, 0.0, flags,
            a.gear, lights, a.rpm)
        sock.sendto(data, (host, int(port)))
        time.sleep(a.interval)
    emit({"sent": a.count, "station": a.station, "to": a.to}, True)


def crc8_sae_j1850(data):
    # poly 0x1D, init 0xFF, xorout 0xFF (the vehicle.dbc checksum)
    crc = 0xFF
    for b in data:
        crc ^= b
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1D) & 0xFF if crc & 0x80 else (crc << 1) & 0xFF
    return crc ^ 0xFF


def intel(data, start, length, signed=False, factor=1.0):
    raw = (int.from_bytes(data, "little") >> start) & ((1 << length) - 1)
    if signed and raw & (1 << (length - 1)):
        raw -= 1 << length
    return raw * factor


def motorola(data, start, length, factor=1.0):
    # DBC Motorola: start is the MSB in sawtooth numbering; walk towards the LSB.
    raw, bit = 0, start
    for _ in range(length):
        raw = (raw << 1) | ((data[bit // 8] >> (bit % 8)) & 1)
        bit = bit - 1 if bit % 8 else bit + 15
    return raw * factor


# id -> (name, dlc, alive counter start bit)
MESSAGES = {0x100: ("VehicleSpeed", 8, 48), 0x101: ("WheelSpeeds", 8, 48),
            0x120: ("Dynamics", 8, 48), 0x130: ("Steering", 4, 16),
            0x140: ("Powertrain", 8, 48), 0x200: ("Lights", 3, 8)}


def decode(can_id, d):
    if can_id == 0x100:
        return {"speed_kmh": intel(d, 0, 16, factor=0.01), "direction": intel(d, 16, 2)}
    if can_id == 0x101:
        return {"wheel_fl_kmh": motorola(d, 7, 12, 0.1), "wheel_rr_kmh": motorola(d, 35, 12, 0.1)}
    if can_id == 0x120:
        return {"long_accel": intel(d, 16, 16, True, 0.001)}
    if can_id == 0x140:
        return {"throttle_pct": intel(d, 0, 8, factor=0.4), "gear": intel(d, 16, 4, True),
                "rpm": intel(d, 24, 16, factor=0.25)}
    if can_id == 0x200:
        return {k: intel(d, i, 1) for k, i in (("ind_left", 0), ("ind_right", 1),
                                                ("hazard", 2), ("brake", 3), ("low", 4))}
    return {}


def cmd_can_read(a):
    s = socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW)
    s.bind((a.iface,))
    if a.ready:
        open(a.ready, "w").close()
    frames, bad, last, counts, gaps = 0, [], {}, {}, 0
    deadline = time.monotonic() + a.seconds
    while time.monotonic() < deadline and (a.max_frames == 0 or frames < a.max_frames):
        wait = max(0.0, deadline - time.monotonic())
        if frames:
            wait = min(wait, a.idle)  # the sender has stopped
        r, _, _ = select.select([s], [], [], wait)
        if not r:
            if frames:
                break
            continue
        can_id, dlc, data = struct.unpack("=IB3x8s", s.recv(16))
        can_id &= 0x1FFFFFFF
        frames += 1
        if can_id not in MESSAGES:
            bad.append(f"unknown id 0x{can_id:X}")
            continue
        name, want_dlc, alive_bit = MESSAGES[can_id]
        d = data[:dlc]
        if dlc != want_dlc:
            bad.append(f"{name}: dlc {dlc}, want {want_dlc}")
            continue
        if crc8_sae_j1850(d[:-1]) != d[-1]:
            bad.append(f"{name}: checksum 0x{d[-1]:02X}, want 0x{crc8_sae_j1850(d[:-1]):02X}")
        alive = intel(d, alive_bit, 4)
        if name in counts and alive != (counts[name] + 1) % 16:
            gaps += 1
        counts[name] = alive
        last[name] = decode(can_id, d)
    s.close()
    out = {"iface": a.iface, "frames": frames, "messages": sorted(last), "last": last,
           "alive_gaps": gaps, "errors": bad[:10]}
    want = {"VehicleSpeed": ("speed_kmh", a.expect_speed_kmh, 0.01),
            "WheelSpeeds": ("wheel_fl_kmh", a.expect_speed_kmh, 0.1),
            "Powertrain": ("gear", a.expect_gear, 0)}
    fails = list(bad[:3])
    if frames == 0:
        fails.append("no CAN frame received")
    for msg in MESSAGES.values():
        if frames and msg[0] not in last:
            fails.append(f"no {msg[0]} frame")
    for msg, (field, value, tol) in want.items():
        if value is not None and msg in last and abs(last[msg][field] - value) > tol + 1e-9:
            fails.append(f"{msg}.{field} = {last[msg][field]}, want {value}")
    if a.expect_lights is not None and "Lights" in last:
        for k in a.expect_lights.split(","):
            if k and last["Lights"].get(k) != 1:
                fails.append(f"Lights.{k} not set")
    if gaps:
        fails.append(f"{gaps} alive-counter gaps")
    out["fails"] = fails
    emit(out, not fails)


def l2_socket(iface, proto):
    s = socket.socket(socket.AF_PACKET, socket.SOCK_RAW, socket.htons(proto))
    s.bind((iface, proto))
    return s


def cmd_raw_send(a):
    s = l2_socket(a.iface, ETH_P_GEONET)
    src = s.getsockname()[4]
    for seq in range(a.count):
        payload = MARKER + a.tag.encode()[:1] + struct.pack("!I", seq) + bytes(32)
        s.send(b"\xff" * 6 + src + struct.pack("!H", ETH_P_GEONET) + payload)
        time.sleep(a.interval)
    emit({"iface": a.iface, "sent": a.count, "tag": a.tag, "src": src.hex(":")}, True)


def collect(s, a, parse):
    if a.ready:
        open(a.ready, "w").close()
    seen = {}
    deadline = time.monotonic() + a.seconds
    stop_file = a.stop
    while time.monotonic() < deadline:
        if stop_file and os.path.exists(stop_file):
            break
        r, _, _ = select.select([s], [], [], 0.2)
        if not r:
            continue
        frame = s.recv(4096)
        i = frame.find(MARKER)
        if i < 0 or len(frame) < i + len(MARKER) + 5:
            continue
        info = parse(frame, i)
        if info is None:
            continue
        tag = chr(frame[i + len(MARKER)])
        seq = struct.unpack_from("!I", frame, i + len(MARKER) + 1)[0]
        seen.setdefault(tag, {"seqs": set(), **info})["seqs"].add(seq)
    return {t: {**{k: v for k, v in d.items() if k != "seqs"}, "count": len(d["seqs"])}
            for t, d in seen.items()}


def cmd_raw_recv(a):
    s = l2_socket(a.iface, ETH_P_GEONET)

    def parse(frame, i):
        # Ethernet framing above mac80211: marker right after the 14-byte header.
        if i != 14 or struct.unpack_from("!H", frame, 12)[0] != ETH_P_GEONET:
            return None
        return {"src": frame[6:12].hex(":")}
    got = collect(s, a, parse)
    with open(a.out, "w") as f:
        json.dump({"iface": a.iface, "tags": got}, f)
    emit({"iface": a.iface, "tags": got}, True)


def cmd_mon_recv(a):
    s = l2_socket(a.iface, ETH_P_ALL)

    def parse(frame, i):
        # radiotap header (length at bytes 2..3, little-endian), then the 802.11 data frame
        # with an LLC/SNAP header carrying the ethertype.
        if len(frame) < 4 or frame[0] != 0:
            return None
        rt_len = struct.unpack_from("<H", frame, 2)[0]
        hdr = frame[rt_len:]
        if len(hdr) < 24 or (hdr[0] >> 2) & 0x3 != 2:  # type 2 = data
            return None
        snap = frame.rfind(b"\xaa\xaa\x03\x00\x00\x00\x89\x47", rt_len, i)
        if snap < 0:
            return None
        # OCB frames carry the wildcard BSSID ff:ff:ff:ff:ff:ff (IEEE 802.11-2016 11.23).
        return {"src": hdr[10:16].hex(":"), "bssid": hdr[16:22].hex(":")}
    got = collect(s, a, parse)
    with open(a.out, "w") as f:
        json.dump({"iface": a.iface, "tags": got}, f)
    emit({"iface": a.iface, "tags": got}, True)


def cmd_mon_count(a):
    """Any GeoNetworking traffic (the stations' CAMs) the monitor radio sees: 802.11 data
    frames with LLC/SNAP 0x8947, counted per transmitter address."""
    # The medium may make its monitor radio after the stations' ones and bring it up later:
    # wait for it to be up (IFF_UP) a little.
    flags = f"/sys/class/net/{a.iface}/flags"
    for _ in range(150):
        try:
            with open(flags) as f:
                if int(f.read(), 16) & 0x1:
                    break
        except (OSError, ValueError):
            pass
        time.sleep(0.1)
    s = l2_socket(a.iface, ETH_P_ALL)
    if a.ready:
        open(a.ready, "w").close()
    count = {}
    deadline = time.monotonic() + a.seconds
    while time.monotonic() < deadline and not (a.stop and os.path.exists(a.stop)):
        r, _, _ = select.select([s], [], [], 0.2)
        if not r:
            continue
        try:
            frame = s.recv(4096)
        except OSError:  # ENETDOWN while the medium still tunes the radio
            time.sleep(0.1)
            continue
        if len(frame) < 4 or frame[0] != 0:
            continue
        rt_len = struct.unpack_from("<H", frame, 2)[0]
        hdr = frame[rt_len:]
        if len(hdr) < 32 or (hdr[0] >> 2) & 0x3 != 2:
            continue
        if frame.find(b"\xaa\xaa\x03\x00\x00\x00\x89\x47", rt_len) < 0:
            continue
        src = hdr[10:16].hex(":")
        count[src] = count.get(src, 0) + 1
    with open(a.out, "w") as f:
        json.dump({"iface": a.iface, "frames": count}, f)
    emit({"iface": a.iface, "frames": count}, True)


def main():
    p = argparse.ArgumentParser(prog="vmtool.py")
    sub = p.add_subparsers(dest="cmd", required=True)
    st = sub.add_parser("state")
    st.add_argument("--to", required=True)
    st.add_argument("--station", type=int, required=True)
    st.add_argument("--x", type=float, default=0.0)
    st.add_argument("--y", type=float, default=0.0)
    st.add_argument("--heading-deg", type=float, default=90.0)
    st.add_argument("--speed", type=float, default=0.0)
    st.add_argument("--accel", type=float, default=0.0)
    st.add_argument("--steer-rad", type=float, default=0.0)
    st.add_argument("--throttle", type=float, default=0.0)
    st.add_argument("--brake", type=float, default=0.0)
    st.add_argument("--gear", type=int, default=1)
    st.add_argument("--rpm", type=float, default=800.0)
    st.add_argument("--lights", default="")
    st.add_argument("--count", type=int, default=1)
    st.add_argument("--interval", type=float, default=0.02)
    st.add_argument("--tick0", type=int, default=1)
    st.add_argument("--start-unix", type=int, help="the scenario's start_time, Unix seconds")
    cr = sub.add_parser("can-read")
    cr.add_argument("--iface", required=True)
    cr.add_argument("--seconds", type=float, default=5.0)
    cr.add_argument("--max-frames", type=int, default=0)
    cr.add_argument("--idle", type=float, default=2.0, help="stop after this long without frames")
    cr.add_argument("--ready")
    cr.add_argument("--expect-speed-kmh", type=float)
    cr.add_argument("--expect-gear", type=int)
    cr.add_argument("--expect-lights")
    rs = sub.add_parser("raw-send")
    rs.add_argument("--iface", required=True)
    rs.add_argument("--count", type=int, default=20)
    rs.add_argument("--interval", type=float, default=0.02)
    rs.add_argument("--tag", default="A")
    for name in ("raw-recv", "mon-recv"):
        rr = sub.add_parser(name)
        rr.add_argument("--iface", required=True)
        rr.add_argument("--seconds", type=float, default=10.0)
        rr.add_argument("--ready")
        rr.add_argument("--stop", help="stop early once this file exists")
        rr.add_argument("--out", required=True)
    mc = sub.add_parser("mon-count")
    mc.add_argument("--iface", required=True)
    mc.add_argument("--seconds", type=float, default=60.0)
    mc.add_argument("--ready")
    mc.add_argument("--stop", help="stop early once this file exists")
    mc.add_argument("--out", required=True)
    a = p.parse_args()
    try:
        {"state": cmd_state, "can-read": cmd_can_read, "raw-send": cmd_raw_send,
         "raw-recv": cmd_raw_recv, "mon-recv": cmd_mon_recv,
         "mon-count": cmd_mon_count}[a.cmd](a)
    except OSError as e:
        print(f"vmtool {a.cmd}: {e}", file=sys.stderr)
        sys.exit(2)


if __name__ == "__main__":
    main()
