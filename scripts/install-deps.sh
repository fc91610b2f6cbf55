#!/usr/bin/env bash
# Installs the Debian packages roomrender builds and tests with. Idempotent: asks apt only for what
# is missing, so a second run is instant and needs no network. Extra package names given as arguments
# are installed the same way (bench/install-bench-deps.sh passes the benchmark's).
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libcpp-httplib-dev nlohmann-json3-dev libglm-dev libstb-dev googletest libgtest-dev
  curl ca-certificates
  "$@"
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -gt 0 ]; then
  echo "install-deps: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
