#!/usr/bin/env bash
# HTTP load benchmark of `roomrender serve` on loopback with wrk (Debian package), written to
# bench/results/load.json (figures in docs/benchmarks.md, section "HTTP service"):
#   1. a stored 640x480 apartment render (scene parsed and tessellated once, BSP tree cached when
#      the pipeline has one): GET /v1/scenes/{id}/render.png, throughput and p50/p99;
#   2. the same URL with If-None-Match (304, what a caching client or proxy sends);
#   3. the inline request POST /v1/render (lua script), for comparison;
#   4. a soak of SOAK_S seconds (default 120) mixing renders from random cameras with stores of new
#      scenes (64 distinct ones, stored again and again: a store keeps what it stored, 507 when full), sampling the server's VmRSS and
#      VmHWM from /proc every second: memory must stay flat once the caches are full.
# Not part of the test run. Usage: bench/load.sh [DURATION_S=30] ; env PIPELINE, SOAK_S, CONNECTIONS.
set -euo pipefail
cd "$(dirname "$0")/.."
duration="${1:-30}"
soak="${SOAK_S:-120}"
connections="${CONNECTIONS:-8}"
pipeline="${PIPELINE:-zbuffer}"

command -v wrk >/dev/null || { sudo=""; [ "$(id -u)" -eq 0 ] || sudo="sudo"; $sudo apt-get install -y -qq wrk; }
scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j2 --target roomrender >/dev/null
mkdir -p bench/results
work="$(mktemp -d)"
trap 'kill "$server_pid" 2>/dev/null || true; rm -rf "$work"' EXIT

# A full scene store answers 507 instead of evicting, so the soak stores 64 distinct scenes again and
# again (each store still parses, validates and hashes its body).
build/roomrender serve --port 0 --log-requests 0 \
  >"$work/server.out" 2>"$work/server.err" &
server_pid=$!
for _ in $(seq 100); do [ -s "$work/server.out" ] && break; sleep 0.1; done
port="$(python3 -c 'import json,sys; print(json.loads(open(sys.argv[1]).readline())["port"])' "$work/server.out")"
origin="http://127.0.0.1:$port"

python3 -c 'import json,sys; print(json.dumps(json.load(open(sys.argv[1]))["scene"]))' examples/apartment.json >"$work/scene.json"
id="$(curl -sf -H 'Content-Type: application/json' --data-binary @"$work/scene.json" "$origin/v1/scenes" |
      python3 -c 'import json,sys; print(json.load(sys.stdin)["id"])')"
url="$origin/v1/scenes/$id/render.png?position=8,6,12&target=5,0,3.5&width=640&height=480&pipeline=$pipeline"
curl -sf -o "$work/warm.png" -D "$work/warm.headers" "$url"
etag="$(grep -i '^etag:' "$work/warm.headers" | cut -d' ' -f2 | tr -d '\r')"

# wrk output -> {requests_per_s, p50_ms, p99_ms, requests, non_2xx_3xx}
parse_wrk() {
  python3 - "$1" <<'PY'
import json, re, sys
text = open(sys.argv[1]).read()
def ms(label):
    m = re.search(r"^\s*" + label + r"\s+([\d.]+)(us|ms|s)\s*$", text, re.M)
    if not m: return None
    return round(float(m.group(1)) * {"us": 1e-3, "ms": 1.0, "s": 1e3}[m.group(2)], 3)
rps = float(re.search(r"Requests/sec:\s+([\d.]+)", text).group(1))
total = int(re.search(r"(\d+) requests in", text).group(1))
bad = re.search(r"Non-2xx or 3xx responses: (\d+)", text)
print(json.dumps({"requests_per_s": rps, "p50_ms": ms("50%"), "p90_ms": ms("90%"), "p99_ms": ms("99%"),
                  "requests": total, "non_2xx_3xx": int(bad.group(1)) if bad else 0}))
PY
}

cat >"$work/post.lua" <<EOF
wrk.method = "POST"
wrk.headers["Content-Type"] = "application/json"
local f = io.open("$PWD/examples/apartment.json", "rb")
wrk.body = f:read("*a")
f:close()
EOF

echo "load: stored render ($pipeline, 640x480), ${duration}s, $connections connections"
wrk -t2 -c"$connections" -d"${duration}s" --latency "$url" >"$work/render.txt"
echo "load: conditional GET (304)"
wrk -t2 -c"$connections" -d"${duration}s" --latency -H "If-None-Match: $etag" "$url" >"$work/304.txt"
echo "load: inline POST /v1/render"
wrk -t2 -c"$connections" -d"${duration}s" --latency -s "$work/post.lua" "$origin/v1/render" >"$work/post.txt"

# Soak: 80% renders of the stored scene from random cameras, 20% stores of new scenes (a box at a
# of 64 places).
python3 - "$work/scene.json" >"$work/soak.lua" <<'PY'
import json, sys
scene = json.dumps(json.load(open(sys.argv[1])))
print('''
local scene = [==[%s]==]
local id = "%s"
math.randomseed(os.time())
request = function()
  if math.random() < 0.2 then
    local x = string.format("%%.4f", math.random(0, 63) / 8 + 1)
    local body = scene:gsub('"solids": %%[', '"solids": [{"type": "box", "center": [' .. x .. ', 3], "size": [0.3, 0.3, 0.3]}, ', 1)
    return wrk.format("POST", "/v1/scenes", {["Content-Type"] = "application/json"}, body)
  end
  local p = string.format("%%.3f,%%.3f,%%.3f", 3 + math.random() * 8, 2 + math.random() * 6, 8 + math.random() * 6)
  return wrk.format("GET", "/v1/scenes/" .. id .. "/render.png?width=640&height=480&target=5,0,3.5&position=" .. p)
end
''' % (scene, "ID"))
PY
sed -i "s/\"ID\"/\"$id\"/" "$work/soak.lua"
echo "load: soak ${soak}s with RSS sampling"
: >"$work/rss.tsv"
(
  start=$(date +%s.%N)
  while kill -0 "$server_pid" 2>/dev/null; do
    now=$(date +%s.%N)
    rss=$(awk '/^VmRSS:/ {print $2}' "/proc/$server_pid/status" 2>/dev/null || echo 0)
    hwm=$(awk '/^VmHWM:/ {print $2}' "/proc/$server_pid/status" 2>/dev/null || echo 0)
    echo "$(awk -v a="$now" -v b="$start" 'BEGIN { printf "%.1f", a - b }') $rss $hwm" >>"$work/rss.tsv"
    sleep 1
  done
) &
sampler=$!
wrk -t2 -c"$connections" -d"${soak}s" --latency -s "$work/soak.lua" "$origin" >"$work/soak.txt"
kill "$sampler" 2>/dev/null || true
metrics="$(curl -sf "$origin/metrics")"

render_json="$(parse_wrk "$work/render.txt")"
cond_json="$(parse_wrk "$work/304.txt")"
post_json="$(parse_wrk "$work/post.txt")"
soak_json="$(parse_wrk "$work/soak.txt")"
python3 - "$work/rss.tsv" "$render_json" "$cond_json" "$post_json" "$soak_json" "$metrics" \
  "$pipeline" "$duration" "$soak" "$connections" <<'PY' >bench/results/load.json
import json, os, platform, re, sys
rss_file, render, cond, post, soak, metrics, pipeline, duration, soak_s, connections = sys.argv[1:]
samples = [tuple(float(x) for x in line.split()) for line in open(rss_file) if len(line.split()) == 3]
samples = [s for s in samples if s[1] > 0]
def rss_at(t):  # MiB at the sample nearest to t seconds
    return round(min(samples, key=lambda s: abs(s[0] - t))[1] / 1024, 1)
def metric(name, labels=""):
    total = 0.0
    for line in metrics.splitlines():
        if line.startswith(name + ("{" if labels else " ")) and labels in line:
            total += float(line.rsplit(" ", 1)[1])
    return total
end = samples[-1][0]
result = {
    "conditions": {
        "machine": f"{os.cpu_count()} cores, {platform.machine()}, shared with other engineers' builds",
        "load_average_at_end": os.getloadavg(),
        "server": "roomrender serve defaults (render workers = cores, queue 4 per worker), default scene store; the soak stores 64 distinct scenes again and again",
        "client": f"wrk -t2 -c{connections} on the same machine (loopback)",
        "scene": "examples/apartment.json stored once; 640x480; pipeline " + pipeline,
        "duration_s": int(duration),
    },
    "stored_render_png": json.loads(render),
    "conditional_get_304": json.loads(cond),
    "inline_post_render": json.loads(post),
    "soak": {
        "duration_s": int(soak_s),
        "mix": "80% GET render.png from random cameras, 20% POST /v1/scenes of new scenes",
        "wrk": json.loads(soak),
        "peak_rss_mib": round(max(s[2] for s in samples) / 1024, 1),
        "rss_mib": {"t10": rss_at(10), "t30": rss_at(30), "t60": rss_at(60), "t90": rss_at(90), "end": rss_at(end)},
        "scene_cache_evictions": metric("roomrender_cache_evictions_total", 'cache="scenes"'),
        "scene_cache_bytes": metric("roomrender_cache_bytes", 'cache="scenes"'),
        "scene_store_bytes": metric("roomrender_store_bytes", 'store="scenes"'),
        "scene_store_budget_bytes": metric("roomrender_store_budget_bytes", 'store="scenes"'),
        "rejected_renders": metric("roomrender_renders_rejected_total"),
    },
}
print(json.dumps(result, indent=2))
PY
cat bench/results/load.json
