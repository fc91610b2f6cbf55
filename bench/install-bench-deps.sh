#!/usr/bin/env bash
# Installs the Debian packages the benchmarks need on top of the service's: Mesa's OSMesa (llvmpipe)
# and Embree 3 for the peer renderers of ../shared/peers that bench/perf.sh builds, stb for the
# peers' PNG writer, and python3 for bench/perf.py. Kept out of scripts/install-deps.sh's own list so
# a server machine never pulls in Mesa or Embree. Idempotent, like install-deps.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh build libosmesa6-dev libgl-dev libembree-dev libstb-dev python3
