#!/usr/bin/env bash
# Installs clients/web's npm packages (esbuild, CodeMirror, playwright-core, ...) from its lockfile
# when node_modules is missing or was installed from another lockfile. Called by
# scripts/install-deps.sh and by the web.npm_ci CTest fixture; a second run does nothing.
set -euo pipefail
cd "$(dirname "$0")"
stamp=node_modules/.installed-from-package-lock.json
if [ -f "$stamp" ] && cmp -s package-lock.json "$stamp"; then
  exit 0
fi
echo "clients/web: npm ci"
npm ci --no-audit --no-fund --loglevel=error
cp package-lock.json "$stamp"
