#!/usr/bin/env bash
# Three replicas behind Debian's nginx with deploy/nginx/roomrender.conf, all on loopback:
#   1. consistent hashing on the scene id: once a client knows a scene's id (the X-Scene-Id of its
#      first answer) every render of it lands on one replica, so each scene is built at most twice
#      (by whichever replica took the first, keyless request, and once by its home replica);
#   2. the same traffic with nginx's default round robin (fresh replicas), for comparison;
#   3. one replica killed: the others keep answering every scene.
# First it reads the Dockerfile, compose file and k8s manifest (tests/deploy/check_manifests.py): the
# image's user owns its data directory, and both deployments run stateless replicas on PostgreSQL.
# These replicas keep the default in-memory store: only inline renders go through them here
# (tests/deploy/test_shared_store.sh covers stored scenes).
# Prints the cache-hit rates and writes them to build/test-output/deploy/replicas.json.
# Usage: tests/deploy/test_replicas.sh BUILD_DIR   (needs nginx, curl, python3, python3-yaml:
#        scripts/install-deps.sh)
set -euo pipefail
source_dir="$(cd "$(dirname "$0")/../.." && pwd)"
build_dir="$(cd "${1:?usage: $0 BUILD_DIR}" && pwd)"
binary="$build_dir/roomrender"
out_dir="$build_dir/test-output/deploy"
mkdir -p "$out_dir"
work="$(mktemp -d)"
scenes=(studio apartment rows four_cylinders cube_pyramid_cylinder cubes_45_pyramid_cylinder tetrahedron tri_intersecting)
renders_per_scene=8
pids=()
nginx_pid=""

cleanup() {
  [ -n "$nginx_pid" ] && kill "$nginx_pid" 2>/dev/null
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT
fail() { echo "test_replicas: FAIL: $*" >&2; [ -f "$work/error.log" ] && tail -5 "$work/error.log" >&2; exit 1; }
# shellcheck source=tests/deploy/cluster.sh
source "$source_dir/tests/deploy/cluster.sh"  # free_port, start_nginx, stop_nginx
command -v nginx >/dev/null || fail "nginx is not installed (scripts/install-deps.sh installs it)"
# The Dockerfile, compose file and k8s manifest, read rather than run (no container engine here).
python3 "$source_dir/tests/deploy/check_manifests.py" "$source_dir" || fail "deploy manifests (above)"

replica_ports=()
start_replicas() {
  pids=()
  replica_ports=()
  for i in 1 2 3; do
    local log="$work/replica-$i.log"
    "$binary" serve --port 0 --bind 127.0.0.1 >"$log" 2>&1 &
    pids+=($!)
    local port=""
    for _ in $(seq 1 100); do
      port=$(grep -o '"port":[0-9]*' "$log" 2>/dev/null | head -1 | cut -d: -f2 || true)
      [ -n "$port" ] && break
      sleep 0.05
    done
    [ -n "$port" ] || fail "replica $i did not start: $(cat "$log")"
    replica_ports+=("$port")
  done
}

stop_replicas() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  for p in "${pids[@]}"; do wait "$p" 2>/dev/null || true; done
  pids=()
}

# Renders every scene $renders_per_scene times through nginx with the bsp pipeline; after the first
# answer of a scene, sends its X-Scene-Id as clients do. Prints "scene upstream cache" lines.
render_all() {
  local scene id headers
  for scene in "${scenes[@]}"; do
    id=""
    python3 -c 'import json, sys; r = json.load(open(sys.argv[1]))
r.setdefault("options", {}).update(pipeline="bsp", width=64, height=48)
json.dump(r, open(sys.argv[2], "w"))' "$source_dir/examples/$scene.json" "$work/request.json"
    for _ in $(seq 1 "$renders_per_scene"); do
      headers="$work/headers"
      curl -sf -o /dev/null -D "$headers" -H 'Content-Type: application/json' ${id:+-H "X-Scene-Id: $id"} \
        --data-binary @"$work/request.json" "http://127.0.0.1:$nginx_port/v1/render" || fail "render of $scene failed"
      id=$(grep -i '^x-scene-id:' "$headers" | tr -d '\r' | awk '{print $2}')
      echo "$scene $(grep -i '^x-upstream:' "$headers" | tr -d '\r' | awk '{print $NF}') $(grep -i '^x-cache:' "$headers" | tr -d '\r' | awk '{print $2}')"
    done
  done
}

hit_rate() { awk '{n++; if ($3 == "hit") h++} END {printf "%.3f", h / n}' "$1"; }

# 1. Consistent hashing.
start_replicas
start_nginx "${replica_ports[@]}"
render_all >"$work/hashed.txt"
grep -qv ' hit$\| miss$' "$work/hashed.txt" && fail "an answer had no X-Cache: $(grep -v ' hit$\| miss$' "$work/hashed.txt" | head -1)"
for scene in "${scenes[@]}"; do
  # Every render after the first carries the scene id: they must share one replica.
  n=$(awk -v s="$scene" '$1 == s {k++; if (k > 1) print $2}' "$work/hashed.txt" | sort -u | wc -l)
  [ "$n" -eq 1 ] || fail "scene $scene reached $n replicas once its id was known"
  misses=$(awk -v s="$scene" '$1 == s && $3 == "miss"' "$work/hashed.txt" | wc -l)
  [ "$misses" -le 2 ] || fail "scene $scene missed $misses times with consistent hashing"
done
replicas_used=$(awk '{print $2}' "$work/hashed.txt" | sort -u | wc -l)
hashed=$(hit_rate "$work/hashed.txt")
builds_metric=0
for p in "${replica_ports[@]}"; do
  m=$(curl -sf "http://127.0.0.1:$p/metrics" | awk '/^roomrender_cache_misses_total\{cache="bsp"\}/ {s += $2} END {print s + 0}')
  builds_metric=$((builds_metric + m))
done
hashed_misses=$(awk '$3 == "miss"' "$work/hashed.txt" | wc -l)
[ "$builds_metric" -eq "$hashed_misses" ] || fail "replicas' /metrics count $builds_metric BSP misses, the answers $hashed_misses"
stop_nginx

# 2. Round robin, fresh replicas (cold caches).
stop_replicas
start_replicas
start_nginx_balanced '' "${replica_ports[@]}"
render_all >"$work/round_robin.txt"
round_robin=$(hit_rate "$work/round_robin.txt")
awk '{print $3}' "$work/round_robin.txt" | grep -q . || fail "no answers with round robin"

# 3. Kill a replica: with hashing, every scene still renders.
stop_nginx
start_nginx "${replica_ports[@]}"
kill -KILL "${pids[0]}"
wait "${pids[0]}" 2>/dev/null || true
render_all >"$work/after_kill.txt" || fail "renders failed after a replica died"
[ "$(wc -l <"$work/after_kill.txt")" -eq $(( ${#scenes[@]} * renders_per_scene )) ] || fail "missing answers after a replica died"
grep -q ":${replica_ports[0]} " "$work/after_kill.txt" && fail "the killed replica still answered"

printf '{"scenes": %d, "renders_per_scene": %d, "replicas_used": %d, "hit_rate_consistent_hash": %s, "hit_rate_round_robin": %s, "bsp_builds_consistent_hash": %d, "renders_after_one_replica_killed": %d}\n' \
  "${#scenes[@]}" "$renders_per_scene" "$replicas_used" "$hashed" "$round_robin" "$builds_metric" \
  "$(wc -l <"$work/after_kill.txt")" | tee "$out_dir/replicas.json"
echo "test_replicas: OK (hit rate $hashed with consistent hashing, $round_robin with round robin)"
