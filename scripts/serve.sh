#!/usr/bin/env bash
# Builds roomrender and serves it with the web page and bundled examples:
#   scripts/serve.sh            -> http://127.0.0.1:8080/
#   PORT=9000 BIND=0.0.0.0 scripts/serve.sh
# Stored scenes and meshes are kept across restarts in ROOMRENDER_DATA_DIR, by default
# ${XDG_DATA_HOME:-~/.local/share}/roomrender; ROOMRENDER_DATA_DIR= (empty) keeps them in memory only.
# Installs its Debian packages first (idempotent).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh build   # serving needs no test tools (the web page is a committed bundle)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)" --target roomrender
data_dir=${ROOMRENDER_DATA_DIR-${XDG_DATA_HOME:-$HOME/.local/share}/roomrender}
echo "roomrender: open http://${BIND:-127.0.0.1}:${PORT:-8080}/ (the apartment example is preselected)"
if [ -n "$data_dir" ]; then
  mkdir -p "$data_dir"
  echo "roomrender: stored scenes are kept in $data_dir"
  exec build/roomrender serve --port "${PORT:-8080}" --bind "${BIND:-127.0.0.1}" --data-dir "$data_dir"
fi
exec env -u ROOMRENDER_DATA_DIR build/roomrender serve --port "${PORT:-8080}" --bind "${BIND:-127.0.0.1}"
