#!/usr/bin/env bash
# Installs the npm packages of DIR (clients/web: esbuild, CodeMirror, playwright-core, ...;
# tests/schema: ajv, swagger-parser) from its lockfile when node_modules is missing or was installed
# from another lockfile; a second run does nothing. Called by scripts/install-deps.sh and by the
# web.npm_ci and schema.npm_ci CTest fixtures (so tests never run npm ci side by side in one DIR).
# Usage: scripts/npm-ci-if-needed.sh DIR
set -euo pipefail
cd "$1"
stamp=node_modules/.installed-from-package-lock.json
if [ -f "$stamp" ] && cmp -s package-lock.json "$stamp"; then
  exit 0
fi
echo "$1: npm ci"
npm ci --no-audit --no-fund --loglevel=error
cp package-lock.json "$stamp"
