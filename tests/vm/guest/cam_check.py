#!/usr/bin/env python3
"""cam_check.py STATUS_FILE WANT_ID...: an its-station's status file (--status-file) shows a fix,
CAMs sent, exactly the wanted neighbours in its LDM, each with the speed its vehicle was fed.
Prints one line of evidence; exit 0 if so, 1 if not."""
import json
import sys

# The speeds test.sh feeds each vehicle (m/s); CAMs carry 0.01 m/s steps (CDD SpeedValue).
SPEEDS = {11: 10.0, 12: 5.0, 13: 7.5}


def main():
    try:
        with open(sys.argv[1]) as f:
            j = json.load(f)
    except (OSError, ValueError) as e:
        print(f"no status file ({e})")
        return 1
    want = sorted(int(x) for x in sys.argv[2:])
    got = {n["station_id"]: n for n in j.get("neighbours", [])}
    bad = [f"speed of {i} is {got[i].get('speed_mps')}, want {SPEEDS[i]}" for i in want
           if i in got and abs(got[i].get("speed_mps", -1.0) - SPEEDS[i]) > 0.1]
    print(f"fix {j.get('fix')}, CAMs sent {j.get('cams_sent')} received {j.get('cams_received')}, "
          f"neighbours {sorted(got)} (want {want}) {' '.join(bad)}".rstrip())
    ok = j.get("fix") and j.get("cams_sent", 0) > 0 and sorted(got) == want and not bad
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
