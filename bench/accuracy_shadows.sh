#!/usr/bin/env bash
# Shadow error within 2 pixels of the reference's shadow edges and away from them (docs/accuracy.md,
# "Shadow error at shadow edges and away from them"): bench_accuracy's shadow configurations only
# (maps at the bench's settings and exact shadow rays), one timed frame each (the errors come from the
# warm-up frame; the times are not the point), over the whole suite. Writes
# bench/results/accuracy_shadows.{json,csv} and the generated part of that section. A few minutes on
# the shared 2-core machine.
#   bench/accuracy_shadows.sh [bench_accuracy flags, e.g. --only sh3d_]
# Environment: BUILD (default build-bench; an existing Release build is reused as configured), JOBS
# (build parallelism, default 2), SHARED (default ../shared/data), BEFORE (bench_accuracy's JSON of an
# earlier commit, for the homes' before/after table; default bench/results/accuracy_shadows_before.json
# when it exists) and BEFORE_COMMIT (its commit, for the doc; default "07aea72 + bench/results/accuracy_shadows_before.patch", that file's).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD:-build-bench}
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DROOMRENDER_TESTS=OFF >/dev/null
fi
nice cmake --build "$build" -j"${JOBS:-2}" --target bench_accuracy bench_gen_scenes
"$build"/bench/bench_gen_scenes --dir "$build"/scenes --out "$build"/scenes/accuracy_manifest.json --soups 1000 >/dev/null
mkdir -p bench/results
nice "$build"/bench/bench_accuracy --out bench/results/accuracy_shadows.json --configs shadows --frames 1 \
  --gen-manifest "$build"/scenes/accuracy_manifest.json --shared "${SHARED:-../shared/data}" "$@"
before=${BEFORE:-bench/results/accuracy_shadows_before.json}
before_args=()
if [ -f "$before" ]; then before_args=(--before "$before" --before-commit "${BEFORE_COMMIT:-07aea72 + bench/results/accuracy_shadows_before.patch}"); fi
python3 bench/accuracy_shadows.py bench/results/accuracy_shadows.json --csv bench/results/accuracy_shadows.csv \
  --doc docs/accuracy.md --commit "$(git rev-parse --short HEAD)" "${before_args[@]}"
echo "wrote bench/results/accuracy_shadows.{json,csv} and docs/accuracy.md's shadow-error section"
