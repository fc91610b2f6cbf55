#!/usr/bin/env bash
# The performance yardstick: roomrender `bench-render` against Mesa's llvmpipe and Embree 3
# (the peers of ../shared/peers) on the same OBJs and cameras as its tools/side_by_side.py, plus the
# nine Sweet Home 3D homes, at 1 and 2 threads, interleaved rounds in one run. Writes
# bench/results/performance.json and docs/performance.md with plots in docs/performance/. Not part of
# the test run; about an hour with 2 rounds on a loaded 2-core machine (`--rounds 2`; default 3).
#   bench/perf.sh [perf.py flags: --rounds N --frames N --size WxH --threads 1,2 --scenes a,b --no-homes]
# Environment:
#   QUICK=1     smoke run: 3 small scenes, 1 round, 5 frames, 640x360, no homes; writes
#               bench/results/performance-quick.{json,md} instead, so it never overwrites the real report
#   ROOMRENDER  a roomrender binary to measure (default: build one, Release, in build-bench/)
#   PEERS       the peers' source (default ../shared/peers; read-only, built outside it)
#   BENCH_CACHE where the peers are built and their scenes generated
#               (default ${XDG_CACHE_HOME:-~/.cache}/roomrender-bench)
#   JOBS        build parallelism (default 2)
set -euo pipefail
cd "$(dirname "$0")/.."
peers=$(cd "${PEERS:-../shared/peers}" && pwd)
cache=${BENCH_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/roomrender-bench}
mkdir -p "$cache"
bench/install-bench-deps.sh

if [ -z "${ROOMRENDER:-}" ]; then
  cmake -S . -B build-bench -DCMAKE_BUILD_TYPE=Release -DROOMRENDER_TESTS=OFF >/dev/null
  nice -n 10 cmake --build build-bench -j"${JOBS:-2}" --target roomrender
  ROOMRENDER=build-bench/roomrender
fi

cmake -S "$peers" -B "$cache/peers-build" -DCMAKE_BUILD_TYPE=Release >/dev/null
nice -n 10 cmake --build "$cache/peers-build" -j"${JOBS:-2}" >/dev/null

# The scenes are deterministic: regenerated only when gen_obj.py changes or a needed one is missing.
scenes="$cache/scenes"
stamp=$(sha256sum "$peers/scenes/gen_obj.py" | cut -d' ' -f1)
[ "$(cat "$scenes/.stamp" 2>/dev/null)" = "$stamp" ] || rm -rf "$scenes"
mkdir -p "$scenes"
if [ -n "${QUICK:-}" ]; then
  [ -f "$scenes/apartment.obj" ] || python3 "$peers/scenes/gen_obj.py" --outdir "$scenes" --only cylinders apartment
  out=(--quick --results bench/results/performance-quick.json --doc bench/results/performance-quick.md)
else
  [ -f "$scenes/grid_1e6.obj" ] || python3 "$peers/scenes/gen_obj.py" --outdir "$scenes"
  out=(--results bench/results/performance.json --doc docs/performance.md)
fi
echo "$stamp" >"$scenes/.stamp"

python3 bench/perf.py --roomrender "$ROOMRENDER" --peers "$peers" --peers-build "$cache/peers-build" \
  --scenes-dir "$scenes" "${out[@]}" "$@"
