#!/usr/bin/env bash
# Installs the Debian packages the benchmarks need on top of the service's: Mesa's OSMesa (the
# llvmpipe peer renderer that bench/peer/osmesa_bench.cpp drives), its GL headers, and python3 for
# bench/perf.py. Kept out of scripts/install-deps.sh's own list so a server machine never pulls in
# Mesa. Idempotent, like install-deps.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh libosmesa6-dev libgl-dev python3
