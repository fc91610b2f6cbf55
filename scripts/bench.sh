#!/usr/bin/env bash
# Runs one benchmark on demand: scripts/bench.sh NAME [ARGS...] builds bench_NAME (Release) and writes
# its results to bench/results/NAME.json (and whatever else it prints). Not part of the test run.
set -euo pipefail
cd "$(dirname "$0")/.."
name="${1:?usage: scripts/bench.sh NAME [ARGS...] (NAME: a file bench/NAME.cpp)}"
shift
scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target "bench_${name}"
mkdir -p bench/results
build/bench/"bench_${name}" --out "bench/results/${name}.json" "$@"
echo "results: bench/results/${name}.json"
