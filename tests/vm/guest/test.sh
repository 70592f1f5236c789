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

# ---- its-station: CAMs over hwsim, fed by the emulator (gpsd + vcan) ------------------------
# Opt-in (tests/vm/run --with-stations): three stations with their gpsd are slow under TCG.
if [[ ${TB_VM_STATIONS:-0} == 1 ]]; then
  # Sim time starts now, so that the NMEA times gpsd reports are current for the stations.
  start_unix=$(date -u +%s)
  # CAN at 20/2 Hz instead of 100/10: three stations under TCG fell minutes behind at 100 Hz.
  sed -e "s/\"start_time\": \"[^\"]*\"/\"start_time\": \"$(date -u -d @$start_unix +%Y-%m-%dT%H:%M:%SZ)\"/" \
    -e 's/"channel":/"rates": { "can_dynamics_hz": 20, "can_body_hz": 2 },\n  "channel":/' \
    "$S" >"$T/scenario-now.json"
  printf '{"stations": [%s]}\n' \
    '{"station_id": 11, "netns": "tbvm1"}, {"station_id": 12, "netns": "tbvm2"}, {"station_id": 13, "netns": "tbvm3"}' \
    >"$T/stations3.json"
  its=()
  for i in 1 2 3; do
    ip -n tbvm$i link add vcan0 type vcan && ip -n tbvm$i link set vcan0 up
    ip netns exec tbvm$i its-station --station-id 1$i --scenario "$T/scenario-now.json" \
      --radio wlan0 --can socketcan --can-interface vcan0 --dbc /tb/share/vehicle.dbc \
      --cam-policy fixed --cam-period-ms 100 --gpsd-wait 30 --status-file "$T/station1$i.json" \
      --log-level info >"$T/its-station1$i.log" 2>&1 &
    its+=($!)
  done
  network-emulator --scenario "$T/scenario-now.json" --stations "$T/stations3.json" --can vcan \
    --dbc /tb/share/vehicle.dbc --listen 127.0.0.1:4700 --status-interval 0 \
    >"$T/network-emulator-cam.log" 2>&1 &
  emu=$!
  sleep 1
  # Up to 30 s of states at 20 Hz, until every station's LDM holds what it should; speeds
  # differ so that each neighbour can be told apart.
  speeds=(0 10 5 7.5)
  xs=(0 10 210 460)
  stc=()
  for i in 1 2 3; do
    tool state --to 127.0.0.1:4700 --station 1$i --x ${xs[$i]} --speed ${speeds[$i]} --gear 3 \
      --count 600 --interval 0.05 --start-unix $start_unix >"$T/state-cam1$i.log" 2>&1 &
    stc+=($!)
  done
  cam_check() { # cam_check STATION WANT_NEIGHBOURS...
    python3 "$G/cam_check.py" "$T/station$1.json" "${@:2}"
  }
  for ((k = 0; k < 30; k++)); do
    sleep 1
    cam_check 11 12 >/dev/null && cam_check 12 11 13 >/dev/null && cam_check 13 12 >/dev/null && break
  done
  echo "cam: waited $k s for the LDMs"
  rcs=""
  for p in "${stc[@]}"; do
    kill -0 $p 2>/dev/null && kill $p
    wait $p
    rcs+="$? "
  done
  [[ $rcs =~ ^((0|143)\ ){3}$ ]]
  check cam.states_sent $? "(exit codes $rcs; 143 = stopped early)"
  why=$(cam_check 11 12)
  check cam.ldm_11_sees_12_only $? "($why)"
  why=$(cam_check 12 11 13)
  check cam.ldm_12_sees_11_and_13 $? "($why)"
  why=$(cam_check 13 12)
  check cam.ldm_13_sees_12_only $? "($why)"
  # Now, not only at the end: a slow stop below may run into the VM's time limit.
  tail -n 20 "$T/its-station11.log" "$T/network-emulator-cam.log"
  rcs=""
  for p in "${its[@]}"; do
    stop $p 15
    rcs+="$stop_rc "
  done
  [[ $rcs == "0 0 0 " ]]
  check cam.stations_exit_cleanly $? "(exit codes $rcs)"
  stop $emu 10
  for i in 1 2 3; do ip -n tbvm$i link del vcan0; done
else
  echo "SKIP cam.*: the its-station stage was not asked for (tests/vm/run --with-stations)"
fi

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
