#!/bin/bash
# The checks inside the VM (run by /sbin/tb-vm-init from the payload disk mounted on /tb).
# Prints one "CHECK <name>: PASS|FAIL <why>" line per check and, last, the line the host script
# looks for: "TB-VM-RESULT: PASS (n checks)" or "TB-VM-RESULT: FAIL (names of failed checks)".
set -u
export PATH=/tb/bin:/usr/sbin:/usr/bin:/sbin:/bin
G=/tb/guest
T=/tmp/tbvm
mkdir -p "$T"
# Options from the host script (tests/vm/run writes /tb/options).
if [[ -f /tb/options ]]; then . /tb/options; fi
tool() { python3 "$G/vmtool.py" "$@"; }

passed=0
failed=()
check() { # check NAME OK(0/1) WHY
  if [[ $2 == 0 ]]; then
    echo "CHECK $1: PASS $3"
    passed=$((passed + 1))
  else
    echo "CHECK $1: FAIL $3"
    failed+=("$1")
  fi
}
finish() {
  echo "---- guest logs ----"
  for f in "$T"/*.log "$T"/*.json; do
    [[ -s $f ]] || continue
    echo "== $f"
    tail -n 40 "$f"
  done
  echo "--------------------"
  echo "stage end: $SECONDS s into the test script"
  if ((${#failed[@]} == 0 && passed > 0)); then
    echo "TB-VM-RESULT: PASS ($passed checks, kernel $(uname -r))"
  else
    echo "TB-VM-RESULT: FAIL (${failed[*]:-no check ran}; $passed passed)"
  fi
}
trap finish EXIT

# wait_for FILE SECONDS [PATTERN]: until FILE exists (and holds PATTERN).
wait_for() {
  local i
  for ((i = 0; i < $2 * 10; i++)); do
    if [[ -e $1 ]] && { [[ -z ${3:-} ]] || grep -q "$3" "$1"; }; then return 0; fi
    sleep 0.1
  done
  return 1
}
# stop PID SECONDS: SIGTERM, wait, the process's exit code in $stop_rc (137 if it had to be killed).
stop() {
  local i
  kill -TERM "$1" 2>/dev/null
  for ((i = 0; i < $2 * 10; i++)); do
    kill -0 "$1" 2>/dev/null || break
    sleep 0.1
  done
  if kill -0 "$1" 2>/dev/null; then
    kill -KILL "$1"
  fi
  wait "$1"
  stop_rc=$?
}

echo "guest: kernel $(uname -r), $(nproc) CPUs"
# Nothing configures the VM's own loopback: the programs talk over 127.0.0.1.
ip link set lo up

# ---- modules ------------------------------------------------------------------------------
modprobe vcan && modprobe can-raw
check modules.can $? "(vcan, can-raw)"
# radios=0: the medium makes its own radios; the module's two default ones would be extra.
modprobe mac80211_hwsim radios=0
check modules.hwsim $? "(mac80211_hwsim radios=0)"
n=$(ls /sys/class/ieee80211 | wc -l)
[[ $n == 0 ]]
check hwsim.no_default_radios $? "($n radios before radio-medium)"

# The scenario: 11 at x=10, 12 at 210, 13 at 460 on a straight road; range 300 m, so 11–12
# (200 m) and 12–13 (250 m) hear each other and 11–13 (450 m) do not.
S=$G/scenario-range.json
for ns in tbvm1 tbvm2 tbvm3; do ip netns add $ns && ip -n $ns link set lo up; done

echo "stage can: starts $SECONDS s into the test script"
# ---- CAN: the network emulator's feeder on vcan in station namespaces ----------------------
for ns in tbvm1 tbvm2; do
  ip -n $ns link add vcan0 type vcan && ip -n $ns link set vcan0 up
done
cat >"$T/stations.json" <<EOF
{"stations": [
  {"station_id": 11, "netns": "tbvm1", "can_interface": "vcan0"},
  {"station_id": 12, "netns": "tbvm2", "can_interface": "vcan0"}
]}
EOF
ip netns exec tbvm1 python3 "$G/vmtool.py" can-read --iface vcan0 --seconds 30 \
  --ready "$T/can1.ready" --expect-speed-kmh 45 --expect-gear 3 --expect-lights low,brake \
  >"$T/can1.json" 2>"$T/can1.err" &
can1=$!
ip netns exec tbvm2 python3 "$G/vmtool.py" can-read --iface vcan0 --seconds 30 \
  --ready "$T/can2.ready" --expect-speed-kmh 18 --expect-gear 2 --expect-lights hazard,ind_left,ind_right \
  >"$T/can2.json" 2>"$T/can2.err" &
can2=$!
ip netns exec tbvm1 candump -n 6 -T 20000 -ta vcan0 >"$T/candump.log" 2>&1 &
candump=$!
wait_for "$T/can1.ready" 20 && wait_for "$T/can2.ready" 20
network-emulator --scenario "$S" --stations "$T/stations.json" --can vcan \
  --dbc /tb/share/vehicle.dbc --listen 127.0.0.1:4700 --status-interval 0 \
  >"$T/network-emulator.log" 2>&1 &
emu=$!
sleep 1
if ! kill -0 $emu 2>/dev/null; then
  wait $emu
  check can.emulator_starts 1 "(network-emulator exited $? at start)"
else
  # 12.5 m/s = 45 km/h; 5 m/s = 18 km/h. States every 20 ms of sim time, 60 of them.
  tool state --to 127.0.0.1:4700 --station 11 --x 10 --speed 12.5 --gear 3 --throttle 0.3 \
    --lights low,brake --count 60 >"$T/state11.log" 2>&1 &
  st11=$!
  tool state --to 127.0.0.1:4700 --station 12 --x 210 --speed 5 --gear 2 --lights hazard \
    --count 60 >"$T/state12.log" 2>&1
  rc12=$?
  wait $st11
  [[ $? == 0 && $rc12 == 0 ]]
  check can.states_sent $? "($(cat "$T/state11.log" "$T/state12.log" | tr '\n' ' '))"
  wait $can1
  rc1=$?
  wait $can2
  rc2=$?
  check can.station11_decodes $rc1 "$(head -c 600 "$T/can1.json")"
  check can.station12_decodes $rc2 "$(head -c 600 "$T/can2.json")"
  wait $candump
  n=$(grep -c "vcan0" "$T/candump.log")
  [[ $n -ge 6 ]]
  check can.candump_sees_frames $? "($n frames, candump -n 6 on tbvm1's vcan0)"
  stop $emu 10
  [[ $stop_rc == 0 ]]
  check can.emulator_exits_cleanly $? "(exit $stop_rc after SIGTERM)"
  grep -q "CAN frames sent" "$T/network-emulator.log"
  check can.emulator_status $? "($(grep -o 'CAN frames sent [0-9]* failed [0-9]*' "$T/network-emulator.log" | tail -1))"
fi
kill $can1 $can2 $candump 2>/dev/null
for ns in tbvm1 tbvm2; do ip -n $ns link del vcan0; done

# ---- CAN: the station's reader (SocketCanBus) at arrival and on demand, its own gtest ---------
# It reads vehicle.dbc at the path built into it, and makes its own namespaces and vcan0.
mkdir -p "$(dirname "$TB_VM_DBC_PATH")" && cp /tb/share/vehicle.dbc "$TB_VM_DBC_PATH"
/tb/tests/can_socketcan_it >"$T/can_socketcan_it.log" 2>&1
rc=$?
passed_line=$(grep -o '\[  PASSED  \] [0-9]* tests\?' "$T/can_socketcan_it.log")
skipped=$(grep -c '^\[  SKIPPED \]' "$T/can_socketcan_it.log")
[[ $rc == 0 && -n $passed_line && $skipped == 0 ]]
check can.socketcan_bus_it $? "(exit $rc; ${passed_line:-no PASSED line}; $skipped skipped: $(grep -E '^\[ +(OK|FAILED|SKIPPED) +\]' "$T/can_socketcan_it.log" | tr -s ' \n' ' ' | head -c 500))"

echo "stage radios: starts $SECONDS s into the test script"
# ---- radios: mac80211_hwsim in OCB mode, driven by radio-medium ----------------------------
radio-medium --scenario "$S" --stations 11=tbvm1,12=tbvm2,13=tbvm3 --mode hwsim --prefix tbvm \
  --positions udp://127.0.0.1:4701 --stats "$T/radio-stats.json" --log-level info \
  >"$T/radio-medium.log" 2>&1 &
rm_pid=$!
if ! wait_for "$T/radio-medium.log" 60 "radio-medium: ready"; then
  check radio.ready 1 "(no 'radio-medium: ready' within 60 s)"
  stop $rm_pid 10
  exit 1
fi
check radio.ready 0 ""
# /sys/class/ieee80211 lists the wiphys of the reader's namespace only (ip netns exec remounts
# /sys), so count per namespace: the monitor here, one radio in each station.
wiphys() { ls /sys/class/ieee80211 | wc -l; for ns in tbvm1 tbvm2 tbvm3; do ip netns exec $ns ls /sys/class/ieee80211 | wc -l; done; }
n=$(wiphys | tr '\n' ' ')
[[ $n == "1 1 1 1 " ]]
check radio.four_radios $? "(wiphys in the host namespace and tbvm1..3: $n; want 1 1 1 1)"
for ns in tbvm1 tbvm2 tbvm3; do
  info=$(ip netns exec $ns iw dev wlan0 info 2>&1)
  echo "$info" | grep -Eq "type (ocb|outside context of a BSS)" && echo "$info" | grep -q "5900 MHz" &&
    echo "$info" | grep -q "width: 10 MHz"
  check "radio.$ns.ocb_5900" $? "($(echo "$info" | grep -E 'type|channel|addr' | tr -s ' \n\t' ' '))"
done
ip link show tbvmmon >/dev/null 2>&1
check radio.monitor_in_host_ns $? "(tbvmmon)"

rxs=()
# Receivers first (they say when they listen), then station 11 sends, then station 12.
for i in 1 2 3; do
  ip netns exec tbvm$i python3 "$G/vmtool.py" raw-recv --iface wlan0 --seconds 40 \
    --ready "$T/rx$i.ready" --stop "$T/rx.stop" --out "$T/rx$i.json" >/dev/null 2>"$T/rx$i.err" &
  rxs+=($!)
done
python3 "$G/vmtool.py" mon-recv --iface tbvmmon --seconds 40 --ready "$T/mon.ready" \
  --stop "$T/rx.stop" --out "$T/mon.json" >/dev/null 2>"$T/mon.err" &
mon=$!
for r in rx1 rx2 rx3 mon; do wait_for "$T/$r.ready" 20; done
ip netns exec tbvm1 python3 "$G/vmtool.py" raw-send --iface wlan0 --count 20 --tag A \
  >"$T/tx11.log" 2>&1
ip netns exec tbvm2 python3 "$G/vmtool.py" raw-send --iface wlan0 --count 20 --tag B \
  >"$T/tx12.log" 2>&1
sleep 2
touch "$T/rx.stop"
wait "${rxs[@]}" $mon
count() { # count FILE TAG
  python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["tags"].get(sys.argv[2], {}).get("count", 0))' "$1" "$2" 2>/dev/null || echo 0
}
a2=$(count "$T/rx2.json" A) a3=$(count "$T/rx3.json" A) a1=$(count "$T/rx1.json" A)
b1=$(count "$T/rx1.json" B) b3=$(count "$T/rx3.json" B)
ma=$(count "$T/mon.json" A) mb=$(count "$T/mon.json" B)
[[ $a2 == 20 ]]
check radio.11_to_12_in_range $? "($a2/20 frames at 200 m)"
[[ $b1 == 20 && $b3 == 20 ]]
check radio.12_to_11_and_13 $? "($b1/20 at 11, $b3/20 at 13, 200 m and 250 m)"
[[ $a3 == 0 ]]
check radio.range_cut_11_to_13 $? "($a3/20 frames at 450 m, range 300 m)"
[[ $a1 == 0 ]]
check radio.no_echo_to_sender $? "($a1 own frames)"
[[ $ma == 20 && $mb == 20 ]]
check radio.monitor_sees_frames $? "($ma/20 from 11, $mb/20 from 12 on tbvmmon)"

src=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["tags"]["A"]["src"])' "$T/rx2.json" 2>/dev/null)
[[ $src == 02:00:00:00:00:0b ]]
check radio.station_mac $? "(frames from station 11 carry ${src:-no address}; want 02:00:00:00:00:0b)"

echo "stage gn: starts $SECONDS s into the test script"
# The project's own GN/BTP stack on the hwsim radios: SHB from 11 reaches 12 (200 m) and not
# 13 (450 m).
probe_pos=(--position 41.1 29.0)
ip netns exec tbvm2 its-gn-probe --receive-count 10 --duration-s 40 "${probe_pos[@]}" \
  >"$T/gn-rx12.log" 2>&1 &
gn12=$!
ip netns exec tbvm3 its-gn-probe --duration-s 12 "${probe_pos[@]}" >"$T/gn-rx13.log" 2>&1 &
gn13=$!
wait_for "$T/gn-rx12.log" 20 '"ready"' && wait_for "$T/gn-rx13.log" 20 '"ready"'
ip netns exec tbvm1 its-gn-probe --send shb --count 10 --interval-ms 100 --duration-s 4 \
  "${probe_pos[@]}" >"$T/gn-tx11.log" 2>&1
tx_rc=$?
wait $gn12
rc12=$?
wait $gn13
rc13=$?
[[ $tx_rc == 0 && $rc12 == 0 ]]
check gn.shb_11_to_12 $? "(its-gn-probe: sender exit $tx_rc, receiver exit $rc12: $(grep summary "$T/gn-rx12.log"))"
got13=$(grep summary "$T/gn-rx13.log" | python3 -c 'import json,sys; print(json.loads(sys.stdin.read())["received"])' 2>/dev/null)
[[ $rc13 == 0 && $got13 == 0 ]]
check gn.range_cut_11_to_13 $? "(its-gn-probe at 450 m: exit $rc13, received ${got13:-?})"

stop $rm_pid 20
[[ $stop_rc == 0 ]]
check radio.exits_cleanly $? "(exit $stop_rc after SIGTERM)"
python3 - "$T/radio-stats.json" <<'EOF'
import json, sys
j = json.load(open(sys.argv[1]))
links = {(l["from"], l["to"]): l for l in j["links"]}
cut = links[(11, 13)]["dropped"]["out_of_range"]
ok = links[(11, 12)]["delivered"] >= 20 and cut >= 20 and links[(12, 13)]["delivered"] >= 20
print(f"11->12 delivered {links[(11, 12)]['delivered']}, 11->13 out_of_range {cut}, "
      f"12->13 delivered {links[(12, 13)]['delivered']}")
sys.exit(0 if ok else 1)
EOF
check radio.stats_out_of_range $? "(radio-medium --stats: $(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["totals"])' "$T/radio-stats.json" 2>&1 | head -c 300))"

echo "stage teardown: starts $SECONDS s into the test script"
# ---- teardown: nothing left ----------------------------------------------------------------
n=$(wiphys | tr '\n' ' ')
[[ $n == "0 0 0 0 " ]]
check teardown.no_wiphys $? "(wiphys in the host namespace and tbvm1..3: $n)"
left=$(iw dev 2>&1; for ns in tbvm1 tbvm2 tbvm3; do ip netns exec $ns iw dev 2>&1; done)
[[ -z $left ]]
check teardown.iw_dev_empty $? "(${left:-nothing})"
links=$({
  ip -o link show | grep tbvm
  for ns in tbvm1 tbvm2 tbvm3; do ip -n $ns -o link show wlan0 2>/dev/null; done
} | cut -d: -f2 | tr -d '\n')
[[ -z $links ]]
check teardown.no_interfaces $? "(${links:-no tbvm* and no wlan0 left})"
for ns in tbvm1 tbvm2 tbvm3; do ip netns del $ns; done

echo "stage stations: starts $SECONDS s into the test script"
# ---- its-stations through the native launcher: CAMs over hwsim, LDM, LCRW -------------------
# scripts/testbed runs the whole chain as on a host: mosquitto, sim-server, the scripted
# drivers (headless sim-client), a namespace per station (with --vcan a vcan0 in each),
# radio-medium (hwsim: the kernel has it), its-station with its gpsd in each namespace, the
# network emulator (NMEA into gpsd, CAN on vcan0). Scenario guest/scenario-lcrw.json: red (1001)
# closes in on black (1002) ahead on its lane and must be warned; lower rates for TCG.
if [[ ${TB_VM_STATIONS:-1} == 1 ]]; then
  # The launcher passes no --dbc: the stations and the emulator read the DBC at the path built
  # into them (the source tree on the host).
  mkdir -p "$(dirname "$TB_VM_DBC_PATH")" && cp /tb/share/vehicle.dbc "$TB_VM_DBC_PATH"
  L=$T/launcher
  SL=$G/scenario-lcrw.json
  mkdir -p "$L"
  st_t0=$SECONDS
  python3 /tb/scripts/testbed run "$SL" --build /tb --out "$L" --vcan >"$T/testbed.log" 2>&1 &
  tb=$!
  sub=""
  if wait_for "$T/testbed.log" 60 "up: mosquitto"; then
    # The HMI's view of the run: the broker's CAM and LCRW topics, read as the HMI user.
    stdbuf -oL mosquitto_sub -h 127.0.0.1 -u hmi -P hmi -t 'its/+/app/lcrw' -t 'its/+/in/cam/+' \
      -v >"$T/mqtt.txt" 2>"$T/mqtt.err" &
    sub=$!
  fi
  mon=""
  if wait_for "$T/testbed.log" 60 "up: radio-medium"; then
    python3 "$G/vmtool.py" mon-count --iface tbrmmon --seconds 120 --ready "$T/mon2.ready" \
      --stop "$T/mon2.stop" --out "$T/mon2.json" >/dev/null 2>"$T/mon2-err.log" &
    mon=$!
    # The launcher waits for wlan0 to exist; the medium may still be setting OCB up.
    for ((k = 0; k < 20; k++)); do
      ocb=""
      for ns in tbst-1001 tbst-1002; do
        info=$(ip netns exec $ns iw dev wlan0 info 2>&1)
        echo "$info" | grep -Eq "type (ocb|outside context of a BSS)" && echo "$info" | grep -q "5900 MHz" ||
          ocb+="$ns: $(echo "$info" | grep -E 'type|channel' | tr -s ' \n\t' ' ') "
      done
      [[ -z $ocb ]] && break
      sleep 0.5
    done
    [[ -z $ocb ]]
    check stations.wlan0_ocb_5900 $? "(${ocb:-wlan0 in tbst-1001 and tbst-1002: OCB on 5900 MHz})"
  fi
  wait_for "$T/testbed.log" 90 "up: its-station"
  st_up=$((SECONDS - st_t0))
  # The launcher stops everything after the scenario's duration_s (38 s); bound it anyway.
  # Meanwhile keep each station's last status file with a fix: the one the station writes on
  # its way out may have lost its fix and neighbours already (gpsd and the feeds stop first).
  run_dir=$(ls -d "$L"/run-* 2>/dev/null | tail -1)
  for ((k = 0; k < 150; k++)); do
    kill -0 $tb 2>/dev/null || break
    for id in 1001 1002; do
      f=$run_dir/station-$id.status.json
      [[ -n $run_dir && -s $f ]] && cp "$f" "$T/status.tmp" && grep -q '"fix":true' "$T/status.tmp" &&
        mv "$T/status.tmp" "$T/status-$id.json"
    done
    sleep 1
  done
  if kill -0 $tb 2>/dev/null; then
    echo "stations: the launcher still runs after $((SECONDS - st_t0)) s: SIGTERM"
    stop $tb 40
  else
    wait $tb
    stop_rc=$?
  fi
  st_rc=$stop_rc
  echo "stations: launcher up after $st_up s, finished after $((SECONDS - st_t0)) s, exit $st_rc"
  touch "$T/mon2.stop"
  [[ -n $mon ]] && wait $mon
  [[ -n $sub ]] && kill $sub 2>/dev/null && wait $sub
  run_dir=$(ls -d "$L"/run-* 2>/dev/null | tail -1)
  # sim-server ends by itself at the scenario's duration ("exited with 0"): not a failure.
  notes=$(grep -E "did not stop|exited with [1-9-]|error" "$T/testbed.log" | tr '\n' ' ')
  [[ $st_rc == 0 && -n $run_dir ]] && grep -q "up: its-station x2" "$T/testbed.log" &&
    grep -q "scenario duration reached" "$T/testbed.log" && [[ -z $notes ]]
  check stations.launcher_run $? "(scripts/testbed exit $st_rc; ${notes:-every process up, stopped in time})"
  ok=1
  while IFS=$'\t' read -r name rc why; do
    if [[ $name == info ]]; then echo "stations: $why"; continue; fi
    check "$name" "$rc" "$why"
    [[ $rc == 0 ]] || ok=0
  done < <(python3 "$G/station_check.py" "${run_dir:-$L}" "$T/mqtt.txt" "$T" 2>&1)
  mons=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["frames"])' "$T/mon2.json" 2>/dev/null)
  python3 -c 'import json,sys; f=json.load(open(sys.argv[1]))["frames"]; sys.exit(0 if f.get("02:00:00:00:03:e9", 0) > 0 and f.get("02:00:00:00:03:ea", 0) > 0 else 1)' "$T/mon2.json" 2>/dev/null
  check stations.monitor_sees_cams $? "(GeoNetworking frames per transmitter on tbrmmon: ${mons:-none})"
  if ((ok == 0)) && [[ -n $run_dir ]]; then
    for f in "$run_dir"/*.log; do echo "== $f"; tail -n 25 "$f"; done
  fi
  # Teardown of the launcher: its namespaces, bridge, veths and radios are gone.
  left=$( {
    ip netns list | grep -o '^tbst-[0-9]*'
    ip -o link show | cut -d: -f2 | grep -E '^ (tbbr0|tbv|tbrm)'
    ls /sys/class/ieee80211
  } | tr -s ' \n' ' ')
  [[ -z ${left// /} ]]
  check teardown.launcher $? "(${left:-no tbst-* namespace, no tbbr0/tbv*/tbrm* link, no wiphy left})"
else
  echo "SKIP stations.*, cam.*, lcrw.*: the its-station stage was turned off (tests/vm/run --no-stations)"
fi
