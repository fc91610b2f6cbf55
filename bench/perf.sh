#!/usr/bin/env bash
# The performance yardstick of issue 8: builds roomrender, the scene generator and the llvmpipe peer
# harness in build-bench/ (Release), generates the benchmark scenes, runs both renderers on every
# scene and mode in one run, and writes bench/results/performance.json and docs/performance.md (with
# SVG plots in docs/performance/). Not part of the test run; takes about 10-20 minutes here.
#   bench/perf.sh [--pipelines zbuffer,painter] [--skip-pixels] [--timeout SECONDS]
# Environment: JOBS (build parallelism, default 2), SOUPS (default 1000,10000,100000,1000000), SHARED
# (third-party data for the conference room and Sweet Home 3D homes, default ../shared/data; skipped
# with a note when absent), HOMES (how many homes, default 9).
set -euo pipefail
cd "$(dirname "$0")/.."
bench/install-bench-deps.sh
cmake -S . -B build-bench -DCMAKE_BUILD_TYPE=Release -DROOMRENDER_TESTS=OFF -DROOMRENDER_PEER_BENCH=ON >/dev/null
cmake --build build-bench -j"${JOBS:-2}" --target roomrender bench_gen_scenes osmesa_bench
build-bench/bench/bench_gen_scenes --dir build-bench/scenes --out build-bench/scenes/manifest.json \
  --soups "${SOUPS:-1000,10000,100000,1000000}"
python3 bench/perf.py --roomrender build-bench/roomrender --peer build-bench/bench/osmesa_bench \
  --manifest build-bench/scenes/manifest.json --results bench/results/performance.json \
  --doc docs/performance.md --shared "${SHARED:-../shared/data}" --homes "${HOMES:-9}" "$@"
