#!/usr/bin/env bash
# Installs the Debian packages roomrender builds and tests with. Idempotent: asks apt only for what
# is missing, so a second run is instant and needs no network.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libcpp-httplib-dev nlohmann-json3-dev libglm-dev libstb-dev googletest libgtest-dev
  zlib1g-dev
  curl ca-certificates
  python3 chromium fonts-dejavu-core
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

# node and npm build the web page and drive Chromium in the browser tests. Any node >= 18 will do,
# also one installed from elsewhere (whose nodejs may conflict with Debian's npm), so Debian's are
# asked for only when the commands are missing.
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
  missing+=(nodejs npm)
fi

if [ ${#missing[@]} -gt 0 ]; then
  echo "install-deps: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# The web client's npm packages (esbuild, CodeMirror, playwright-core), from its lockfile, once.
"$(dirname "$0")/../clients/web/npm-ci-if-needed.sh"
