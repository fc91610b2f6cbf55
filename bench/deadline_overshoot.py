#!/usr/bin/env python3
"""Deadline overshoot: how long after its render deadline a heavy BSP build is answered.

Starts `roomrender serve --render-timeout-ms T` on a free loopback port and POSTs, --runs times, a
render of a random triangle soup (--triangles triangles scattered through a 20 m cube, seeded, so
nearly every splitter cuts many of them) with the bsp pipeline. Each request's BSP tree is new to
the server (the soup's seed changes per run), so every request builds. Reports, per run, the status
and the time from the body's last byte to the answer, and the overshoot = that time - T, then the
server's RSS (from /metrics) before and after. A normal render (examples/studio.json, 320x240) is
sent last and must answer 200. Standard library only; loopback only; bounded by --runs.

usage: bench/deadline_overshoot.py [--binary build/roomrender] [--timeout-ms 2000] [--runs 3]
                                   [--triangles 100000] [--edge 3]
"""
import argparse
import http.client
import json
import os
import random
import subprocess
import sys
import time

from bench_server import resident_mib, start_server

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def soup_request(triangles, edge, seed):
    rng = random.Random(seed)
    vertices, faces = [], []
    while len(faces) < triangles:
        a = [rng.uniform(-10, 10) for _ in range(3)]
        b = [a[k] + rng.uniform(-edge, edge) for k in range(3)]
        c = [a[k] + rng.uniform(-edge, edge) for k in range(3)]
        u = [b[k] - a[k] for k in range(3)]
        v = [c[k] - a[k] for k in range(3)]
        n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
        if sum(x * x for x in n) ** 0.5 < 0.05 * edge * edge:  # no slivers
            continue
        first = len(vertices)
        vertices += [[round(x, 4) for x in p] for p in (a, b, c)]
        faces.append([first, first + 1, first + 2])
    return {"scene": {"background": "#202020",
                      "solids": [{"type": "mesh", "id": "soup", "color": "#b0b0b0",
                                  "vertices": vertices, "faces": faces}]},
            "camera": {"position": [0, 2, 30], "target": [0, 0, 0], "far": 100},
            "options": {"width": 320, "height": 240, "pipeline": "bsp", "shading": "flat"}}


def post(port, body, timeout_s):
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=timeout_s)
    conn.request("POST", "/v1/render", body=body, headers={"Content-Type": "application/json"})
    # From the body's last byte written: the deadline runs from admission, after the body is read,
    # so the upload of a large body is not part of the overshoot.
    started = time.perf_counter()
    response = conn.getresponse()
    response.read()
    elapsed_ms = (time.perf_counter() - started) * 1000.0
    conn.close()
    return response.status, elapsed_ms


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--binary", default=os.path.join(ROOT, "build", "roomrender"))
    parser.add_argument("--timeout-ms", type=int, default=2000)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--triangles", type=int, default=100000)
    parser.add_argument("--edge", type=float, default=3.0, help="largest edge offset in metres")
    parser.add_argument("--server-flag", action="append", default=[], help="passed on to serve (repeat)")
    args = parser.parse_args()

    bodies = [json.dumps(soup_request(args.triangles, args.edge, seed)).encode() for seed in range(args.runs)]
    server, port = start_server(args.binary, ["--render-timeout-ms", str(args.timeout_ms), "--max-body-bytes", str(64 << 20), *args.server_flag])
    try:
        print(f"binary {args.binary}, deadline {args.timeout_ms} ms, {args.triangles} triangles (edge {args.edge} m), bsp")
        print(f"RSS before: {resident_mib(port):.0f} MiB")
        for run, body in enumerate(bodies):
            status, elapsed_ms = post(port, body, 120)
            print(f"run {run}: status {status}, answered after {elapsed_ms:.0f} ms, "
                  f"overshoot {elapsed_ms - args.timeout_ms:+.0f} ms, RSS {resident_mib(port):.0f} MiB")
        with open(os.path.join(ROOT, "examples", "studio.json"), "rb") as f:
            studio = json.load(f)
        studio.setdefault("options", {}).update({"width": 320, "height": 240})
        status, elapsed_ms = post(port, json.dumps(studio).encode(), 60)
        print(f"normal render after: status {status}, {elapsed_ms:.0f} ms")
    finally:
        server.terminate()
        server.wait(timeout=30)


if __name__ == "__main__":
    main()
