#!/usr/bin/env bash
# Builds roomrender and runs every test suite: the README's test command, and what .ci/run calls.
# Installs its Debian packages first (idempotent). Warnings are errors here.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DROOMRENDER_WERROR=ON
cmake --build build -j"$(nproc)"
ctest --test-dir build --output-on-failure -j"$(nproc)" "$@"
