#!/usr/bin/env python3
"""Exact shadows on the nine Sweet Home 3D homes from inside: shadow rays against shadow maps and Embree.

  python3 bench/shadow_rays_homes.py BUILD_DIR [--inside 10] [--threads 1 2] [--frames 3] [--map-frames 1]
                                     [--seed 2029] [--homes 3BedroomApartment Studio] [--out FILE]

Each home is imported with its furniture models as the service imports it, with its own sun and lamps,
and exported to OBJ (polygon k = face k). Cameras: the home's observer camera and --inside seeded
interior cameras at eye height (bench_culling frames, tests/support/culling_cases.hpp: the cameras the
culling bench and identity tests use). For every camera and thread count, one after another:
- Embree (../shared/peers peer_render --mode rt --lights: a primary ray and one exact shadow ray per
  lamp within reach, the home's lights and ambient, the OBJ without materials);
- ours, Phong + shadows with shadow.method rays (bench-render --request, the same camera);
- ours, Phong + shadows with shadow.method map, the default (fewer frames: it is the slow one).
Ours runs with --shadow-cache off: every frame pays for its shadows, as the first frame of an edited
scene does (a cached map frame costs about what a frame without shadows costs).
Window panes are made opaque in our request, as ../shared/peers/tools/side_by_side.py --home-lights
does: the peers cannot see or shine through a pane. 1280x720. Ratios per camera are taken within one
camera's back-to-back runs; a home's figure is the median over its cameras, and the summary's the median
over homes. Needs the peer harness built outside ../shared (PEERS_BUILD, default /work/peers/build).
Writes JSON (default bench/results/shadow_rays_homes.json). Standard library only.
"""
import argparse, glob, json, os, statistics, subprocess, sys, tempfile, time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from culling import SHARED, PEER, cam_flags, load, peer, run, write_lights  # noqa: E402  (the culling bench's helpers)


def ours(binary, req, cam, method, frames, threads):
    j = run([binary, "bench-render", "--request", req] + cam +
            ["--size", "1280x720", "--frames", str(frames), "--threads", str(threads), "--shading", "phong",
             "--shadows", "true", "--shadow-method", method, "--shadow-cache", "off"])
    return {"ms": j["frame_ms_median"], "stages": j.get("stage_ms_median", {})} if j else None


def prepare(binary, xml, work):
    """The imported request (panes opaque), its OBJ export and its peer lights file."""
    name = os.path.splitext(os.path.basename(xml))[0]
    req, obj = os.path.join(work, name + ".json"), os.path.join(work, name + ".obj")
    with open(req, "w") as f:
        subprocess.run([binary, "import", xml, "--furniture", "models"], stdout=f, stderr=subprocess.DEVNULL, check=True)
    subprocess.run([binary, "export", req, "--obj", obj], capture_output=True, check=True)
    r = json.load(open(req))
    scene = r["scene"]
    for w in scene.get("walls", []):
        for o in w.get("openings", []):
            if o.get("type") == "window":
                o["opacity"] = 1.0
    opaque = os.path.join(work, name + ".opaque.json")
    json.dump(r, open(opaque, "w"))
    lights = os.path.join(work, name + ".lights.json")
    write_lights(scene, lights)
    return name, opaque, obj, lights, len(scene.get("lights", []))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("--inside", type=int, default=10)
    ap.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--frames", type=int, default=3, help="frames of rays and of Embree per camera (median)")
    ap.add_argument("--map-frames", type=int, default=1, help="frames of the shadow-map method per camera")
    ap.add_argument("--seed", type=int, default=2029)
    ap.add_argument("--homes", nargs="*", help="only these homes (file names without .xml)")
    ap.add_argument("--out", default=os.path.join(HERE, "results", "shadow_rays_homes.json"))
    a = ap.parse_args()
    if not os.path.exists(PEER):
        sys.exit("no peer harness at %s (see ../shared/peers/README.md)" % PEER)
    binary = os.path.join(a.build, "roomrender")
    cams_tool = os.path.join(a.build, "bench", "bench_culling")
    work = tempfile.mkdtemp(prefix="shadow-rays-homes-")
    xmls = sorted(glob.glob(os.path.join(SHARED, "data", "floorplans", "sweethome3d", "*.xml")))
    if a.homes:
        xmls = [x for x in xmls if os.path.splitext(os.path.basename(x))[0] in a.homes]
    rows, homes, start = [], [], time.time()
    for xml in xmls:
        name, req, obj, lights, n_lights = prepare(binary, xml, work)
        listed = run([cams_tool, "frames", "--request", req, "--inside", str(a.inside), "--threads", "1", "--frames", "1",
                      "--seed", str(a.seed), "--size", "64x36", "--out", os.path.join(work, name + ".cams.json")])
        if not listed:
            continue
        for threads in a.threads:
            before, mine = load(), []
            for k, c in enumerate(listed):
                cam = cam_flags(c["camera"], light=False)
                # Embree with the same thread count (peer_render's --threads; LP_NUM_THREADS is llvmpipe's).
                e = peer("rt", obj, cam, a.frames, threads, ["--lights", lights, "--threads", str(threads)])
                r = ours(binary, req, cam, "rays", a.frames, threads)
                m = ours(binary, req, cam, "map", a.map_frames, threads)
                if not (e and r and m):
                    continue
                row = {"home": name, "lights": n_lights, "camera_index": k, "camera_kind": c["kind"], "camera": c["camera"],
                       "threads": threads, "embree_ms": e, "rays_ms": r["ms"], "map_ms": m["ms"],
                       "rays_stages": r["stages"], "map_stages": m["stages"],
                       "rays_over_embree": r["ms"] / e, "map_over_rays": m["ms"] / r["ms"]}
                rows.append(row), mine.append(row)
            if mine:
                h = {"home": name, "lights": n_lights, "threads": threads, "cameras": len(mine),
                     "rays_ms": statistics.median(x["rays_ms"] for x in mine),
                     "embree_ms": statistics.median(x["embree_ms"] for x in mine),
                     "map_ms": statistics.median(x["map_ms"] for x in mine),
                     "rays_over_embree": statistics.median(x["rays_over_embree"] for x in mine),
                     "map_over_rays": statistics.median(x["map_over_rays"] for x in mine),
                     "observer_rays_over_embree": mine[0]["rays_over_embree"] if mine[0]["camera_kind"] == "observer" else None,
                     "load_before": before, "load_after": load()}
                homes.append(h)
                print("%-28s %2d lights t%d: rays %6.1f  Embree %6.1f  map %7.1f ms (medians of %d cameras); rays/Embree %.2f,"
                      " map/rays %.1f; load %s" % (name, n_lights, threads, h["rays_ms"], h["embree_ms"], h["map_ms"], len(mine),
                                                   h["rays_over_embree"], h["map_over_rays"], h["load_after"]), flush=True)
    summary = {}
    for threads in a.threads:
        hs = [h for h in homes if h["threads"] == threads]
        if hs:
            summary["t%d" % threads] = {"homes": len(hs),
                                        "median_home_rays_over_embree": statistics.median(h["rays_over_embree"] for h in hs),
                                        "median_home_map_over_rays": statistics.median(h["map_over_rays"] for h in hs)}
            print("t%d: median home rays/Embree %.2f (goal <= 1.0), map/rays %.1f (goal >= 10)" % (
                threads, summary["t%d" % threads]["median_home_rays_over_embree"], summary["t%d" % threads]["median_home_map_over_rays"]))
    result = {"inside_cameras": a.inside, "frames": a.frames, "map_frames": a.map_frames, "seed": a.seed, "size": "1280x720",
              "seconds": round(time.time() - start), "summary": summary, "homes": homes, "rows": rows}
    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    json.dump(result, open(a.out, "w"), indent=1)
    print("wrote %s (%d rows, %d s)" % (a.out, len(rows), result["seconds"]))


if __name__ == "__main__":
    main()
