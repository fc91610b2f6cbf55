#!/usr/bin/env python3
"""Occlusion culling over HTTP: a stored furnished home rendered from its observer camera with
options.culling on and off.

A server starts with a fresh data directory and --render-threads 2; the home (default
3BedroomApartment of ../shared/data/floorplans/sweethome3d, zipped with its furniture/ folder as
scripts/render-home.sh sends it) is imported with POST /v1/import/sh3d?store=1; then
POST /v1/scenes/{id}/render from the receipt's camera at 1280x720, flat, zbuffer, one first render
each way and --renders (default 5) interleaved renders each way. Per setting: the Server-Timing totals,
their median, the last answer's stages, and whether the PNG bytes are identical on and off. Writes
bench/results/cells_http.json (or --out). Standard library only; loopback only.

usage: bench/culling_http.py [--binary build/roomrender] [--home 3BedroomApartment] [--renders 5]
"""
import argparse
import http.client
import json
import os
import re
import statistics
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_server import start_server  # noqa: E402
from store_homes import home_zip  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.environ.get("ROOMRENDER_SHARED", os.path.join(os.path.dirname(ROOT), "shared"))


def post(port, path, body, content_type):
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=600)
    try:
        conn.request("POST", path, body=body, headers={"Content-Type": content_type})
        answer = conn.getresponse()
        return answer.status, dict(answer.getheaders()), answer.read()
    finally:
        conn.close()


def stages(header):
    return {m.group(1): float(m.group(2)) for m in re.finditer(r"(\w+);dur=([0-9.]+)", header)}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--binary", default=os.path.join(ROOT, "build", "roomrender"))
    ap.add_argument("--home", default="3BedroomApartment")
    ap.add_argument("--renders", type=int, default=5)
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results", "cells_http.json"))
    a = ap.parse_args()
    path = os.path.join(SHARED, "data", "floorplans", "sweethome3d", a.home + ".xml")
    with open(path, encoding="utf-8") as f:
        body = home_zip(path, f.read())
    load_before = [round(x, 2) for x in os.getloadavg()]
    server, port = start_server(a.binary, ["--data-dir", tempfile.mkdtemp(prefix="culling-http-"),
                                           "--render-threads", "2", "--render-timeout-ms", "120000"])
    try:
        status, _, answer = post(port, "/v1/import/sh3d?store=1", body, "application/zip")
        if status != 201:
            sys.exit("import answered %d: %s" % (status, answer[:300]))
        receipt = json.loads(answer)
        location, camera = receipt["location"], receipt["camera"]
        totals, last, pngs = {"on": [], "off": []}, {}, {}
        for k in range(a.renders + 1):  # render 0 of each warms the caches; not counted
            for culling in ("on", "off"):
                view = {"camera": camera, "options": {"width": 1280, "height": 720, "shading": "flat",
                                                      "pipeline": "zbuffer", "culling": culling}}
                status, headers, png = post(port, location + "/render", json.dumps(view), "application/json")
                if status != 200:
                    sys.exit("render answered %d: %s" % (status, png[:300]))
                timing = stages(headers.get("Server-Timing", headers.get("server-timing", "")))
                if k > 0:
                    totals[culling].append(timing["total"])
                last[culling], pngs[culling] = timing, png
    finally:
        server.terminate()
        server.wait()
    out = {"scene": a.home + " (with models, stored)", "id": location.rsplit("/", 1)[-1],
           "server_timing_total_ms": totals,
           "median_on": statistics.median(totals["on"]), "median_off": statistics.median(totals["off"]),
           "ratio_on_off": statistics.median(totals["on"]) / statistics.median(totals["off"]),
           "png_identical": pngs["on"] == pngs["off"], "last_stages": last,
           "load_before": load_before, "load_after": [round(x, 2) for x in os.getloadavg()]}
    with open(a.out, "w") as f:
        json.dump(out, f, indent=1)
        f.write("\n")
    print("%s: Server-Timing total median on %.1f ms, off %.1f ms (%.2f), PNG identical %s, load %s -> %s" % (
        a.home, out["median_on"], out["median_off"], out["ratio_on_off"], out["png_identical"], load_before,
        out["load_after"]))


if __name__ == "__main__":
    main()
