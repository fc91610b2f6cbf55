#!/usr/bin/env bash
# Stores a scene once, then renders views of it by id: no scene upload, parse or tessellation per
# view. Takes a request file, stores its "scene" member, and writes three views into OUT_DIR:
#   view_post.png  POST /v1/scenes/{id}/render with {camera, options}
#   view_get.png   GET  /v1/scenes/{id}/render.png?position=...&target=...  (immutable: cacheable)
#   view_top.png   the same from above
#   clients/curl/store-and-render.sh examples/studio.json views/
set -euo pipefail
. "$(dirname "$0")/common.sh"
request="${1:?usage: store-and-render.sh REQUEST.json OUT_DIR}"
out_dir="${2:?usage: store-and-render.sh REQUEST.json OUT_DIR}"
mkdir -p "$out_dir"

# The scene member of the request is the scene document (python3 extracts it).
python3 -c 'import json, sys; json.dump(json.load(open(sys.argv[1]))["scene"], sys.stdout)' "$request" \
  > "$out_dir/scene.json"
fetch_to "$out_dir/receipt.json" -X POST -H 'Content-Type: application/json' --data-binary @"$out_dir/scene.json" \
  -D "$out_dir/receipt.headers" "$ROOMRENDER_URL/v1/scenes"
location="$(tr -d '\r' < "$out_dir/receipt.headers" | sed -n 's/^[Ll]ocation: //p')"
echo "stored at $location"

fetch_to "$out_dir/view_post.png" -X POST -H 'Content-Type: application/json' \
  --data '{"camera": {"position": [5.3, 1.6, 4], "target": [1.4, 1, 0.8]}, "options": {"width": 320, "height": 240}}' \
  "$ROOMRENDER_URL$location/render"
fetch_to "$out_dir/view_get.png" \
  "$ROOMRENDER_URL$location/render.png?position=5.3,1.6,4&target=1.4,1,0.8&width=320&height=240"
fetch_to "$out_dir/view_top.png" \
  "$ROOMRENDER_URL$location/render.png?position=3,12,2.3&target=3,0,2.25&width=320&height=240&pipeline=zbuffer"
echo "wrote $out_dir/view_post.png $out_dir/view_get.png $out_dir/view_top.png"
