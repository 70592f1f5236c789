#!/usr/bin/env bash
# Builds the HMI into hmi/dist (served by Mosquitto's http_dir). Installs the npm packages from
# package-lock.json first when node_modules is missing or older than the lock file.
set -euo pipefail
cd "$(dirname "$0")"
if [[ ! -d node_modules || package-lock.json -nt node_modules/.package-lock.json ]]; then
  npm ci --no-audit --no-fund
fi
node build.mjs
