#!/usr/bin/env bash
# Builds the HMI into hmi/dist (served by Mosquitto's http_dir).
#
#   hmi/build.sh [--debian] [--out DIR]
#
# Default: the npm packages of package-lock.json (npm ci when node_modules is missing or older
# than the lock file), bundled by build.mjs. --debian, or where npm is missing: Debian 12's
# packages only, no registry (the broker image builds this way): the esbuild program, mqtt.js 4
# (node-mqtt) and the browser stand-ins of Node's process, buffer and url modules. Both bundles
# are tested in Chromium (ctest hmi.browser and hmi.browser.debian).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
out=$here/dist
mode=npm
while (($#)); do
  case $1 in
    --debian) mode=debian ;;
    --out) out=$(realpath -m "$2"); shift ;;
    *) echo "hmi/build.sh: unknown argument '$1' (usage: hmi/build.sh [--debian] [--out DIR])" >&2; exit 2 ;;
  esac
  shift
done
if [[ $mode == npm ]] && ! command -v npm >/dev/null; then
  echo "hmi/build.sh: npm missing, building from Debian's packages instead (--debian)"
  mode=debian
fi

if [[ $mode == npm ]]; then
  cd "$here"
  if [[ ! -d node_modules || package-lock.json -nt node_modules/.package-lock.json ]]; then
    npm ci --no-audit --no-fund
  fi
  HMI_OUT=$out node build.mjs
  exit 0
fi

# Debian's packages: the same options as build.mjs, with Node's modules from /usr/share/nodejs.
nodejs=/usr/share/nodejs
missing=()
command -v esbuild >/dev/null || missing+=(esbuild)
for m in mqtt buffer url process; do
  [[ -d $nodejs/$m ]] || missing+=("node-$m")
done
if ((${#missing[@]})); then
  echo "hmi/build.sh: Debian packages missing for the HMI's build: ${missing[*]}" \
    "(scripts/install-deps installs them)" >&2
  exit 1
fi
rm -rf "$out"
mkdir -p "$out"
# mqtt.js 4 expects Node's process and Buffer as globals (its npm build brought browserify's);
# ws is only the Node transport, the browser's own WebSocket replaces it (ws/browser.js).
NODE_PATH=$nodejs esbuild "$here/src/main.js" --bundle --minify --sourcemap --format=iife \
  --platform=browser --target=es2020 --outfile="$out/app.js" --log-level=warning \
  --inject:"$here/debian-globals.js" --define:global=globalThis --alias:ws=$nodejs/ws/browser.js
cp "$here/index.html" "$here/style.css" "$out/"
echo "hmi: built $out (Debian's packages)"
