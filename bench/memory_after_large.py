#!/usr/bin/env python3
"""Memory after large requests: the server's RSS at rest, after one large render and after a burst.

For each configuration (--configs, default: all of CONFIGS; an older binary without --trim-after-ms
runs only "defaults") starts `roomrender serve` on a free loopback port, renders
examples/studio.json at 320x240 a few times (the baseline), then POSTs a room of --boxes boxes
(zbuffer, 640x480), then --burst concurrent renders of the same room with different colours (so
nothing is cached), and reads process_resident_memory_bytes from /metrics after a 0.5 s pause each
time. Also times --small small renders (studio at 320x240) to show what the trim costs a request
that does not reach the threshold and one that does (--trim-after-ms 0 trims after every render).
Standard library only; loopback only; bounded by the counts above.

usage: bench/memory_after_large.py [--binary build/roomrender] [--boxes 135292] [--burst 4]
                                   [--small 40]
"""
import argparse
import http.client
import json
import os
import statistics
import subprocess
import sys
import threading
import time

from bench_server import resident_mib, start_server

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

CONFIGS = {
    "trim off": ({}, ["--trim-after-ms", "-1"]),
    "defaults (trim after 100 ms)": ({}, []),
    "MALLOC_ARENA_MAX=2 and trim off": ({"MALLOC_ARENA_MAX": "2"}, ["--trim-after-ms", "-1"]),
    "trim after every render": ({}, ["--trim-after-ms", "0"]),
}


def start_large_server(binary, env_extra, flags):
    return start_server(binary, ["--max-body-bytes", str(64 << 20), "--render-timeout-ms", "120000", *flags],
                        env_extra)


def settled_resident_mib(port):
    time.sleep(0.5)  # let the answering thread finish its trim
    return resident_mib(port)


def post(port, body):
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=120)
    started = time.perf_counter()
    conn.request("POST", "/v1/render", body=body, headers={"Content-Type": "application/json"})
    response = conn.getresponse()
    response.read()
    conn.close()
    return response.status, (time.perf_counter() - started) * 1000.0


def boxes_request(count, shade):
    side = int(count ** 0.5) + 1
    solids = []
    for k in range(count):
        x, z = k % side, k // side
        solids.append({"type": "box", "id": f"b{k}", "color": f"#{shade:02x}8080",
                       "center": [0.5 + x * 0.4, 0.5 + z * 0.4], "size": [0.2, 0.2 + (k % 7) * 0.1, 0.2]})
    extent = side * 0.4
    return {"scene": {"background": "#202020", "solids": solids,
                      "lights": [{"type": "directional", "direction": [-0.3, -1, -0.5]}]},
            "camera": {"position": [-5, 20, -5], "target": [extent / 2, 0, extent / 2], "far": 4 * extent + 100},
            "options": {"width": 640, "height": 480, "pipeline": "zbuffer", "shading": "flat"}}


def measure(binary, name, env_extra, flags, large, burst, small_body, small_count):
    server, port = start_large_server(binary, env_extra, flags)
    try:
        for _ in range(3):
            post(port, small_body)
        base = settled_resident_mib(port)
        status, large_ms = post(port, large[0])
        after_large = settled_resident_mib(port)
        results = []
        threads = [threading.Thread(target=lambda b=b: results.append(post(port, b))) for b in large[1:1 + burst]]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        after_burst = settled_resident_mib(port)
        small_ms = [post(port, small_body)[1] for _ in range(small_count)]
        statuses = sorted({status, *(s for s, _ in results)})
        print(f"{name:32s} {base:8.0f} {after_large:12.0f} {after_burst:12.0f} {large_ms:9.0f} "
              f"{statistics.median(small_ms):9.1f}   {statuses}")
    finally:
        server.terminate()
        server.wait(timeout=30)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--binary", default=os.path.join(ROOT, "build", "roomrender"))
    parser.add_argument("--boxes", type=int, default=135292)
    parser.add_argument("--burst", type=int, default=4)
    parser.add_argument("--small", type=int, default=40)
    parser.add_argument("--configs", default=",".join(CONFIGS), help="comma-separated names of CONFIGS")
    args = parser.parse_args()

    large = [json.dumps(boxes_request(args.boxes, 0x40 + k)).encode() for k in range(1 + args.burst)]
    with open(os.path.join(ROOT, "examples", "studio.json"), "rb") as f:
        studio = json.load(f)
    studio.setdefault("options", {}).update({"width": 320, "height": 240})
    small_body = json.dumps(studio).encode()
    print(f"binary {args.binary}; large: {args.boxes} boxes ({len(large[0]) / 2**20:.1f} MiB body), "
          f"burst of {args.burst} at once; RSS in MiB")
    print(f"{'configuration':32s} {'baseline':>8s} {'after large':>12s} {'after burst':>12s} "
          f"{'large ms':>9s} {'small ms':>9s}   statuses")
    for name in args.configs.split(","):
        env_extra, flags = CONFIGS[name]
        measure(args.binary, name, env_extra, flags, large, args.burst, small_body, args.small)


if __name__ == "__main__":
    main()
