#!/usr/bin/env python3
"""A user's homes at scale: --homes distinct furnished homes stored in one server, and its resident
memory against the prepared cache's budget while it is busy.

The homes are the nine Sweet Home 3D homes of ../shared/data/floorplans/sweethome3d, each zipped with
its furniture/ folder as scripts/render-home.sh sends it, in name order and then again moved 50 m
further east per round (every plan coordinate of the XML shifted), so each is a scene of its own. For
each --cache-bytes (default: the server's default and 1 GiB) a server starts with a fresh data
directory and otherwise default budgets; the homes are imported with POST /v1/import/sh3d?store=1
from 2 connections; then --busy-seconds of renders from 4 connections, each of a random stored home
(seeded) from its own camera at 640x480, one in four with the bsp pipeline (a BSP tree per home joins
the cache). The server's resident memory (VmRSS of /proc/PID/status) is sampled every 0.2 s
throughout; /metrics gives the cache's and the stores' fill. Writes bench/results/store_homes.json.
Standard library only; loopback only; bounded by the counts above.

usage: bench/store_homes.py [--binary build/roomrender] [--homes 100] [--cache-bytes N ...]
                            [--busy-seconds 60]
"""
import argparse
import http.client
import io
import json
import os
import random
import re
import shutil
import statistics
import sys
import tempfile
import threading
import time
import zipfile

from bench_server import start_server

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
HOMES = os.path.join(ROOT, "..", "shared", "data", "floorplans", "sweethome3d")
TAG = re.compile(r"<([A-Za-z]+)\b[^>]*>")
COORDINATE = re.compile(r"""(\s)(x|y|xStart|yStart|xEnd|yEnd)=(['"])([^'"]*)\3""")


def moved(xml, dx_cm):
    """The home with every plan coordinate moved dx_cm east; a light source's and a sash's coordinates
    are relative to their piece and stay (as tests/support/sweet_homes.cpp moves them)."""
    def move_tag(tag):
        if tag.group(1) in ("lightSource", "sash"):
            return tag.group(0)
        def move(a):
            value = float(a.group(4)) + (dx_cm if a.group(2).startswith("x") else 0.0)
            return f"{a.group(1)}{a.group(2)}={a.group(3)}{value!r}{a.group(3)}"
        return COORDINATE.sub(move, tag.group(0))
    return TAG.sub(move_tag, xml)


def home_zip(path, xml):
    out = io.BytesIO()
    furniture = os.path.join(os.path.dirname(path), "furniture")
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr(os.path.basename(path), xml)
        for name in sorted(os.listdir(furniture)):
            z.write(os.path.join(furniture, name), "furniture/" + name)
    return out.getvalue()


def distinct_home(files, i):
    path = files[i % len(files)]
    with open(path, encoding="utf-8") as f:
        xml = f.read()
    rounds = i // len(files)
    return home_zip(path, moved(xml, 5000.0 * rounds) if rounds else xml)


def resident_bytes(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) * 1024
    return 0


def metrics(port):
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
    conn.request("GET", "/metrics")
    text = conn.getresponse().read().decode()
    conn.close()
    out = {}
    for line in text.splitlines():
        if line and not line.startswith("#"):
            name, value = line.rsplit(" ", 1)
            out[name] = float(value)
    return out


class Sampler(threading.Thread):
    """The server's VmRSS every 0.2 s: the peak of the current phase and of all phases."""
    def __init__(self, pid):
        super().__init__(daemon=True)
        self.pid, self.peak, self.phase_peak, self.stopped = pid, 0, 0, False

    def run(self):
        while not self.stopped:
            rss = resident_bytes(self.pid)
            self.peak, self.phase_peak = max(self.peak, rss), max(self.phase_peak, rss)
            time.sleep(0.2)

    def next_phase(self):
        peak, self.phase_peak = self.phase_peak, 0
        return peak


def post(port, path, body, content_type):
    """One request on a connection of its own: the server may close an idle keep-alive connection
    while the client prepares its next home, and a request is seconds of work next to a connect."""
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=600)
    try:
        conn.request("POST", path, body=body, headers={"Content-Type": content_type})
        answer = conn.getresponse()
        return answer.status, answer.read()
    finally:
        conn.close()


def store_all(port, files, count):
    homes, statuses, lock = [None] * count, {}, threading.Lock()

    def worker(first):
        for i in range(first, count, 2):
            status, body = post(port, "/v1/import/sh3d?store=1&width=640&height=480", distinct_home(files, i),
                                "application/zip")
            with lock:
                statuses[status] = statuses.get(status, 0) + 1
            if status == 201:
                receipt = json.loads(body)
                homes[i] = (receipt["location"], receipt["camera"])

    threads = [threading.Thread(target=worker, args=(c,)) for c in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    return [h for h in homes if h], statuses


def busy(port, homes, seconds, seed):
    latencies, statuses, lock = [], {}, threading.Lock()
    stop_at = time.monotonic() + seconds

    def worker(k):
        rng = random.Random(seed * 16 + k)
        while time.monotonic() < stop_at:
            location, camera = rng.choice(homes)
            options = {"width": 640, "height": 480}
            if rng.random() < 0.25:
                options["pipeline"] = "bsp"
            started = time.perf_counter()
            status, _ = post(port, location + "/render", json.dumps({"camera": camera, "options": options}),
                             "application/json")
            with lock:
                latencies.append(time.perf_counter() - started)
                statuses[status] = statuses.get(status, 0) + 1

    threads = [threading.Thread(target=worker, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    latencies.sort()
    return {"renders": len(latencies), "statuses": statuses,
            "p50_ms": round(1000 * latencies[len(latencies) // 2], 1) if latencies else None,
            "p99_ms": round(1000 * latencies[int(len(latencies) * 0.99)], 1) if latencies else None}


def run(binary, files, count, cache_bytes, busy_seconds, seed):
    data_dir = tempfile.mkdtemp(prefix="roomrender-homes-")
    flags = ["--data-dir", data_dir, "--render-timeout-ms", "120000"]
    if cache_bytes:
        flags += ["--cache-bytes", str(cache_bytes)]
    server, port = start_server(binary, flags)
    sampler = Sampler(server.pid)
    sampler.start()
    try:
        idle = resident_bytes(server.pid)
        started = time.monotonic()
        homes, statuses = store_all(port, files, count)
        store_seconds = time.monotonic() - started
        stored = metrics(port)
        store_peak = sampler.next_phase()
        load = busy(port, homes, busy_seconds, seed)
        busy_peak = sampler.next_phase()
        end = metrics(port)
        budget = end['roomrender_cache_budget_bytes{cache="all"}']
        mib = lambda b: round(b / 2**20, 1)
        return {
            "cache_budget_mib": mib(budget),
            "homes_posted": count,
            "import_statuses": statuses,
            "store_seconds": round(store_seconds, 1),
            "scene_documents_mib": mib(stored['roomrender_store_bytes{store="scenes"}']),
            "mesh_documents_mib": mib(stored['roomrender_store_bytes{store="meshes"}']),
            "scenes_stored": int(stored['roomrender_store_entries{store="scenes"}']),
            "meshes_stored": int(stored['roomrender_store_entries{store="meshes"}']),
            "data_dir_mib": mib(sum(os.path.getsize(os.path.join(d, f)) for d, _, fs in os.walk(data_dir) for f in fs)),
            "rss_idle_mib": mib(idle),
            "rss_peak_storing_mib": mib(store_peak),
            "cache_after_storing_mib": mib(stored['roomrender_cache_bytes{cache="all"}']),
            "busy": load,
            "rss_peak_busy_mib": mib(busy_peak),
            "rss_end_mib": mib(resident_bytes(server.pid)),
            "cache_end_mib": mib(end['roomrender_cache_bytes{cache="all"}']),
            "cache_end_by_part_mib": {p: mib(end[f'roomrender_cache_bytes{{cache="{p}"}}'])
                                      for p in ("scenes", "meshes", "bsp", "shadow")},
            "scene_rebuilds": int(end['roomrender_cache_builds_total{cache="scenes"}']),
            "cache_evictions": int(end['roomrender_cache_evictions_total{cache="all"}']),
            "rss_peak_over_budget_mib": mib(max(store_peak, busy_peak) - budget),
        }
    finally:
        sampler.stopped = True
        server.terminate()
        server.wait()
        shutil.rmtree(data_dir, ignore_errors=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--binary", default=os.path.join(ROOT, "build", "roomrender"))
    parser.add_argument("--homes", type=int, default=100)
    parser.add_argument("--cache-bytes", type=int, nargs="*", default=[0, 1 << 30],
                        help="prepared-cache budgets to run; 0: the server's default")
    parser.add_argument("--busy-seconds", type=float, default=60)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--out", default=os.path.join(ROOT, "bench", "results", "store_homes.json"))
    args = parser.parse_args()
    files = sorted(os.path.join(HOMES, f) for f in os.listdir(HOMES) if f.endswith(".xml")) \
        if os.path.isdir(HOMES) else []
    if not files:
        sys.exit(f"no homes in {HOMES}")
    load_before = os.getloadavg()
    runs = [run(args.binary, files, args.homes, b, args.busy_seconds, args.seed) for b in args.cache_bytes]
    result = {"homes": args.homes, "busy_seconds": args.busy_seconds, "cores": os.cpu_count(),
              "load_average_before": [round(x, 2) for x in load_before],
              "load_average_after": [round(x, 2) for x in os.getloadavg()],
              "when_utc": time.strftime("%Y-%m-%d %H:%M", time.gmtime()), "runs": runs}
    os.makedirs(os.path.dirname(args.out), exist_ok=True)
    with open(args.out, "w") as f:
        json.dump(result, f, indent=2)
        f.write("\n")
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
