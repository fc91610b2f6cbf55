#!/usr/bin/env bash
# Renders a request (scene + camera + options) to a PNG and prints the stage timings.
#   clients/curl/render.sh examples/studio.json studio.png
# The PNG answer carries the timings in Server-Timing and the static geometry's hash in X-Scene-Id.
set -euo pipefail
. "$(dirname "$0")/common.sh"
request="${1:?usage: render.sh REQUEST.json OUT.png}"
out="${2:?usage: render.sh REQUEST.json OUT.png}"
headers="$(mktemp)"
trap 'rm -f "$headers"' EXIT
fetch_to "$out" -X POST -H 'Content-Type: application/json' --data-binary @"$request" -D "$headers" \
  "$ROOMRENDER_URL/v1/render"
grep -i -E '^(server-timing|x-scene-id|x-cache):' "$headers"
echo "wrote $out"
