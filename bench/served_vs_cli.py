#!/usr/bin/env python3
"""Served vs command line: the same render through `roomrender render` and through a real server.

Renders examples/apartment.json at 1280x720 (zbuffer, the example's own options otherwise) in
interleaved pairs: one CLI run, then one POST /v1/render to a `roomrender serve` this script starts
on a free loopback port. Both report stage timings: the CLI in its JSON line, the server in
Server-Timing. `total` is parse -> encode in both (the server's queue wait is its own stage, not
part of total), so the ratio compares like with like. Reports the median over the pairs of
served total / CLI total (goal <= 1.15), the client-measured wall time of each (process start to
exit for the CLI, request to last byte for HTTP), the encode times and the PNG sizes.

Writes bench/results/served_vs_cli.json (one entry per --label, so a "before" and an "after" run of
different binaries sit side by side) and prints a short table. Standard library only.

usage: bench/served_vs_cli.py [--binary build/roomrender] [--pairs 7] [--label after]
                              [--width 1280] [--height 720] [--out bench/results/served_vs_cli.json]
"""
import argparse
import http.client
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

from bench_server import start_server

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def server_timing(header):
    """'parse;dur=1.2, total;dur=3.4' -> {'parse': 1.2, 'total': 3.4}"""
    stages = {}
    for entry in header.split(","):
        name, _, rest = entry.strip().partition(";")
        for param in rest.split(";"):
            key, _, value = param.strip().partition("=")
            if key == "dur":
                stages[name] = float(value)
    return stages


def cli_render(binary, request_path, png_path):
    started = time.perf_counter()
    run = subprocess.run([binary, "render", request_path, "-o", png_path], capture_output=True, text=True)
    wall_ms = (time.perf_counter() - started) * 1000.0
    if run.returncode != 0:
        sys.exit(f"roomrender render failed: {run.stderr}")
    line = json.loads(run.stdout)
    with open(png_path, "rb") as f:
        size = len(f.read())
    return {"wall_ms": wall_ms, "timings_ms": line["timings_ms"], "png_bytes": size}


def served_render(port, body):
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=120)
    started = time.perf_counter()
    connection.request("POST", "/v1/render", body=body, headers={"Content-Type": "application/json"})
    response = connection.getresponse()
    png = response.read()
    wall_ms = (time.perf_counter() - started) * 1000.0
    connection.close()
    if response.status != 200:
        sys.exit(f"POST /v1/render answered {response.status}: {png[:300]!r}")
    return {"wall_ms": wall_ms, "timings_ms": server_timing(response.getheader("Server-Timing", "")),
            "png_bytes": len(png)}


def median_of(runs, key):
    return statistics.median(key(r) for r in runs)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--binary", default=os.path.join(ROOT, "build", "roomrender"))
    parser.add_argument("--pairs", type=int, default=7)
    parser.add_argument("--label", default="after")
    parser.add_argument("--width", type=int, default=1280)
    parser.add_argument("--height", type=int, default=720)
    parser.add_argument("--out", default=os.path.join(ROOT, "bench", "results", "served_vs_cli.json"))
    args = parser.parse_args()
    if args.pairs < 5:
        sys.exit("--pairs must be at least 5")

    with open(os.path.join(ROOT, "examples", "apartment.json")) as f:
        request = json.load(f)
    request.setdefault("options", {}).update({"width": args.width, "height": args.height})
    body = json.dumps(request).encode()

    server, port = start_server(args.binary)
    work = tempfile.mkdtemp(prefix="served_vs_cli.")
    request_path, png_path = os.path.join(work, "request.json"), os.path.join(work, "out.png")
    with open(request_path, "wb") as f:
        f.write(body)
    try:
        cli_render(args.binary, request_path, png_path)  # warm-up: page cache, allocator
        served_render(port, body)
        pairs = []
        for _ in range(args.pairs):
            cli = cli_render(args.binary, request_path, png_path)
            served = served_render(port, body)
            pairs.append({"cli": cli, "served": served,
                          "total_ratio": served["timings_ms"]["total"] / cli["timings_ms"]["total"]})
    finally:
        server.terminate()
        server.wait(timeout=30)
        for path in (request_path, png_path):
            if os.path.exists(path):
                os.remove(path)
        os.rmdir(work)

    def summary(side):
        runs = [p[side] for p in pairs]
        return {"total_ms": median_of(runs, lambda r: r["timings_ms"]["total"]),
                "encode_ms": median_of(runs, lambda r: r["timings_ms"].get("encode", 0.0)),
                "queue_ms": median_of(runs, lambda r: r["timings_ms"].get("queue", 0.0)),
                "wall_ms": median_of(runs, lambda r: r["wall_ms"]),
                "png_bytes": runs[-1]["png_bytes"]}

    result = {
        "binary": os.path.abspath(args.binary),
        "scene": "examples/apartment.json", "width": args.width, "height": args.height,
        "pipeline": request["options"].get("pipeline", "zbuffer"), "pairs": args.pairs,
        "cpu_count": os.cpu_count(), "load_average": os.getloadavg()[0],
        "median_total_ratio": statistics.median(p["total_ratio"] for p in pairs),
        "cli": summary("cli"), "served": summary("served"),
        "runs": pairs,
    }
    results = {}
    if os.path.exists(args.out):
        with open(args.out) as f:
            results = json.load(f)
    results[args.label] = result
    os.makedirs(os.path.dirname(args.out), exist_ok=True)
    with open(args.out, "w") as f:
        json.dump(results, f, indent=2)
        f.write("\n")

    print(f"{args.label}: apartment {args.width}x{args.height}, {args.pairs} pairs, {args.binary}")
    print(f"{'':8} {'total ms':>9} {'encode ms':>10} {'queue ms':>9} {'wall ms':>8} {'PNG bytes':>10}")
    for side in ("cli", "served"):
        s = result[side]
        print(f"{side:8} {s['total_ms']:9.1f} {s['encode_ms']:10.1f} {s['queue_ms']:9.1f} {s['wall_ms']:8.1f} "
              f"{s['png_bytes']:10d}")
    print(f"median served/CLI total: {result['median_total_ratio']:.3f} (goal <= 1.15)")


if __name__ == "__main__":
    main()
