#!/usr/bin/env bash
# Imports a Sweet Home 3D home (Home.xml, or the .sh3d file) into a complete render request, then
# renders it from the home's own observer camera.
#   clients/curl/import-sh3d.sh Home.xml home.json home.png
set -euo pipefail
. "$(dirname "$0")/common.sh"
home="${1:?usage: import-sh3d.sh HOME.xml|HOME.sh3d REQUEST_OUT.json PNG_OUT}"
request="${2:?usage: import-sh3d.sh HOME.xml|HOME.sh3d REQUEST_OUT.json PNG_OUT}"
png="${3:?usage: import-sh3d.sh HOME.xml|HOME.sh3d REQUEST_OUT.json PNG_OUT}"
fetch_to "$request" -X POST -H 'Content-Type: application/octet-stream' --data-binary @"$home" \
  "$ROOMRENDER_URL/v1/import/sh3d?width=640&height=480"
fetch_to "$png" -X POST -H 'Content-Type: application/json' --data-binary @"$request" "$ROOMRENDER_URL/v1/render"
echo "wrote $request and $png"
