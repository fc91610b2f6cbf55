#!/usr/bin/env bash
# Builds the libFuzzer target with clang (ASan + UBSan) in build-fuzz/ and fuzzes it for SECONDS
# (default 300), one process at low priority. The corpus persists in build-fuzz/corpus (seeded from
# examples/*.json, fuzz/seeds/ and fuzz/regressions/); crashing, leaking or slow inputs land in
# build-fuzz/artifacts/.
# Usage: fuzz/run.sh [SECONDS] [extra libFuzzer flags...]   (docs/fuzzing.md)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
seconds="${1:-300}"
shift || true
build="${ROOMRENDER_FUZZ_BUILD:-$root/build-fuzz}"

cmake -S "$root" -B "$build" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DROOMRENDER_FUZZ=ON -DROOMRENDER_WERROR=ON -DROOMRENDER_TESTS=OFF -DROOMRENDER_BENCH=OFF >/dev/null
nice -n 10 cmake --build "$build" -j"${JOBS:-2}" --target fuzz_render_request

mkdir -p "$build/corpus" "$build/artifacts"
cp -n "$root"/examples/*.json "$build/corpus/"
cp -n "$root"/fuzz/seeds/* "$build/corpus/"
if compgen -G "$root/fuzz/regressions/*" >/dev/null; then cp -n "$root"/fuzz/regressions/* "$build/corpus/"; fi

# -timeout: one input is a <= 32x32 render and should take milliseconds; 10 s is a hang.
# -rss_limit_mb: the caps in fuzz_harness.cpp keep a run far below this; beyond it is a finding.
# -max_len: room for the largest example (apartment.json, ~7 kB) to grow.
cd "$build"
nice -n 10 ./fuzz/fuzz_render_request "$build/corpus" \
  -dict="$root/fuzz/request.dict" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
  -max_len=16384 -workers=1 -artifact_prefix="$build/artifacts/" -print_final_stats=1 "$@" \
  2>&1 | tee -a "$build/fuzz.log"
