#!/usr/bin/env bash
# Tests radio-medium on real mac80211_hwsim radios in a qemu VM with Debian 12's stock kernel
# (this machine's kernel has no hwsim; REFERENCES.md, "A VM with Debian's stock kernel").
#
# Usage: network-emulator/radio/tests/hwsim_vm_test.sh [BIN_DIR] [WORK_DIR]
#   BIN_DIR   the build's bin/ with radio-medium and radio-probe (default build/radio/bin)
#   WORK_DIR  where the root file system is kept between runs (default /tmp/radio-hwsim-vm)
# Needs root, debootstrap, qemu-system-x86_64 and network access to Debian's mirror on the first
# run (about 3 minutes to build the root, then about 1 minute per run under TCG). Exits 0 when
# every check passed. Not registered with ctest: too slow and needs the network.
set -euo pipefail

ROOT_DIR=$(cd "$(dirname "$0")/../../.." && pwd)
BIN=${1:-$ROOT_DIR/build/radio/bin}
WORK=${2:-/tmp/radio-hwsim-vm}
for tool in debootstrap qemu-system-x86_64 mkfs.ext4; do
  command -v "$tool" >/dev/null || { echo "hwsim_vm_test: $tool is missing" >&2; exit 2; }
done
for prog in radio-medium radio-probe; do
  [[ -x $BIN/$prog ]] || { echo "hwsim_vm_test: no $BIN/$prog (build it first)" >&2; exit 2; }
done
mkdir -p "$WORK"
ROOT=$WORK/root

if [[ ! -e $ROOT/.ready ]]; then
  rm -rf "$ROOT"
  debootstrap --variant=minbase bookworm "$ROOT" http://deb.debian.org/debian >"$WORK/debootstrap.log"
  chroot "$ROOT" sh -c 'DEBIAN_FRONTEND=noninteractive apt-get install -y -qq \
      --no-install-recommends linux-image-amd64 iproute2 iw kmod libnl-3-200 libnl-genl-3-200 \
      libnl-route-3-200 libspdlog1.10 libfmt9' >"$WORK/chroot-apt.log"
  touch "$ROOT/.ready"
fi

mkdir -p "$ROOT/opt/radio"
cp "$BIN/radio-medium" "$BIN/radio-probe" "$ROOT/opt/radio/"
# Stations at x = 10, 210 and 460 m: with a 300 m range 11 hears 12, 12 hears both, 13 hears 12.
python3 - "$ROOT/opt/radio" <<'PY'
import json, sys
base = {
  "name": "hwsim-vm", "map": {"type": "straight", "lanes": 2, "length": 2000},
  "origin": {"lat": 41.1, "lon": 29.0, "alt": 60}, "start_time": "2025-06-02T09:00:00Z",
  "vehicles": [{"id": v, "station_id": s, "spawn": {"x": x, "y": 0, "heading_deg": 90},
                "driver": "human"} for v, s, x in (("a", 11, 10), ("b", 12, 210), ("c", 13, 460))]}
for name, channel in (("range", {"model": "range", "range_m": 300}), ("ideal", {"model": "ideal"}),
                      ("delay", {"model": "ideal", "delay_ms": 2, "jitter_ms": 2})):
    json.dump(dict(base, channel=channel), open(f"{sys.argv[1]}/{name}.json", "w"))
PY
cat >"$ROOT/opt/radio/init.sh" <<'SH'
#!/bin/sh
mount -t proc proc /proc; mount -t sysfs sys /sys; mount -t tmpfs tmp /run; mount -t tmpfs tmp /tmp
mkdir -p /run/netns; export PATH=/usr/sbin:/usr/bin:/sbin:/bin
cd /opt/radio
modprobe mac80211_hwsim radios=0 || echo "RESULT FAIL modprobe"
for n in a b c; do ip netns add st$n; done
check() {  # label scenario expected-at-12 expected-at-13
  ./radio-medium --scenario $2 --stations 11=sta,12=stb,13=stc --stats /tmp/$1.json \
      >/tmp/$1.out 2>&1 &
  mp=$!
  for i in $(seq 1 150); do grep -q ready /tmp/$1.out && break; sleep 0.2; done
  cat /tmp/$1.out
  ip netns exec stb ./radio-probe recv --count 100 --timeout 15 >/tmp/$1.b &
  rb=$!
  ip netns exec stc ./radio-probe recv --count 100 --timeout 15 >/tmp/$1.c &
  rc=$!
  sleep 1
  ip netns exec sta ./radio-probe send --count 100
  wait $rb; wait $rc
  echo "RESULT $1 station12 $(cat /tmp/$1.b)"
  echo "RESULT $1 station13 $(cat /tmp/$1.c)"
  grep -q "received $3 of 100" /tmp/$1.b && grep -q "received $4 of 100" /tmp/$1.c \
    && echo "RESULT PASS $1 delivery" || echo "RESULT FAIL $1 delivery"
  ip -br link | grep -q tbrmmon && echo "RESULT PASS $1 monitor" || echo "RESULT FAIL $1 monitor"
  kill -TERM $mp; wait $mp && echo "RESULT PASS $1 exit" || echo "RESULT FAIL $1 exit"
  echo "RESULT $1 stats $(tr -d ' \n' </tmp/$1.json | head -c 400)"
  left="$(ls /sys/class/ieee80211/) $(ip -n sta -br link | grep -v '^lo')"
  [ -z "$(echo $left | tr -d ' ')" ] && echo "RESULT PASS $1 cleanup" \
    || echo "RESULT FAIL $1 cleanup: $left"
}
check range range.json 100 0
check ideal ideal.json 100 100
check delay delay.json 100 100
echo "RESULT END"
echo o >/proc/sysrq-trigger
SH
chmod +x "$ROOT/opt/radio/init.sh"

rm -f "$WORK/disk.img"
truncate -s 1G "$WORK/disk.img"
mkfs.ext4 -q -F -d "$ROOT" "$WORK/disk.img"
KERNEL=$(ls "$ROOT"/boot/vmlinuz-* | head -1)
INITRD=$(ls "$ROOT"/boot/initrd.img-* | head -1)
timeout 600 qemu-system-x86_64 -accel tcg -m 1024 -smp 2 -nographic -no-reboot \
  -kernel "$KERNEL" -initrd "$INITRD" -drive file="$WORK/disk.img",format=raw,if=virtio \
  -append "root=/dev/vda rw console=ttyS0 init=/opt/radio/init.sh quiet panic=-1" \
  >"$WORK/console.log" 2>&1 || true

grep -a "RESULT\|radio-medium:" "$WORK/console.log" || true
if ! grep -aq "RESULT END" "$WORK/console.log"; then
  echo "hwsim_vm_test: the VM did not finish; see $WORK/console.log" >&2
  exit 1
fi
if grep -aq "RESULT FAIL" "$WORK/console.log"; then
  echo "hwsim_vm_test: FAILED (console in $WORK/console.log)" >&2
  exit 1
fi
echo "hwsim_vm_test: passed"
