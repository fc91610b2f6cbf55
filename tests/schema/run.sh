#!/usr/bin/env bash
# CTest entry of the schema test: installs its npm packages from the lockfile when they are missing
# (normally scripts/install-deps.sh or the schema.npm_ci fixture has done that), then runs run.mjs
# against the built server.
#   tests/schema/run.sh BUILD/roomrender REPOSITORY_ROOT
set -euo pipefail
binary="$(realpath "$1")"
repo="$(realpath "$2")"
cd "$(dirname "$0")"
../../scripts/npm-ci-if-needed.sh .
exec node run.mjs "$binary" "$repo"
