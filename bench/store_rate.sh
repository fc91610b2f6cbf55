#!/usr/bin/env bash
# Store and scale-out rates on this machine, in interleaved rounds:
#   stores: one server with the embedded store (--data-dir on local disk, fsync per scene) against
#           one with PostgreSQL (each empty at the start of its round) (Debian's package in a temporary directory, fsync on, default
#           settings): bench/store_rate.py stores SCENES distinct scenes and reads each back 4 times
#           from CONNECTIONS connections, giving throughput and p50/p99 latency of each;
#   renders: wrk POST /v1/render (examples/apartment.json) through Debian's nginx with
#           deploy/nginx/roomrender.conf in front of 1, 2 and 3 replicas (inline renders: no store).
# Writes bench/results/store.json (every round, medians, uptime). Not part of the test run.
# Usage: bench/store_rate.sh [ROUNDS=3]; env SCENES (1000), CONNECTIONS (4), RENDER_SECONDS (10),
#        STORES ("embedded postgresql")
set -euo pipefail
source_dir="$(cd "$(dirname "$0")/.." && pwd)"
cd "$source_dir"
rounds="${1:-3}"
scenes="${SCENES:-1000}"
connections="${CONNECTIONS:-4}"
stores="${STORES:-embedded postgresql}"
seconds="${RENDER_SECONDS:-10}"  # not SECONDS: bash counts that one itself
binary="$source_dir/build/roomrender"
work="$(mktemp -d)"
fail() { echo "store_rate: $*" >&2; exit 1; }
source "$source_dir/tests/deploy/cluster.sh"
trap 'cluster_cleanup; rm -rf "$work"' EXIT
command -v wrk >/dev/null || fail "wrk is missing (bench/install-bench-deps.sh)"
[ -n "$pg_bin" ] || [ "$stores" = embedded ] || fail "PostgreSQL's server binaries are missing (scripts/install-deps.sh)"
[ -x "$binary" ] || fail "build roomrender first (nice ninja -j2 -C build roomrender)"

cat >"$work/post.lua" <<LUA
wrk.method = "POST"
wrk.headers["Content-Type"] = "application/json"
local f = io.open("$source_dir/examples/apartment.json", "rb")
wrk.body = f:read("*a")
f:close()
LUA

case " $stores " in *" postgresql "*) pg_init ;; esac
for r in $(seq "$rounds"); do
  for store in $stores; do
    echo "store_rate: round $r: $store store, $scenes scenes" >&2
    rm -rf "$work/data"
    case "$store" in
      embedded) start_replica --data-dir "$work/data" ;;
      postgresql) pg_reset_db; start_replica --store "$store_url" ;;
      *) fail "unknown store $store" ;;
    esac
    python3 bench/store_rate.py "http://127.0.0.1:${replica_ports[0]}" --scenes "$scenes" \
      --concurrency "$connections" --seed "$r$RANDOM" >"$work/$store.$r.json"
    grep -q '"errors": 0}' "$work/$store.$r.json" || fail "$store: failed requests: $(cat "$work/$store.$r.json")"
    stop_replicas
  done
  for n in 1 2 3; do
    echo "store_rate: round $r: renders through nginx, $n replicas, ${seconds}s" >&2
    for _ in $(seq "$n"); do start_replica; done
    start_nginx "${replica_ports[@]}"
    curl -sf -o /dev/null -H 'Content-Type: application/json' --data-binary @examples/apartment.json \
      "http://127.0.0.1:$nginx_port/v1/render" || fail "warm-up render failed"
    wrk -t2 -c"$connections" -d"${seconds}s" --latency -s "$work/post.lua" \
      "http://127.0.0.1:$nginx_port/v1/render" >"$work/wrk.$n.$r.txt"
    stop_nginx
    stop_replicas
  done
done

mkdir -p bench/results
python3 - "$work" "$rounds" "$scenes" "$connections" "$seconds" "$(uptime)" "$stores" <<'PY'
import json, re, statistics, sys
work, rounds, scenes, connections, seconds, uptime, stores = sys.argv[1:8]
rounds = int(rounds)
out = {"scenes_per_round": int(scenes), "connections": int(connections), "render_seconds": int(seconds),
       "render_request": "examples/apartment.json", "uptime_at_end": uptime.strip(), "stores": {}, "renders": {}}
keys = ["write_per_s", "write_p50_ms", "write_p99_ms", "read_per_s", "read_p50_ms", "read_p99_ms"]
for store in stores.split():
    runs = [json.load(open(f"{work}/{store}.{r}.json")) for r in range(1, rounds + 1)]
    out["stores"][store] = {"rounds": runs, "median": {k: statistics.median(x[k] for x in runs) for k in keys}}
def wrk_ms(text, label):
    m = re.search(label + r"\s+([\d.]+)(us|ms|s)\b", text)
    return round(float(m.group(1)) * {"us": 0.001, "ms": 1, "s": 1000}[m.group(2)], 2)
for n in (1, 2, 3):
    runs = []
    for r in range(1, rounds + 1):
        text = open(f"{work}/wrk.{n}.{r}.txt").read()
        bad = re.search(r"Non-2xx or 3xx responses: (\d+)", text)
        runs.append({"per_s": float(re.search(r"Requests/sec:\s+([\d.]+)", text).group(1)),
                     "p50_ms": wrk_ms(text, "50%"), "p99_ms": wrk_ms(text, "99%"),
                     "non_2xx": int(bad.group(1)) if bad else 0})
    out["renders"][f"{n}_replicas"] = {"rounds": runs, "median": {k: statistics.median(x[k] for x in runs)
                                                                  for k in ("per_s", "p50_ms", "p99_ms")}}
json.dump(out, open("bench/results/store.json", "w"), indent=1)
print(json.dumps({"stores": {s: v["median"] for s, v in out["stores"].items()},
                  "renders": {n: v["median"] for n, v in out["renders"].items()}, "uptime": out["uptime_at_end"]}))
PY
