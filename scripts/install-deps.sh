#!/usr/bin/env bash
# Installs the Debian packages roomrender builds and tests with. Idempotent: asks apt only for what
# is missing, so a second run is instant and needs no network.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libcpp-httplib-dev nlohmann-json3-dev libglm-dev libstb-dev googletest libgtest-dev
  curl ca-certificates
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# node and npm run the schema test (tests/schema). Any node >= 18 will do, also one installed from
# elsewhere, so Debian's are asked for only when the commands are missing.
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then missing+=(nodejs npm); fi

if [ ${#missing[@]} -gt 0 ]; then
  echo "install-deps: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# ajv for the schema test, from its lockfile, once (node_modules is not committed).
schema_dir="$(cd "$(dirname "$0")/.." && pwd)/tests/schema"
if [ ! -f "$schema_dir/node_modules/ajv/package.json" ]; then
  echo "install-deps: npm ci in tests/schema"
  (cd "$schema_dir" && npm ci --no-audit --no-fund --loglevel=error)
fi
