#!/usr/bin/env python3
"""Cells and portals at eye level in the nine homes: what the portal walk adds to occlusion culling.

Each Sweet Home 3D home of ../shared/data/floorplans/sweethome3d is imported with its furniture
models (`roomrender import --furniture models`, as the service imports it); `bench_culling frames`
then draws it from its observer camera and --inside seeded interior cameras at eye height (seed
--seed, tests/support/culling_cases.hpp), 1280x720, zbuffer flat, --threads render threads, culling
off, on without the portal walk ("occlusion") and on with it, interleaved frame after frame
(--frames each). Per home: the polygons projected with cells as a share of the home's (median and
worst camera; the goal is <= 15 %), the median frame times of the three settings over the cameras,
and the cells visited. Writes bench/results/cells.json (or --out) and prints a Markdown table.

usage: bench/cells.py BUILD_DIR [--threads 2] [--inside 10] [--frames 5] [--seed 2029]
"""
import argparse
import glob
import json
import os
import statistics
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.environ.get("ROOMRENDER_SHARED", os.path.join(os.path.dirname(ROOT), "shared"))
SUN = "0.4,1,0.3"


def load():
    return [round(x, 2) for x in os.getloadavg()]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--inside", type=int, default=10)
    ap.add_argument("--frames", type=int, default=5)
    ap.add_argument("--seed", type=int, default=2029)
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results", "cells.json"))
    a = ap.parse_args()
    binary = os.path.join(a.build, "roomrender")
    bench = os.path.join(a.build, "bench", "bench_culling")
    work = tempfile.mkdtemp(prefix="cells-homes-")
    rows = []
    for xml in sorted(glob.glob(os.path.join(SHARED, "data", "floorplans", "sweethome3d", "*.xml"))):
        name = os.path.splitext(os.path.basename(xml))[0]
        req, out = os.path.join(work, name + ".json"), os.path.join(work, name + ".frames.json")
        with open(req, "w") as f:
            subprocess.run([binary, "import", xml, "--furniture", "models"], stdout=f, stderr=subprocess.DEVNULL,
                           check=True)
        before = load()
        subprocess.run([bench, "frames", "--request", req, "--inside", str(a.inside), "--threads", str(a.threads),
                        "--frames", str(a.frames), "--light-dir", SUN, "--seed", str(a.seed), "--out", out],
                       stdout=subprocess.DEVNULL, check=True)
        with open(out) as f:
            cams = json.load(f)
        polygons = cams[0]["polygons"]
        share = [100.0 * c["on"]["polygons_projected"] / polygons for c in cams]
        share_occlusion = [100.0 * c["occlusion"]["polygons_projected"] / polygons for c in cams]
        ms = {m: statistics.median(c[m]["frame_ms"] for c in cams) for m in ("on", "occlusion", "off")}
        row = {"home": name, "polygons": polygons, "cells": cams[0]["on"]["cells"], "threads": a.threads,
               "cameras": len(cams),
               "projected_pct": {"median": statistics.median(share), "observer": share[0], "worst": max(share)},
               "projected_occlusion_pct": {"median": statistics.median(share_occlusion), "observer": share_occlusion[0],
                                           "worst": max(share_occlusion)},
               "frame_ms_median": ms,
               "observer_frame_ms": {m: cams[0][m]["frame_ms"] for m in ("on", "occlusion", "off")},
               "cells_visited": [c["on"]["cells_visited"] for c in cams],
               "cull_ms_median": {m: statistics.median(c[m]["cull_ms"] for c in cams) for m in ("on", "occlusion")},
               "per_camera": cams, "load_before": before, "load_after": load()}
        rows.append(row)
        print("%s: projected %.1f %% median, %.1f %% observer, %.1f %% worst (occlusion alone %.1f / %.1f / %.1f); "
              "flat ms median cells %.1f, occlusion %.1f, off %.1f; load %s" % (
                  name, row["projected_pct"]["median"], share[0], max(share),
                  row["projected_occlusion_pct"]["median"], share_occlusion[0], max(share_occlusion),
                  ms["on"], ms["occlusion"], ms["off"], before), flush=True)
    with open(a.out, "w") as f:
        json.dump({"seed": a.seed, "inside": a.inside, "frames": a.frames, "threads": a.threads, "size": "1280x720",
                   "homes": rows}, f, indent=1)
        f.write("\n")
    print("\n| home | polygons | cells | projected with cells: median; observer; worst (%) | occlusion alone (%) "
          "| flat ms, median camera: cells / occlusion / off | observer: cells / occlusion / off |")
    print("|---|---:|---:|---|---|---|---|")
    for r in rows:
        p, q, m, o = r["projected_pct"], r["projected_occlusion_pct"], r["frame_ms_median"], r["observer_frame_ms"]
        print("| %s | %d | %d | %.1f; %.1f; %.1f | %.1f; %.1f; %.1f | %.1f / %.1f / %.1f | %.1f / %.1f / %.1f |" % (
            r["home"], r["polygons"], r["cells"], p["median"], p["observer"], p["worst"], q["median"], q["observer"],
            q["worst"], m["on"], m["occlusion"], m["off"], o["on"], o["occlusion"], o["off"]))


if __name__ == "__main__":
    main()
