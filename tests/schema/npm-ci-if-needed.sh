#!/usr/bin/env bash
# Installs tests/schema's npm packages (ajv, swagger-parser) from its lockfile when node_modules is
# missing or was installed from another lockfile. Called by scripts/install-deps.sh and by the
# schema.npm_ci CTest fixture (so the schema tests never run npm ci side by side); a second run does
# nothing.
set -euo pipefail
cd "$(dirname "$0")"
stamp=node_modules/.installed-from-package-lock.json
if [ -f "$stamp" ] && cmp -s package-lock.json "$stamp"; then
  exit 0
fi
echo "tests/schema: npm ci"
npm ci --no-audit --no-fund --loglevel=error
cp package-lock.json "$stamp"
