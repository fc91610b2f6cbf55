#!/usr/bin/env bash
# Installs the Debian packages roomrender builds and tests with. Idempotent: asks apt only for what
# is missing, so a second run is instant and needs no network.
#   scripts/install-deps.sh          everything the README's commands need (build + all tests)
#   scripts/install-deps.sh build    only what compiling and the C++ tests need (the Dockerfile's
#                                    build stage uses this, so the image never carries test tools)
#   scripts/install-deps.sh [build|all] PACKAGE...   also installs the extra packages given
#                                    (bench/install-bench-deps.sh passes the benchmark's)
set -euo pipefail

build_packages=(
  build-essential cmake pkg-config
  libcpp-httplib-dev nlohmann-json3-dev libglm-dev libstb-dev googletest libgtest-dev
  zlib1g-dev libpugixml-dev libzip-dev libpng-dev libturbojpeg0-dev
  libpq-dev
)
# clang-format-14 is pinned: another version formats differently and scripts/check-format.sh, run by
# .ci/run, holds the tree to this one.
test_packages=(
  curl ca-certificates python3 python3-yaml nginx-light chromium fonts-dejavu-core
  postgresql clang-format-14
)

mode=all
case "${1:-}" in
  build | all) mode="$1"; shift ;;
esac
if [ "$mode" = build ]; then packages=("${build_packages[@]}" "$@"); else packages=("${build_packages[@]}" "${test_packages[@]}" "$@"); fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# node and npm run the schema test (tests/schema), build the web page and drive Chromium in the
# browser tests. Any node >= 18 will do, also one installed from
# elsewhere, so Debian's are asked for only when the commands are missing.
if [ "$mode" = all ] && { ! command -v node >/dev/null || ! command -v npm >/dev/null; }; then
  missing+=(nodejs npm)
fi

if [ ${#missing[@]} -gt 0 ]; then
  echo "install-deps: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# ajv and swagger-parser for the schema tests, from their lockfile, once (node_modules is not committed).
if [ "$mode" = all ]; then "$(dirname "$0")/npm-ci-if-needed.sh" "$(dirname "$0")/../tests/schema"; fi

# The web client's npm packages (esbuild, CodeMirror, playwright-core), from its lockfile, once.
if [ "$mode" = all ]; then "$(dirname "$0")/npm-ci-if-needed.sh" "$(dirname "$0")/../clients/web"; fi
