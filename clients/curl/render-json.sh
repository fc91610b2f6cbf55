#!/usr/bin/env bash
# Renders a request and asks for the JSON answer: the PNG in base64 with per-stage timings, polygon
# counts, cache outcome and placement warnings. Prints the JSON without the image and writes the
# image (python3 decodes it).
#   clients/curl/render-json.sh examples/apartment.json apartment.png
set -euo pipefail
. "$(dirname "$0")/common.sh"
request="${1:?usage: render-json.sh REQUEST.json OUT.png}"
out="${2:?usage: render-json.sh REQUEST.json OUT.png}"
answer="$(mktemp)"
trap 'rm -f "$answer"' EXIT
fetch_to "$answer" -X POST -H 'Content-Type: application/json' -H 'Accept: application/json' \
  --data-binary @"$request" "$ROOMRENDER_URL/v1/render"
python3 -c '
import base64, json, sys
answer = json.load(open(sys.argv[1]))
open(sys.argv[2], "wb").write(base64.b64decode(answer.pop("png_base64")))
print(json.dumps(answer, indent=2))' "$answer" "$out"
