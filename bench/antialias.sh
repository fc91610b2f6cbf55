#!/usr/bin/env bash
# Anti-aliasing benchmark (docs/antialiasing.md, "Against llvmpipe 4x MSAA"): builds roomrender,
# bench_antialias_peer_scene and the in-repo llvmpipe peer (bench/peer, needs libosmesa6-dev), then
# bench/antialias.py measures edge error against the 256-sample reference and frame times against
# llvmpipe 4x MSAA on the example scenes, interleaved, in one run (a few minutes on 2 cores).
# Writes bench/results/antialias.{json,csv} and docs/antialiasing-bench.md.
#   bench/antialias.sh [antialias.py flags: --scenes a b --rounds N --frames N --width W --height H]
# Environment: BUILD (default build-bench-aa), JOBS (default 2).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD:-build-bench-aa}
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DROOMRENDER_PEER_BENCH=ON >/dev/null
nice -n 10 cmake --build "$build" -j"${JOBS:-2}" --target roomrender bench_antialias_peer_scene osmesa_bench
python3 bench/antialias.py --roomrender "$build/roomrender" --peer "$build/bench/osmesa_bench" \
  --peer-scene "$build/bench/bench_antialias_peer_scene" --source . "$@"
