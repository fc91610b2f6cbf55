#!/usr/bin/env bash
# CTest entry of the schema test: installs ajv from the lockfile when it is missing (normally
# scripts/install-deps.sh has done that), then runs run.mjs against the built server.
#   tests/schema/run.sh BUILD/roomrender REPOSITORY_ROOT
set -euo pipefail
binary="$(realpath "$1")"
repo="$(realpath "$2")"
cd "$(dirname "$0")"
if [ ! -f node_modules/ajv/package.json ]; then
  npm ci --no-audit --no-fund --loglevel=error
fi
exec node run.mjs "$binary" "$repo"
