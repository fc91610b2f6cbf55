#!/usr/bin/env bash
# Served against in-process render rate: wrk on POST /v1/render with examples/apartment.json (the
# request as it is, zbuffer at the example's size) against bench_render_rate running the same path
# in-process (parse, prepare, render, encode) with the server's render slots and tile threads, in
# interleaved rounds. Goal: served >= 0.85x in-process. Writes bench/results/service_rate.json.
# Not part of the test run. Usage: bench/service_rate.sh [SECONDS=15] [ROUNDS=2]; env CONNECTIONS (4).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-15}"
rounds="${2:-2}"
connections="${CONNECTIONS:-4}"
request="$PWD/examples/apartment.json"
command -v wrk >/dev/null || { sudo=""; [ "$(id -u)" -eq 0 ] || sudo="sudo"; $sudo apt-get install -y -qq wrk; }
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j2 --target roomrender bench_render_rate >/dev/null
workers=$(nproc)  # the server's defaults: one render slot and one tile thread per core
work="$(mktemp -d)"
trap 'kill "$server_pid" 2>/dev/null || true; rm -rf "$work"' EXIT

build/roomrender serve --port 0 --log-requests 0 >"$work/server.out" 2>"$work/server.err" &
server_pid=$!
for _ in $(seq 100); do [ -s "$work/server.out" ] && break; sleep 0.1; done
port="$(python3 -c 'import json,sys; print(json.loads(open(sys.argv[1]).readline())["port"])' "$work/server.out")"
cat >"$work/post.lua" <<LUA
wrk.method = "POST"
wrk.headers["Content-Type"] = "application/json"
local f = io.open("$request", "rb")
wrk.body = f:read("*a")
f:close()
LUA
curl -sf -o /dev/null -H 'Content-Type: application/json' --data-binary @"$request" "http://127.0.0.1:$port/v1/render"

for r in $(seq "$rounds"); do
  echo "service_rate: round $r: in-process, $workers workers x $workers threads, ${seconds}s" >&2
  build/bench/bench_render_rate --request "$request" --workers "$workers" --threads "$workers" \
    --seconds "$seconds" >"$work/inproc.$r.json"
  echo "service_rate: round $r: wrk POST /v1/render, $connections connections, ${seconds}s" >&2
  wrk -t2 -c"$connections" -d"${seconds}s" --latency -s "$work/post.lua" "http://127.0.0.1:$port/v1/render" \
    >"$work/wrk.$r.txt"
done

mkdir -p bench/results
python3 - "$work" "$rounds" "$connections" "$(uptime)" <<'PY'
import json, re, statistics, sys
work, rounds, connections, uptime = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
out = {"request": "examples/apartment.json", "connections": connections, "uptime_at_end": uptime.strip(), "rounds": []}
for r in range(1, rounds + 1):
    inproc = json.load(open("%s/inproc.%d.json" % (work, r)))
    text = open("%s/wrk.%d.txt" % (work, r)).read()
    served = float(re.search(r"Requests/sec:\s+([\d.]+)", text).group(1))
    bad = re.search(r"Non-2xx or 3xx responses: (\d+)", text)
    out["rounds"].append({"in_process_per_s": round(inproc["renders_per_s"], 2), "served_per_s": served,
                          "non_2xx": int(bad.group(1)) if bad else 0,
                          "ratio": round(served / inproc["renders_per_s"], 3)})
out["ratio_median"] = statistics.median(r["ratio"] for r in out["rounds"])
out["goal"] = ">= 0.85"
json.dump(out, open("bench/results/service_rate.json", "w"), indent=1)
print(json.dumps(out))
PY
