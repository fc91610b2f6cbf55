#!/usr/bin/env bash
# Renders a Sweet Home 3D home with its furniture through a running service, as a client would:
# zips HOME.xml with the furniture/ folder beside it, POSTs the zip to /v1/import/sh3d?store=1
# (each distinct model becomes a stored mesh) and renders the stored scene from its observer camera.
# Usage: scripts/render-home.sh HOME.xml OUT.png [URL] [extra options as JSON, merged into "options"]
set -euo pipefail
home=${1:?HOME.xml}; out=${2:?OUT.png}; url=${3:-http://127.0.0.1:8080}; extra=${4:-'{}'}
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT

python3 - "$home" "$work/home.zip" <<'PY'
import os, sys, zipfile
home, out = sys.argv[1], sys.argv[2]
furniture = os.path.join(os.path.dirname(os.path.abspath(home)), "furniture")
with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as z:
    z.write(home, os.path.basename(home))
    for name in sorted(os.listdir(furniture)) if os.path.isdir(furniture) else []:
        z.write(os.path.join(furniture, name), "furniture/" + name)
PY

curl -sS --fail-with-body -H 'Content-Type: application/zip' --data-binary @"$work/home.zip" \
  "$url/v1/import/sh3d?store=1&width=800&height=600" -o "$work/receipt.json"
python3 - "$work/receipt.json" "$extra" > "$work/view.json" <<'PY'
import json, sys
receipt = json.load(open(sys.argv[1]))
options = dict(receipt["options"], **json.loads(sys.argv[2]))
json.dump({"camera": receipt["camera"], "options": options}, sys.stdout)
print(receipt["location"], file=sys.stderr)
PY
location=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["location"])' "$work/receipt.json")
curl -sS --fail-with-body -H 'Content-Type: application/json' --data-binary @"$work/view.json" \
  -D "$work/headers" "$url$location/render" -o "$out"
grep -i '^x-render-timing\|^x-scene-id\|^server-timing' "$work/headers" >&2 || true
echo "$out: $(stat -c %s "$out") bytes, scene $location" >&2
