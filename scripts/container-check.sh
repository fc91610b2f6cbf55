#!/usr/bin/env bash
# Proves the Dockerfile builds and the image serves what its users touch, on a machine without a
# Docker engine:
#   1. the deployment files read against the Dockerfile (tests/deploy/check_manifests.py);
#   2. a debian:bookworm base made with debootstrap (cached in $ROOMRENDER_BASE_DIR) and imported
#      into podman as docker.io/library/debian:bookworm (so the Dockerfile is untouched);
#   3. podman build --isolation chroot --pull=never, then the image's configuration (user, health
#      check, schemas and data directories, volume);
#   4. the image's server run with buildah (`podman run` needs cgroups this kind of machine lacks)
#      with the image's own environment: a render, the web page, /openapi.json, a schema, the
#      furniture catalogue (its entries, an icon, a read-only catalogue mesh), textures (the
#      textured example's PNGs; a Sweet Home 3D home whose catalogue textures, JPEGs compiled into
#      the binary, are imported and rendered), an OBJ import stored with store=1, the stored scene rendered by id (also anti-aliased) and picked,
#      /metrics, the health check;
#   5. SIGTERM, a second start of the same container, and the stored scene still there (the data
#      directory is the image's VOLUME, written by the image's user).
#   6. with --attacks, bench/attacks.py against the image's server (second start; its attacks share
#      that one server), its table merged under the label "container" into bench/results/attacks.md
#      (about 3 minutes more; .ci/run leaves it out).
# Prints the image size, the time from starting the container to the first successful render and
# one PASS/FAIL line per check; exits 1 if any check fails.
# Usage: scripts/container-check.sh [--attacks] [IMAGE_TAG]   (needs root; installs podman, buildah,
#        debootstrap, curl, python3-yaml idempotently)
set -euo pipefail
cd "$(dirname "$0")/.."
attacks=""
if [ "${1:-}" = --attacks ]; then attacks=1; shift; fi
tag="${1:-localhost/roomrender:check}"
base_dir="${ROOMRENDER_BASE_DIR:-/var/tmp/roomrender-base}"
port="${ROOMRENDER_CHECK_PORT:-18080}"
runtime_uid=10001
work="$(mktemp -d "${TMPDIR:-/tmp}/roomrender-container.XXXXXX")"
build_log="${TMPDIR:-/tmp}/roomrender-container-build.log"
url="http://127.0.0.1:$port"

checks=0
failures=0
pass() { checks=$((checks + 1)); echo "container-check: PASS $*"; }
fail() { checks=$((checks + 1)); failures=$((failures + 1)); echo "container-check: FAIL $*"; }
# A failure after which nothing else can be checked.
give_up() { fail "$*"; echo "container-check: FAILED ($failures of $checks checks; the rest could not run)"; exit 1; }

need=()
for p in podman buildah debootstrap curl; do command -v "$p" >/dev/null || need+=("$p"); done
python3 -c 'import yaml' 2>/dev/null || need+=(python3-yaml)
if [ ${#need[@]} -gt 0 ]; then
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${need[@]}" >/dev/null
fi

if python3 tests/deploy/check_manifests.py . >"$work/manifests.txt" 2>&1; then
  pass "deploy manifests agree with the Dockerfile ($(grep -c PASS "$work/manifests.txt") checks, tests/deploy/check_manifests.py)"
else
  grep -v PASS "$work/manifests.txt" | sed 's/^/  /'
  fail "deploy manifests (tests/deploy/check_manifests.py, above)"
fi

if ! podman image exists docker.io/library/debian:bookworm; then
  if [ ! -x "$base_dir/rootfs/usr/bin/apt-get" ]; then
    echo "container-check: debootstrap bookworm into $base_dir/rootfs (a few minutes, once)"
    rm -rf "$base_dir/rootfs"
    mkdir -p "$base_dir"
    debootstrap --variant=minbase bookworm "$base_dir/rootfs" http://deb.debian.org/debian >"$base_dir/debootstrap.log"
  fi
  tar -C "$base_dir/rootfs" -c . | podman import - docker.io/library/debian:bookworm >/dev/null
fi

echo "container-check: podman build -t $tag (log: $build_log)"
build_start=$(date +%s)
podman build --format docker --isolation chroot --pull=never -t "$tag" . >"$build_log" 2>&1 || {
  tail -40 "$build_log"; give_up "podman build"; }
pass "podman build (in $(( $(date +%s) - build_start )) s; -Werror, unit tests passed in the build stage)"
size_bytes=$(podman image inspect --format '{{.Size}}' "$tag")
echo "container-check: image size $(( size_bytes / 1000000 )) MB ($size_bytes bytes)"

# --- The image's configuration, as a runtime reads it ----------------------------------------------
inspect() { podman image inspect --format "$1" "$tag"; }
user=$(inspect '{{.Config.User}}')
[ "$user" = roomrender ] && pass "image user is roomrender" || fail "image user is '$user', not roomrender"
health=$(inspect '{{json .Config.Healthcheck}}')
if echo "$health" | grep -q livez && echo "$health" | grep -qF "/dev/tcp/127.0.0.1/\${ROOMRENDER_PORT}"; then
  pass "HEALTHCHECK on /livez"
else
  fail "HEALTHCHECK on /livez (or it changed and this check needs updating): $health"
fi
env_list=$(inspect '{{json .Config.Env}}')
schemas_dir=$(echo "$env_list" | python3 -c 'import json,sys; print(next((e.split("=",1)[1] for e in json.load(sys.stdin) if e.startswith("ROOMRENDER_SCHEMAS_DIR=")), ""))')
data_dir=$(echo "$env_list" | python3 -c 'import json,sys; print(next((e.split("=",1)[1] for e in json.load(sys.stdin) if e.startswith("ROOMRENDER_DATA_DIR=")), ""))')
volumes=$(inspect '{{json .Config.Volumes}}')
[ "$schemas_dir" = /usr/share/roomrender/schemas ] && pass "ROOMRENDER_SCHEMAS_DIR=$schemas_dir" ||
  fail "ROOMRENDER_SCHEMAS_DIR is '$schemas_dir', not /usr/share/roomrender/schemas"
if [ -n "$data_dir" ] && echo "$volumes" | grep -qF "\"$data_dir\""; then
  pass "ROOMRENDER_DATA_DIR=$data_dir, a VOLUME"
else
  fail "ROOMRENDER_DATA_DIR is '$data_dir', volumes $volumes"
fi

# --- The image's server ------------------------------------------------------------------------------
ctr=$(buildah from --pull-never "$tag")
server_pid=""
cleanup() {
  [ -n "$server_pid" ] && kill "$server_pid" 2>/dev/null || true
  buildah rm "$ctr" >/dev/null 2>&1 || true
  rm -rf "$work"
}
trap cleanup EXIT

# The image's own environment (data directory included); only the port differs, so a busy 8080
# cannot clash, and the bind, so nothing outside this machine can reach the server.
start_server() {
  buildah run --isolation chroot --env ROOMRENDER_PORT="$port" --env ROOMRENDER_BIND=127.0.0.1 "$ctr" \
    -- /usr/local/bin/roomrender serve >"$1" 2>&1 &
  server_pid=$!
}

# buildah run does not forward signals, but with chroot isolation the server is an ordinary process
# of this machine: find it to signal it directly, as a container runtime would, and to read its uid.
descendants() { local p; for p in $(pgrep -P "$1"); do echo "$p"; descendants "$p"; done; }
server_process() {
  local p
  for p in $(descendants "$server_pid"); do
    [ "$(cat /proc/"$p"/comm 2>/dev/null)" = roomrender ] && { echo "$p"; return; }
  done
  return 0
}

stop_server() {  # $1: the server's log
  local inner rc
  inner=$(server_process)
  [ -n "$inner" ] || give_up "server process not found"
  kill -TERM "$inner"
  wait "$server_pid" && rc=0 || rc=$?
  server_pid=""
  if [ "$rc" -eq 0 ] && grep -q '"event":"stopped"' "$1"; then
    pass "SIGTERM -> drained, exit 0"
  else
    tail -5 "$1"; fail "SIGTERM -> exit $rc, stopped event $(grep -c '"event":"stopped"' "$1")"
  fi
}

# GET (or any method with curl's arguments) -> "STATUS MEDIA_TYPE", the body in $out.
fetch() {
  local path="$1"; shift
  curl -s -o "$work/out" -w '%{http_code} %{content_type}' "$@" "$url$path" || true
}
is_png() { [ "$(head -c 8 "$1" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ]; }
json_field() { python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])' "$@" 2>/dev/null; }

log1="$work/serve-1.log"
start_ns=$(date +%s%N)
start_server "$log1"
rendered=""
for _ in $(seq 1 600); do
  if curl -sf -o "$work/first.png" -H 'Content-Type: application/json' \
       --data-binary @examples/studio.json "$url/v1/render"; then
    rendered=1
    break
  fi
  kill -0 "$server_pid" 2>/dev/null || { cat "$log1"; give_up "server exited at start"; }
  sleep 0.05
done
first_ms=$(( ($(date +%s%N) - start_ns) / 1000000 ))
[ -n "$rendered" ] || { tail -5 "$log1"; give_up "no render within 30 s of start"; }
if is_png "$work/first.png"; then
  pass "POST /v1/render -> PNG ($(stat -c %s "$work/first.png") bytes)"
  echo "container-check: first successful render $first_ms ms after start"
else
  fail "POST /v1/render answered something other than a PNG"
fi

inner=$(server_process)
uid=""
[ -z "$inner" ] || uid=$(awk '/^Uid:/ {print $2}' /proc/"$inner"/status)
[ "$uid" = "$runtime_uid" ] && pass "server runs as uid $uid" || fail "server runs as uid '${uid:-?}', not $runtime_uid"
grep -qF "\"data_dir\":\"$data_dir\"" "$log1" && pass "server keeps stored scenes in $data_dir" ||
  fail "server's data_dir is not $data_dir: $(grep -o '"data_dir":[^,]*' "$log1")"

got=$(fetch /livez)
[ "${got%% *}" = 200 ] && pass "GET /livez -> $got" || fail "GET /livez -> $got"

got=$(fetch /)
if [ "${got%% *}" = 200 ] && [[ "$got" == *text/html* ]] && grep -qi "<html" "$work/out"; then
  pass "GET / -> $got (the web page)"
else
  fail "GET / -> $got"
fi

got=$(fetch /openapi.json)
if [ "${got%% *}" = 200 ] && [ -n "$(json_field "$work/out" openapi)" ]; then
  pass "GET /openapi.json -> $got (OpenAPI $(json_field "$work/out" openapi))"
else
  fail "GET /openapi.json -> $got"
fi

got=$(fetch /v1/schemas/request.schema.json)
if [ "${got%% *}" = 200 ] && [ -n "$(json_field "$work/out" '$schema')" ]; then
  pass "GET /v1/schemas/request.schema.json -> $got"
else
  fail "GET /v1/schemas/request.schema.json -> $got"
fi

# The furniture catalogue from the image's copy: its entries, an icon, a catalogue mesh read-only.
got=$(fetch /v1/catalogue)
items=$(python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); print(len(d["items"]))' "$work/out" 2>/dev/null || echo 0)
chair_ref=$(python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); print(next(i["piece"]["parts"][0]["ref"] for i in d["items"] if i["id"] == "chair"))' "$work/out" 2>/dev/null || true)
if [ "${got%% *}" = 200 ] && [ "$items" -ge 30 ] && [[ "$chair_ref" =~ ^[0-9a-f]{16}$ ]]; then
  pass "GET /v1/catalogue -> $got, $items entries"
else
  fail "GET /v1/catalogue -> $got: $(head -c 300 "$work/out")"
fi
got=$(fetch /v1/catalogue/chair/icon.png)
[ "${got%% *}" = 200 ] && is_png "$work/out" && pass "GET /v1/catalogue/chair/icon.png -> $got, PNG" ||
  fail "GET /v1/catalogue/chair/icon.png -> $got"
if [ -n "$chair_ref" ]; then
  got=$(fetch "/v1/meshes/$chair_ref" -X DELETE)
  [ "${got%% *}" = 403 ] && pass "DELETE /v1/meshes/$chair_ref (a catalogue mesh) -> $got" ||
    fail "DELETE /v1/meshes/$chair_ref -> $got"
fi

# Textures: the textured example (PNG images, libpng), then a Sweet Home 3D home whose floor and
# wall side name default-catalogue textures (JPEGs compiled into the binary, libjpeg-turbo): the
# import carries them as data: URIs, and the textured render is a PNG far larger than the same room
# without them (texels do not compress as flat colours do).
got=$(fetch /v1/render -H 'Content-Type: application/json' --data-binary @examples/studio_textured.json)
[ "${got%% *}" = 200 ] && is_png "$work/out" && pass "POST /v1/render examples/studio_textured.json -> $got, PNG" ||
  fail "POST /v1/render examples/studio_textured.json -> $got: $(head -c 300 "$work/out")"
sh3d_room() {
  printf '%s' "<home wallHeight='250'><observerCamera attribute='observerCamera' x='200' y='280' z='160' \
yaw='3.1415927' pitch='0.25' fieldOfView='1.2'/><wall id='w' xStart='0' yStart='0' xEnd='400' yEnd='0' height='250' \
thickness='10'>$2</wall><room name='R'><point x='0' y='0'/><point x='400' y='0'/><point x='400' y='300'/>\
<point x='0' y='300'/>$1</room></home>"
}
sh3d_room "<texture attribute='floorTexture' catalogId='eTeks#redTiles' name='t' width='40' height='40' image='r'/>" \
  "<texture attribute='rightSideTexture' catalogId='eTeks#smallBricks' name='b' width='23' height='14.9' image='b'/>" \
  >"$work/textured.xml"
sh3d_room "" "" >"$work/plain.xml"
for kind in textured plain; do
  fetch '/v1/import/sh3d?width=320&height=240' -H 'Content-Type: application/xml' \
    --data-binary @"$work/$kind.xml" >/dev/null
  cp "$work/out" "$work/$kind.json"
  fetch /v1/render -H 'Content-Type: application/json' --data-binary @"$work/$kind.json" >/dev/null
  cp "$work/out" "$work/$kind.png"
done
jpegs=$(grep -o 'data:image/jpeg;base64,' "$work/textured.json" | wc -l)
textured_bytes=$(stat -c %s "$work/textured.png") plain_bytes=$(stat -c %s "$work/plain.png")
if [ "$jpegs" -ge 2 ] && is_png "$work/textured.png" && is_png "$work/plain.png" &&
  [ "$textured_bytes" -gt $((4 * plain_bytes)) ]; then
  pass "Sweet Home 3D catalogue textures imported ($jpegs JPEGs) and rendered: $textured_bytes-byte PNG, $plain_bytes untextured"
else
  fail "Sweet Home 3D catalogue textures: $jpegs JPEGs, PNGs of $textured_bytes and $plain_bytes bytes: $(head -c 300 "$work/textured.png")"
fi

# The texture catalogue from the image's copy, and the same textured home imported with store=1:
# its scene names the catalogue's images by id (no data: URI), and the stored scene renders textured.
got=$(fetch /v1/catalogue/textures)
textures=$(python3 -c 'import json,sys; print(len(json.load(open(sys.argv[1]))["textures"]))' "$work/out" 2>/dev/null || echo 0)
[ "${got%% *}" = 200 ] && [ "$textures" -eq 26 ] && pass "GET /v1/catalogue/textures -> $got, $textures images" ||
  fail "GET /v1/catalogue/textures -> $got, $textures images: $(head -c 300 "$work/out")"
got=$(fetch '/v1/import/sh3d?store=1&width=320&height=240' -H 'Content-Type: application/xml' \
  --data-binary @"$work/textured.xml")
location=$(json_field "$work/out" location || true)
fetch "$location" >/dev/null
ids=$(grep -o '"image":"[0-9a-f]\{16\}"' "$work/out" | sort -u | wc -l)
uris=$(grep -c 'data:' "$work/out" || true)
fetch "$location/render.png?width=320&height=240" >/dev/null
cp "$work/out" "$work/stored-textured.png"
stored_bytes=$(stat -c %s "$work/stored-textured.png")
if [ "${got%% *}" = 201 ] && [ "$ids" -eq 2 ] && [ "$uris" -eq 0 ] && is_png "$work/stored-textured.png" &&
  [ "$stored_bytes" -gt $((4 * plain_bytes)) ]; then
  pass "textured home stored with store=1 -> $got, $ids images by id, rendered: $stored_bytes-byte PNG"
else
  fail "textured home with store=1 -> $got, $ids ids, $uris data: URIs, $stored_bytes-byte PNG: $(head -c 300 "$work/out")"
fi

# A unit cube as a Wavefront OBJ, imported and stored in one request.
printf 'v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nv 0 1 0\nv 1 1 0\nv 1 1 1\nv 0 1 1\n%s\n' \
  'f 1 2 3 4
f 5 8 7 6
f 1 5 6 2
f 2 6 7 3
f 3 7 8 4
f 4 8 5 1' >"$work/cube.obj"
got=$(fetch '/v1/import/obj?store=1' -H 'Content-Type: model/obj' --data-binary @"$work/cube.obj")
id=$(json_field "$work/out" id || true)
if [ "${got%% *}" = 201 ] && [[ "$id" =~ ^[0-9a-f]{16}$ ]]; then
  pass "POST /v1/import/obj?store=1 (a cube) -> $got, scene $id"
else
  fail "POST /v1/import/obj?store=1 -> $got: $(head -c 300 "$work/out")"
fi

if [ -n "$id" ]; then
  got=$(fetch "/v1/scenes/$id/render.png?width=320&height=240")
  [ "${got%% *}" = 200 ] && is_png "$work/out" && pass "GET /v1/scenes/$id/render.png -> $got, PNG" ||
    fail "GET /v1/scenes/$id/render.png -> $got"
  got=$(fetch "/v1/scenes/$id/render.png?width=320&height=240&antialias=4")
  [ "${got%% *}" = 200 ] && is_png "$work/out" && pass "GET /v1/scenes/$id/render.png?antialias=4 -> $got, PNG" ||
    fail "GET /v1/scenes/$id/render.png?antialias=4 -> $got"
  # The pixel at the centre of a framed view of the cube is the cube: the only element, /solids/0.
  got=$(fetch "/v1/scenes/$id/pick" -H 'Content-Type: application/json' \
          --data '{"camera":{"frame":"all"},"options":{"width":64,"height":48},"x":32,"y":24}')
  picked=$(json_field "$work/out" pointer || true)
  [ "${got%% *}" = 200 ] && [ "$picked" = /solids/0 ] && pass "POST /v1/scenes/$id/pick (framed, centre) -> $picked" ||
    fail "POST /v1/scenes/$id/pick -> $got: $(head -c 300 "$work/out")"
  owner=$(buildah run --isolation chroot "$ctr" -- stat -c %u "$data_dir/scenes/$id.json" 2>&1 | tail -1 || true)
  [ "$owner" = "$runtime_uid" ] && pass "$data_dir/scenes/$id.json written, owned by uid $owner" ||
    fail "$data_dir/scenes/$id.json: $owner"
fi

got=$(fetch /metrics)
if [ "${got%% *}" = 200 ] && [[ "$got" == *text/plain* ]] &&
   grep -q '^# TYPE roomrender_http_requests_total counter' "$work/out" &&
   grep -q 'route="/v1/import/{format}"' "$work/out"; then
  pass "GET /metrics -> $got (Prometheus text, the import counted)"
else
  fail "GET /metrics -> $got"
fi

# The image's health check command itself, inside the container, against the live server.
if buildah run --isolation chroot --env ROOMRENDER_PORT="$port" "$ctr" -- bash -c \
     "exec 3<>/dev/tcp/127.0.0.1/\${ROOMRENDER_PORT} && printf 'GET /livez HTTP/1.0\r\n\r\n' >&3 && head -n1 <&3 | grep -q ' 200 '"; then
  pass "the HEALTHCHECK command passes inside the container"
else
  fail "the HEALTHCHECK command fails inside the container"
fi

stop_server "$log1"

# --- Restart: the same container, its data volume kept --------------------------------------------------
log2="$work/serve-2.log"
start_server "$log2"
up=""
for _ in $(seq 1 600); do
  curl -sf -o /dev/null "$url/livez" && { up=1; break; }
  kill -0 "$server_pid" 2>/dev/null || { cat "$log2"; give_up "server exited at its second start"; }
  sleep 0.05
done
[ -n "$up" ] || give_up "no /livez within 30 s of the second start"
if [ -n "$id" ]; then
  got=$(fetch "/v1/scenes/$id")
  [ "${got%% *}" = 200 ] && [ -n "$(json_field "$work/out" solids)" ] &&
    pass "after a restart GET /v1/scenes/$id -> $got (kept in $data_dir)" ||
    fail "after a restart GET /v1/scenes/$id -> $got"
  got=$(fetch "/v1/scenes/$id/render.png?width=320&height=240")
  [ "${got%% *}" = 200 ] && is_png "$work/out" && pass "after a restart GET /v1/scenes/$id/render.png -> $got, PNG" ||
    fail "after a restart GET /v1/scenes/$id/render.png -> $got"
fi

# The hostile-client benchmark against the image's own binary (built in the image's build stage from
# the same sources as build/roomrender, so the same code, though not the same bytes).
if [ -n "$attacks" ]; then
  echo "container-check: image binary sha256 $(buildah run --isolation chroot "$ctr" -- sha256sum /usr/local/bin/roomrender | cut -c1-16)…"
  if python3 bench/attacks.py --port "$port" --label container; then
    pass "bench/attacks.py against the image's server (table: bench/results/attacks.md, label container)"
  else
    fail "bench/attacks.py against the image's server"
  fi
fi
stop_server "$log2"

if [ "$failures" -eq 0 ]; then
  echo "container-check: OK ($checks checks)"
else
  echo "container-check: FAILED ($failures of $checks checks)"
  exit 1
fi
