#!/usr/bin/env python3
"""A contact sheet of the Sweet Home 3D homes seen from their observer cameras with Phong and shadows.

One row per home (sun_leaks.HOMES, in that order); columns: shadow maps drawn by BEFORE, by AFTER,
then shadow rays by BEFORE, by AFTER (e.g. two builds either side of a change). Each build imports
each home with its furniture models. The tiles are PNGs asked for with `--png none`, read and the
sheet written with sun_leaks' PNG helpers.

    python3 bench/contact_sheet.py OUT.png BEFORE/roomrender AFTER/roomrender [--tile 256x144]

Homes are read from ../shared/data/floorplans/sweethome3d (ROOMRENDER_SHARED names another parent).
"""
import argparse
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sun_leaks import HOMES, read_png, write_png  # noqa: E402

GAP = 4  # white pixels around and between tiles


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out")
    parser.add_argument("before")
    parser.add_argument("after")
    parser.add_argument("--tile", default="256x144")
    args = parser.parse_args()
    tw, th = (int(v) for v in args.tile.split("x"))
    repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    shared = os.environ.get("ROOMRENDER_SHARED", os.path.join(repo, "..", "shared"))
    homes = os.path.join(shared, "data", "floorplans", "sweethome3d")
    cells = [("map", args.before), ("map", args.after), ("rays", args.before), ("rays", args.after)]
    width = len(cells) * tw + (len(cells) + 1) * GAP
    height = len(HOMES) * th + (len(HOMES) + 1) * GAP
    sheet = bytearray(b"\xff" * (width * height * 3))
    with tempfile.TemporaryDirectory() as tmp:
        for row, name in enumerate(HOMES):
            requests = {}
            for b, binary in enumerate((args.before, args.after)):
                path = os.path.join(tmp, f"{name}.{b}.json")
                with open(path, "wb") as f:
                    f.write(subprocess.run([binary, "import", os.path.join(homes, name + ".xml"), "--furniture", "models"],
                                           check=True, capture_output=True).stdout)
                requests[binary] = path
            for col, (method, binary) in enumerate(cells):
                png = os.path.join(tmp, f"{name}.{col}.png")
                subprocess.run([binary, "render", requests[binary], "-o", png, "--png", "none", "--size", f"{tw}x{th}",
                                "--shading", "phong", "--shadows", "true", "--shadow-method", method],
                               check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                w, h, channels, pixels = read_png(png)
                x0, y0 = GAP + col * (tw + GAP), GAP + row * (th + GAP)
                for y in range(min(th, h)):
                    line = pixels[y * w * channels:(y + 1) * w * channels]
                    rgb = bytes(line) if channels == 3 else bytes(v for i, v in enumerate(line) if i % 4 != 3)
                    start = ((y0 + y) * width + x0) * 3
                    sheet[start:start + min(tw, w) * 3] = rgb[:min(tw, w) * 3]
            print(f"{name}: done", flush=True)
    write_png(args.out, width, height, bytes(sheet))
    print(f"wrote {args.out} ({width}x{height}, {os.path.getsize(args.out)} bytes); rows: {', '.join(HOMES)}")


if __name__ == "__main__":
    main()
