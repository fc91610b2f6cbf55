#!/usr/bin/env bash
# Builds a libFuzzer target with clang (ASan + UBSan) in build-fuzz/ and fuzzes it for SECONDS
# (default 300), one process at low priority. FUZZ_TARGET picks the target:
#   render_request (default)  request JSON -> a tiny render; corpus seeded from examples/*.json,
#                             fuzz/seeds/ and fuzz/regressions/, dictionary fuzz/request.dict
#   http_seam                 request bytes -> the connection front's parse against cpp-httplib's;
#                             corpus seeded from fuzz/http_seeds/ and fuzz/http_regressions/,
#                             dictionary fuzz/http.dict
#   texture_decode            encoded image bytes -> decode_texture with the service's limits; corpus
#                             seeded from fuzz/texture_seeds/ (small PNGs and JPEGs, and findings) and
#                             the 26 default textures of catalogue/textures/, no dictionary
# The corpus persists in build-fuzz/corpus (render_request) or build-fuzz/corpus-http_seam; crashing,
# leaking, slow or (http_seam) disagreeing inputs land in build-fuzz/artifacts/. Exits 77 when clang
# or its libFuzzer runtime is missing, so ctest reports the bounded run as skipped.
# Usage: [FUZZ_TARGET=http_seam] fuzz/run.sh [SECONDS] [extra libFuzzer flags...]   (docs/fuzzing.md)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
seconds="${1:-300}"
shift || true
build="${ROOMRENDER_FUZZ_BUILD:-$root/build-fuzz}"
target="${FUZZ_TARGET:-render_request}"

case "$target" in
  render_request) corpus="$build/corpus" dict="$root/fuzz/request.dict" seeds=("$root"/examples/*.json "$root"/fuzz/seeds/* "$root"/fuzz/regressions/*) ;;
  http_seam) corpus="$build/corpus-http_seam" dict="$root/fuzz/http.dict" seeds=("$root"/fuzz/http_seeds/* "$root"/fuzz/http_regressions/*) ;;
  texture_decode) corpus="$build/corpus-texture_decode" dict="" seeds=("$root"/fuzz/texture_seeds/* "$root"/catalogue/textures/*) ;;
  *) echo "fuzz/run.sh: unknown FUZZ_TARGET '$target' (render_request, http_seam or texture_decode)" >&2; exit 2 ;;
esac

if ! command -v clang++ >/dev/null ||
  ! echo 'extern "C" int LLVMFuzzerTestOneInput(const char*, unsigned long) { return 0; }' |
  clang++ -x c++ -fsanitize=fuzzer -o /dev/null - 2>/dev/null; then
  echo "fuzz/run.sh: clang++ with libFuzzer (Debian: clang libclang-rt-dev) is not installed; not fuzzing"
  exit 77
fi

launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S "$root" -B "$build" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo "${launcher[@]}" \
  -DROOMRENDER_FUZZ=ON -DROOMRENDER_WERROR=ON -DROOMRENDER_TESTS=OFF -DROOMRENDER_BENCH=OFF >/dev/null
nice -n 10 cmake --build "$build" -j"${JOBS:-2}" --target "fuzz_$target"

mkdir -p "$corpus" "$build/artifacts"
for seed in "${seeds[@]}"; do
  if [ -f "$seed" ] && [ "$(basename "$seed")" != .gitkeep ]; then cp -n "$seed" "$corpus/"; fi
done

# -error_exitcode=1: libFuzzer's own default, 77, is the code that tells ctest a test was skipped.
# -timeout: one input takes milliseconds (a <= 32x32 render, or one request parsed twice); 10 s is a hang.
# -rss_limit_mb: the harnesses' caps keep a run far below this; beyond it is a finding.
# -max_len: room for the largest example (apartment.json, ~7 kB) to grow, and for request lines past
#  the 8190-byte cap.
cd "$build"
nice -n 10 "./fuzz/fuzz_$target" "$corpus" \
  ${dict:+-dict="$dict"} -max_total_time="$seconds" -error_exitcode=1 -timeout=10 -rss_limit_mb=2048 \
  -max_len=16384 -workers=1 -artifact_prefix="$build/artifacts/" -print_final_stats=1 "$@" \
  2>&1 | tee -a "$build/fuzz.log"
