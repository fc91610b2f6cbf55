#!/usr/bin/env bash
# Run time against error (issue 6): builds bench_accuracy and the scene generator in build-bench/
# (Release), generates the apartment and a triangle soup, renders the whole suite with every pipeline
# and option against the reference pipeline, and writes bench/results/accuracy.{json,csv} and the
# "Run time against error" section of docs/accuracy.md (plots in docs/accuracy/). Not part of the test
# run; about 15-20 minutes on the shared 2-core machine.
#   bench/accuracy.sh [bench_accuracy flags, e.g. --only tri_,rows --size 320x180]
#   RESULTS=bench/results/accuracy_textures bench/accuracy.sh --only textured_
#       the textured class alone: its table in docs/accuracy.md ("Texture error"), about a minute
# Environment: JOBS (build parallelism, default 2), SHARED (default ../shared/data), BUILD (the build
# directory, default build-bench; an existing Release build such as build/ is reused as configured),
# RESULTS (the results' path without .json/.csv, default bench/results/accuracy).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD:-build-bench}
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DROOMRENDER_TESTS=OFF >/dev/null
fi
cmake --build "$build" -j"${JOBS:-2}" --target bench_accuracy bench_gen_scenes
"$build"/bench/bench_gen_scenes --dir "$build"/scenes --out "$build"/scenes/accuracy_manifest.json --soups 1000 >/dev/null
results=${RESULTS:-bench/results/accuracy}
mkdir -p "$(dirname "$results")"
nice "$build"/bench/bench_accuracy --out "$results.json" \
  --gen-manifest "$build"/scenes/accuracy_manifest.json --shared "${SHARED:-../shared/data}" "$@"
python3 bench/accuracy_report.py "$results.json" --csv "$results.csv" \
  --doc docs/accuracy.md --svg-dir docs/accuracy --commit "$(git rev-parse --short HEAD)"
echo "wrote $results.{json,csv}, docs/accuracy.md and docs/accuracy/*.svg"
