#!/usr/bin/env bash
# Renders a camera path: FRAMES views turning once around the request's camera target, into
# OUT_DIR/frame_0001.png ... with a progress bar. The scene is stored once; each frame is a GET of
# the stored scene's render.png with the camera in the query. awk computes the path.
#   clients/curl/orbit.sh examples/studio.json 36 frames/
#   ffmpeg -i frames/frame_%04d.png orbit.mp4      # (not part of roomrender) to make a video
set -euo pipefail
. "$(dirname "$0")/common.sh"
request="${1:?usage: orbit.sh REQUEST.json FRAMES OUT_DIR [WIDTH HEIGHT]}"
frames="${2:?usage: orbit.sh REQUEST.json FRAMES OUT_DIR [WIDTH HEIGHT]}"
out_dir="${3:?usage: orbit.sh REQUEST.json FRAMES OUT_DIR [WIDTH HEIGHT]}"
width="${4:-320}"
height="${5:-240}"
mkdir -p "$out_dir"

# Scene document and the start camera (defaults as in docs/scene-format.md), via python3.
read -r px py pz tx ty tz < <(python3 -c '
import json, sys
request = json.load(open(sys.argv[1]))
json.dump(request["scene"], open(sys.argv[2], "w"))
camera = {"position": [0, 1.6, 5], "target": [0, 1, 0], **request.get("camera", {})}
print(*camera["position"], *camera["target"])' "$request" "$out_dir/scene.json")
fetch_to "$out_dir/receipt.json" -X POST -H 'Content-Type: application/json' --data-binary @"$out_dir/scene.json" \
  -D "$out_dir/receipt.headers" "$ROOMRENDER_URL/v1/scenes"
location="$(tr -d '\r' < "$out_dir/receipt.headers" | sed -n 's/^[Ll]ocation: //p')"

awk -v n="$frames" -v px="$px" -v pz="$pz" -v tx="$tx" -v tz="$tz" 'BEGIN {
  r = sqrt((px - tx) ^ 2 + (pz - tz) ^ 2); a0 = atan2(px - tx, pz - tz); pi = atan2(0, -1)
  for (i = 0; i < n; i++) { a = a0 + 2 * pi * i / n; printf "%.6f %.6f\n", tx + r * sin(a), tz + r * cos(a) }
}' | {
  i=0
  while read -r x z; do
    i=$((i + 1))
    file="$(printf '%s/frame_%04d.png' "$out_dir" "$i")"
    fetch_to "$file" "$ROOMRENDER_URL$location/render.png?position=$x,$py,$z&target=$tx,$ty,$tz&width=$width&height=$height"
    filled=$((30 * i / frames))
    printf '\r[%s%s] %d/%d %s' "$(printf '%*s' "$filled" '' | tr ' ' '#')" \
      "$(printf '%*s' $((30 - filled)) '' | tr ' ' '.')" "$i" "$frames" "$(basename "$file")" >&2
  done
  echo >&2
}
echo "wrote $frames frames to $out_dir"
