#!/usr/bin/env bash
# Proves the Dockerfile builds and the image serves, on a machine without a Docker engine:
#   1. a debian:bookworm base made with debootstrap (cached in $ROOMRENDER_BASE_DIR) and imported
#      into podman as docker.io/library/debian:bookworm (so the Dockerfile is untouched);
#   2. podman build --isolation chroot --pull=never;
#   3. the image's server run with buildah (`podman run` needs cgroups this kind of machine lacks),
#      a render over HTTP, its PNG checked, then SIGTERM and a clean exit.
# Prints the image size and the time from starting the container to the first successful render.
# Usage: scripts/container-check.sh [IMAGE_TAG]        (needs root; installs podman, buildah,
#        debootstrap, curl idempotently)
set -euo pipefail
cd "$(dirname "$0")/.."
tag="${1:-localhost/roomrender:check}"
base_dir="${ROOMRENDER_BASE_DIR:-/var/tmp/roomrender-base}"
port="${ROOMRENDER_CHECK_PORT:-18080}"

need=()
for p in podman buildah debootstrap curl; do command -v "$p" >/dev/null || need+=("$p"); done
if [ ${#need[@]} -gt 0 ]; then
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${need[@]/curl/curl}" >/dev/null
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

echo "container-check: podman build -t $tag"
build_start=$(date +%s)
podman build --format docker --isolation chroot --pull=never -t "$tag" . >"${TMPDIR:-/tmp}/roomrender-container-build.log" 2>&1 || {
  tail -40 "${TMPDIR:-/tmp}/roomrender-container-build.log"; echo "container-check: build FAILED"; exit 1; }
echo "container-check: built in $(( $(date +%s) - build_start )) s"
size_bytes=$(podman image inspect --format '{{.Size}}' "$tag")
echo "container-check: image size $(( size_bytes / 1000000 )) MB ($size_bytes bytes)"

ctr=$(buildah from --pull-never "$tag")
log="${TMPDIR:-/tmp}/roomrender-container-serve.log"
cleanup() {
  [ -n "${server_pid:-}" ] && kill "$server_pid" 2>/dev/null || true
  buildah rm "$ctr" >/dev/null 2>&1 || true
}
trap cleanup EXIT

start_ns=$(date +%s%N)
# The image's own entrypoint and environment; only the port differs, so a busy 8080 cannot clash.
buildah run --isolation chroot --env ROOMRENDER_PORT="$port" --env ROOMRENDER_BIND=127.0.0.1 "$ctr" \
  -- /usr/local/bin/roomrender serve >"$log" 2>&1 &
server_pid=$!

png="${TMPDIR:-/tmp}/roomrender-container.png"
for _ in $(seq 1 200); do
  if curl -sf -o "$png" -H 'Content-Type: application/json' \
       --data-binary @examples/studio.json "http://127.0.0.1:$port/v1/render"; then
    break
  fi
  kill -0 "$server_pid" 2>/dev/null || { cat "$log"; echo "container-check: server exited"; exit 1; }
  sleep 0.05
done
first_ms=$(( ($(date +%s%N) - start_ns) / 1000000 ))
head -c 8 "$png" | od -An -tx1 | grep -q "89 50 4e 47 0d 0a 1a 0a" || { echo "container-check: not a PNG"; exit 1; }
echo "container-check: first successful render $first_ms ms after start ($(stat -c %s "$png") bytes PNG)"
curl -sf "http://127.0.0.1:$port/livez" >/dev/null && echo "container-check: /livez answers"
curl -sf "http://127.0.0.1:$port/" | grep -qi "<html" && echo "container-check: web page served"

# The image's user and the health check command, as a runtime would see them.
user=$(podman image inspect --format '{{.Config.User}}' "$tag")
[ "$user" = "roomrender" ] || { echo "container-check: image user is '$user', not roomrender"; exit 1; }
health=$(podman image inspect --format '{{json .Config.Healthcheck}}' "$tag")
echo "$health" | grep -q livez || { echo "container-check: no HEALTHCHECK on /livez: $health"; exit 1; }
# Run the image's health check command itself, inside the container, against the live server.
buildah run --isolation chroot --env ROOMRENDER_PORT="$port" "$ctr" -- bash -c \
  "exec 3<>/dev/tcp/127.0.0.1/\${ROOMRENDER_PORT} && printf 'GET /livez HTTP/1.0\r\n\r\n' >&3 && head -n1 <&3 | grep -q ' 200 '" \
  || { echo "container-check: the HEALTHCHECK command fails"; exit 1; }
echo "$health" | grep -qF "/dev/tcp/127.0.0.1/\${ROOMRENDER_PORT}" || { echo "container-check: HEALTHCHECK changed; update this check"; exit 1; }
echo "container-check: runs as $user; HEALTHCHECK on /livez passes inside the container"

# buildah run does not forward signals, but with chroot isolation the server is an ordinary process
# of this machine: signal it directly, as a container runtime would.
descendants() { local p; for p in $(pgrep -P "$1"); do echo "$p"; descendants "$p"; done; }
inner=""
for p in $(descendants "$server_pid"); do
  [ "$(cat /proc/"$p"/comm 2>/dev/null)" = roomrender ] && inner="$p"
done
[ -n "$inner" ] || { echo "container-check: server process not found"; exit 1; }
kill -TERM "$inner"
wait "$server_pid" && rc=0 || rc=$?
grep -q '"event":"stopped"' "$log" || { cat "$log"; echo "container-check: no clean stop"; exit 1; }
echo "container-check: SIGTERM -> exit $rc"
server_pid=""
[ "$rc" -eq 0 ] || exit 1
echo "container-check: OK"
