#!/usr/bin/env bash
# Installs the Debian packages the benchmarks need on top of scripts/install-deps.sh: Mesa's OSMesa
# (the llvmpipe peer renderer that bench/peer/osmesa_bench.cpp drives) and its GL headers. Kept out of
# the service's install so a server machine never pulls in Mesa. Idempotent, like install-deps.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh

packages=(libosmesa6-dev libgl-dev python3)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -gt 0 ]; then
  echo "install-bench-deps: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
