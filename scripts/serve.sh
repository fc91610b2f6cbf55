#!/usr/bin/env bash
# Builds roomrender and serves it with the web page and bundled examples:
#   scripts/serve.sh            -> http://127.0.0.1:8080/
#   PORT=9000 BIND=0.0.0.0 scripts/serve.sh
# Installs its Debian packages first (idempotent).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh build   # serving needs no test tools (the web page is a committed bundle)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)" --target roomrender
echo "roomrender: open http://${BIND:-127.0.0.1}:${PORT:-8080}/ (the apartment example is preselected)"
exec build/roomrender serve --port "${PORT:-8080}" --bind "${BIND:-127.0.0.1}"
