#!/usr/bin/env python3
"""Sunlight leaks of the shadow maps, measured against exact shadow rays, on Sweet Home 3D homes.

For each home: `roomrender import HOME.xml --furniture models` at 960x540 from its observer camera,
the lamps dropped (the sun alone), Phong + shadows, rendered with the sun on and at intensity 0, for
`options.shadow.method` `map` and `rays`. A pixel is *lit* by the sun when the two renders of a
method differ by more than 2 levels in a channel. A *leak* is a pixel the map lights where rays
leaves it dark, away from the 2-pixel band (Chebyshev distance) around rays' shadow edges (a pixel
whose lit state differs from a 4-neighbour's), the band of docs/accuracy.md's shadow error.

  bench/sun_leaks.py BUILD_DIR [--homes DIR] [--only NAME ...] [--request FILE ...] [--images DIR]
                    [--json FILE] [--options JSON]

Prints one line per home (leaks, and for scale the pixels each method lights, the reverse
disagreement and the band's size); --images writes per home the four renders and a picture of the
map's lit pixels with the leaks in red; --json writes the numbers. Pure Python: the renders are
asked for with `--png none` (stored, unfiltered), which this script decodes itself.
"""
import argparse
import json
import os
import struct
import subprocess
import sys
import tempfile
import zlib

HOMES = ["1BedroomApartmentWithRoundWall", "2BedroomApartment", "2BedroomApartmentWithBowWindow",
         "2BedroomHouseWithBasement", "3BedroomApartment", "3BedroomHouseWithAttic",
         "3BedroomHouseWithMezzanine", "4BedroomHouse", "Studio"]
WIDTH, HEIGHT = 960, 540
LIT_LEVELS = 2  # a pixel the sun lights differs by more than this in some channel
BAND = 2        # Chebyshev distance to rays' shadow edges left out


def read_png(path):
    """(width, height, channels, bytes) of an 8-bit RGB/RGBA PNG written with `--png none`."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    pos, idat, header = 8, b"", None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    width, height, depth, colour = header[:4]
    assert depth == 8 and colour in (2, 6), f"{path}: 8-bit RGB or RGBA expected"
    channels = 3 if colour == 2 else 4
    raw = zlib.decompress(idat)
    stride = width * channels
    rows = []
    for y in range(height):
        row = raw[y * (stride + 1):(y + 1) * (stride + 1)]
        assert row[0] == 0, f"{path}: an unfiltered PNG (--png none) expected"
        rows.append(row[1:])
    return width, height, channels, b"".join(rows)


def write_png(path, width, height, rgb):
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    raw = b"".join(b"\x00" + rgb[y * width * 3:(y + 1) * width * 3] for y in range(height))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


def lit_mask(on, off, channels):
    n = len(on) // channels
    mask = bytearray(n)
    for i in range(n):
        k = i * channels
        for c in range(3):
            if abs(on[k + c] - off[k + c]) > LIT_LEVELS:
                mask[i] = 1
                break
    return mask


def edge_band(mask, width, height):
    """Pixels within BAND (Chebyshev) of a pixel whose mask differs from a 4-neighbour's."""
    edge = bytearray(width * height)
    for y in range(height):
        for x in range(width):
            i = y * width + x
            m = mask[i]
            if (x > 0 and mask[i - 1] != m) or (x + 1 < width and mask[i + 1] != m) or \
               (y > 0 and mask[i - width] != m) or (y + 1 < height and mask[i + width] != m):
                edge[i] = 1
    band = bytearray(width * height)
    for y in range(height):
        for x in range(width):
            if edge[y * width + x]:
                for yy in range(max(0, y - BAND), min(height, y + BAND + 1)):
                    row = yy * width
                    for xx in range(max(0, x - BAND), min(width, x + BAND + 1)):
                        band[row + xx] = 1
    return band


def sun_alone(request, extra):
    """The request with its directional lights only (the sun), Phong + shadows, 960x540, `extra`
    merged into its options (`shadow` member by member)."""
    scene = request["scene"]
    scene["lights"] = [light for light in scene.get("lights", []) if light.get("type") == "directional"]
    options = request.setdefault("options", {})
    options.update({"width": WIDTH, "height": HEIGHT, "shading": "phong", "shadows": True})
    extra = dict(extra)
    options.setdefault("shadow", {}).update(extra.pop("shadow", {}))
    options.update(extra)
    return request


def render(binary, request, method, sun_on, out_png, tmp):
    request = json.loads(json.dumps(request))
    request["options"].setdefault("shadow", {})["method"] = method
    if not sun_on:
        for light in request["scene"]["lights"]:
            light["intensity"] = 0
    path = os.path.join(tmp, "request.json")
    with open(path, "w") as f:
        json.dump(request, f)
    subprocess.run([binary, "render", path, "-o", out_png, "--png", "none"], check=True,
                   stdout=subprocess.DEVNULL)
    return read_png(out_png)


def measure(binary, source, images, tmp, extra):
    if source.endswith(".xml"):
        request = json.loads(subprocess.run(
            [binary, "import", source, "--furniture", "models", "--width", str(WIDTH), "--height", str(HEIGHT)],
            check=True, capture_output=True).stdout)
    else:
        with open(source) as f:
            request = json.load(f)
    request = sun_alone(request, extra)
    if not request["scene"]["lights"]:
        return {"sun": False}
    name = os.path.splitext(os.path.basename(source))[0]
    lit, frames = {}, {}
    for method in ("map", "rays"):
        shots = []
        for sun_on in (True, False):
            png = os.path.join(images or tmp, f"{name}_{method}_{'on' if sun_on else 'off'}.png")
            shots.append(render(binary, request, method, sun_on, png, tmp))
        width, height, channels, on = shots[0]
        lit[method] = lit_mask(on, shots[1][3], channels)
        frames[method] = (on, channels)
    band = edge_band(lit["rays"], width, height)
    leaks = [i for i in range(width * height) if lit["map"][i] and not lit["rays"][i] and not band[i]]
    dark = sum(1 for i in range(width * height) if lit["rays"][i] and not lit["map"][i] and not band[i])
    if images:
        on, channels = frames["map"]
        rgb = bytearray(width * height * 3)
        for i in range(width * height):
            g = on[i * channels + 1] // 3 + (150 if lit["map"][i] else 0)
            rgb[i * 3:i * 3 + 3] = bytes((g, g, g))
        for i in leaks:
            rgb[i * 3:i * 3 + 3] = b"\xff\x00\x00"
        write_png(os.path.join(images, f"{name}_leaks.png"), width, height, bytes(rgb))
    return {"sun": True, "leaks": len(leaks), "rays_lit_map_dark": dark,
            "map_lit": sum(lit["map"]), "rays_lit": sum(lit["rays"]), "band": sum(band),
            "leak_pixels": [[i % width, i // width] for i in leaks[:50]]}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build")
    parser.add_argument("--homes", default=None, help="folder of the homes' XML (default ../shared/...)")
    parser.add_argument("--only", nargs="*", default=None, help="home names (default: the nine)")
    parser.add_argument("--images", default=None, help="folder for the renders and leak pictures")
    parser.add_argument("--request", nargs="*", default=[], help="render requests to measure instead of homes")
    parser.add_argument("--json", default=None)
    parser.add_argument("--options", default="{}", help="JSON merged into each request's options, e.g. "
                        "'{\"pipeline\": \"bsp\", \"shadow\": {\"size\": 4096}}'")
    args = parser.parse_args()
    here = os.path.dirname(os.path.abspath(__file__))
    homes = args.homes
    if homes is None:
        for shared in (os.path.join(here, "..", "..", "shared"), "/work/shared"):
            if os.path.isdir(os.path.join(shared, "data/floorplans/sweethome3d")):
                homes = os.path.join(shared, "data/floorplans/sweethome3d")
                break
    if homes is None and not args.request:
        sys.exit("no homes folder: pass --homes")
    binary = os.path.join(os.path.abspath(args.build), "roomrender")
    if args.images:
        os.makedirs(args.images, exist_ok=True)
    results = {}
    with tempfile.TemporaryDirectory() as tmp:
        sources = args.request or [os.path.join(homes, name + ".xml") for name in args.only or HOMES]
        for source in sources:
            name = os.path.splitext(os.path.basename(source))[0]
            r = measure(binary, source, args.images, tmp, json.loads(args.options))
            results[name] = r
            if not r["sun"]:
                print(f"{name:32s} no sun")
                continue
            print(f"{name:32s} leaks {r['leaks']:6d}   map lit {r['map_lit']:7d}  rays lit {r['rays_lit']:7d}"
                  f"  rays lit, map dark {r['rays_lit_map_dark']:5d}  band {r['band']:7d}", flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"size": [WIDTH, HEIGHT], "lit_levels": LIT_LEVELS, "band": BAND, "homes": results}, f,
                      indent=1)


if __name__ == "__main__":
    main()
