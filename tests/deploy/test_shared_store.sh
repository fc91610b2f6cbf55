#!/usr/bin/env bash
# Stateless replicas on one PostgreSQL store, behind Debian's nginx with deploy/nginx/roomrender.conf
# (all on loopback; PostgreSQL from Debian's package in a temporary directory, as `nobody` when run
# as root). 100 scenes (10 placing stored meshes) and 10 meshes stored with POST through nginx must
# read back through nginx byte-identical to what a lone embedded-store server answers for them:
#   1. right away (stores spread over the replicas);  2. after one replica is SIGKILLed;
#   3. with a replacement and a fourth replica;  4. after every replica and nginx restarted;
# then: 5. the same content stored at once by two owners on two replicas is one row with two owners;
#   6. with PostgreSQL frozen (SIGSTOP) and 7. stopped, stores answer 503 + Retry-After within 15 s
#      while inline renders answer 200, and once it is back new stores succeed and every item still
#      reads back.
# Writes build/test-output/deploy/shared_store.json. Exit 77 (skipped) without PostgreSQL's server
# binaries. Usage: tests/deploy/test_shared_store.sh BUILD_DIR   (scripts/install-deps.sh)
set -euo pipefail
source_dir="$(cd "$(dirname "$0")/../.." && pwd)"
build_dir="$(cd "${1:?usage: $0 BUILD_DIR}" && pwd)"
binary="$build_dir/roomrender"
out_dir="$build_dir/test-output/deploy"
mkdir -p "$out_dir"
work="$(mktemp -d)"
check="$source_dir/tests/deploy/store_check.py"
fail() {
  echo "test_shared_store: FAIL: $*" >&2
  for f in "$work"/replica-*.log "$work/error.log" "$work/pg/server.log"; do
    [ -s "$f" ] && { echo "--- $f" >&2; tail -5 "$f" >&2; }
  done
  exit 1
}
source "$source_dir/tests/deploy/cluster.sh"
trap 'cluster_cleanup; rm -rf "$work"' EXIT

if [ -z "$pg_bin" ] || [ ! -x "$pg_bin/initdb" ]; then
  echo "SKIP: test_shared_store: PostgreSQL's server binaries (/usr/lib/postgresql/*/bin/initdb) are missing; scripts/install-deps.sh installs them"
  exit 77
fi
command -v nginx >/dev/null || fail "nginx is not installed (scripts/install-deps.sh installs it)"
help="$("$binary" serve --help 2>&1 || true)"
grep -q -- '--store ' <<<"$help" || fail "$binary has no --store option"

# Two owners: each scene's owners are the names of the tokens that stored it.
export ROOMRENDER_TEST_TOKENS="alice:alice-token-0123456789abcdef,bob:bob-token-0123456789abcdef"
tr ',' '\n' <<<"$ROOMRENDER_TEST_TOKENS" >"$work/tokens"
python3 -c 'import json, sys; r = json.load(open(sys.argv[1]))
r.setdefault("options", {}).update(width=64, height=48)
json.dump(r, open(sys.argv[2], "w"))' "$source_dir/examples/studio.json" "$work/render.json"

# The expected bytes: what the embedded store answers for the same documents.
start_replica --api-token-file "$work/tokens"
python3 "$check" reference "http://127.0.0.1:${replica_ports[0]}" "$work/manifest.json" 100 10 || fail "reference store"
stop_replicas

pg_init
replica_args=(--store "$store_url" --api-token-file "$work/tokens")
for _ in 1 2 3; do start_replica "${replica_args[@]}"; done
start_nginx "${replica_ports[@]}"
front="http://127.0.0.1:$nginx_port"

echo "test_shared_store: 1. stored through nginx, read back through nginx"
python3 "$check" store "$front" "$work/manifest.json" || fail "storing through nginx"
python3 "$check" check "$front" "$work/manifest.json" || fail "reading back right after storing"

echo "test_shared_store: 2. one replica killed"
kill_replica 0
python3 "$check" check "$front" "$work/manifest.json" || fail "reading back with a replica killed"

echo "test_shared_store: 3. a replacement and a fourth replica"
start_replica "${replica_args[@]}"
start_replica "${replica_args[@]}"
stop_nginx
start_nginx $(live_ports)
[ "$(live_ports | wc -l)" -eq 4 ] || fail "expected 4 live replicas"
python3 "$check" check "$front" "$work/manifest.json" || fail "reading back with four replicas"

echo "test_shared_store: 4. every replica and nginx restarted"
stop_nginx
stop_replicas
for _ in 1 2 3; do start_replica "${replica_args[@]}"; done
start_nginx "${replica_ports[@]}"
python3 "$check" check "$front" "$work/manifest.json" || fail "reading back after restarting everything"

echo "test_shared_store: 5. the same content stored at once from two replicas by two owners"
a="http://127.0.0.1:${replica_ports[0]}" b="http://127.0.0.1:${replica_ports[1]}"
python3 "$check" race "$a" "$b" 10 >"$work/race.ids" || fail "concurrent stores"
for id in $(cat "$work/race.ids"); do
  rows=$(psql_value "SELECT count(*) FROM rr_scenes WHERE id = '$id'")
  owners=$(psql_value "SELECT string_agg(owner, ',' ORDER BY owner) FROM rr_scene_owners WHERE id = '$id'")
  [ "$rows" = 1 ] && [ "$owners" = "alice,bob" ] || fail "scene $id: $rows rows, owners '$owners' in the database"
done
python3 "$check" release "$a" "$b" "$work/race.ids" || fail "releasing the concurrently stored scenes"

echo "test_shared_store: 6. PostgreSQL frozen (SIGSTOP: connections hang, as with a stuck host)"
pg_pids="$(head -1 "$work/pg/data/postmaster.pid") $(ps -o pid= --ppid "$(head -1 "$work/pg/data/postmaster.pid")")"
kill -STOP $pg_pids
python3 "$check" outage "$front" "$work/manifest.json" "$work/render.json" || { kill -CONT $pg_pids; fail "with the database frozen"; }
kill -CONT $pg_pids
python3 "$check" recovered "$front" "$work/manifest.json" || fail "after the database thawed"

echo "test_shared_store: 7. PostgreSQL stopped, then back"
pg_stop
python3 "$check" outage "$front" "$work/manifest.json" "$work/render.json" || fail "with the database down"
pg_start
python3 "$check" recovered "$front" "$work/manifest.json" || fail "after the database returned"

rows=$(psql_value "SELECT count(*) FROM rr_scenes")
printf '{"scenes": 100, "meshes": 10, "replicas": [3, 2, 4, 3], "race_pairs": 10, "scene_rows_at_end": %s}\n' \
  "$rows" | tee "$out_dir/shared_store.json"
echo "test_shared_store: OK"
