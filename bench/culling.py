#!/usr/bin/env python3
"""Occlusion culling against the peers (../shared/peers: llvmpipe and Embree), culling on and off, in one run.

  python3 bench/culling.py BUILD_DIR [--rounds 2] [--frames 7] [--threads 1 2] [--inside 10] [--quick]
                           [--out bench/results/culling.json]

Needs the peer harness built outside ../shared (PEERS_BUILD, default /work/peers/build) and its scenes
generated (PEERS_SCENES, default /work/peers/scenes), as ../shared/peers/README.md says; the data is read
from ../shared (ROOMRENDER_SHARED elsewhere).

- Homes (flat, one sun: the yardstick of side_by_side.py --homes): each Sweet Home 3D home imported with
  its furniture models as the service imports it; bench_culling draws its request from the observer
  camera and --inside seeded interior cameras at eye height, zbuffer flat, culling off and on interleaved
  frame by frame; llvmpipe (gl-flat) draws the home's OBJ export from each of the same cameras. Each
  round runs the peer and then ours, so drift cancels in the ratio (ours / llvmpipe, median over rounds).
- Homes with their own lights (as side_by_side.py --home-lights), observer camera: our Phong without
  shadows, culling off and on, against llvmpipe's N-light Phong without a shadow pass.
- The conference room, the peers' apartment (bird's-eye and interior) and the triangle soups 10^3..10^6:
  bench-render --obj, culling off and on, against llvmpipe gl-flat and Embree rt (a primary and a
  shadow ray per pixel) on the same OBJ and camera.
- A log-log plot of flat frame time against scene size at the highest thread count (the soups): ours on
  and off, llvmpipe, Embree (SVG beside the JSON).
The load average is recorded before and after each scene: on a shared machine the times are noisy;
the ratios, measured back to back, much less so. Standard library only.
"""
import argparse, glob, json, math, os, random, statistics, subprocess, sys, tempfile, time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.environ.get("ROOMRENDER_SHARED", os.path.join(os.path.dirname(ROOT), "shared"))  # read-only data
PEER = os.path.join(os.environ.get("PEERS_BUILD", "/work/peers/build"), "peer_render")
SCN = os.environ.get("PEERS_SCENES", "/work/peers/scenes")
SUN = "0.4,1,0.3"
OBJ_CAMS = {  # as ../shared/peers/tools/side_by_side.py
    "apartment_birdseye": ("apartment.obj", "--eye 2,13,11 --target 0,0,0.3 --up 0,1,0 --fovy 45 --near 0.1 --far 100 --light-dir 0.45,1,0.3"),
    "apartment_interior": ("apartment.obj", "--eye -0.6,1.6,-4.0 --target 1.0,1.0,4.0 --up 0,1,0 --fovy 60 --near 0.05 --far 50 --light-dir 0.45,1,0.3"),
    "conference": (os.path.join(SHARED, "data", "meshes", "conference", "conference.obj"),
                   "--eye 1400,400,300 --target -400,100,-500 --up 0,1,0 --fovy 60 --near 1 --far 5000 --light-dir 0.3,1,0.2"),
}
for n in ("1e3", "1e4", "1e5", "1e6"):
    OBJ_CAMS["soup_" + n] = ("grid_%s.obj" % n, "--eye 0,0,16 --target 0,0,0 --up 0,1,0 --fovy 45 --near 0.1 --far 100 --light-dir 0.4,1,0.6")


def load():
    return [round(x, 2) for x in os.getloadavg()]


def last_json(text):
    lines = [l for l in text.splitlines() if l.strip().startswith(("{", "["))]
    return json.loads(lines[-1]) if lines else None


def run(cmd, env=None, timeout=1800):
    p = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=timeout)
    j = last_json(p.stdout)
    if j is None:
        print("  failed: " + " ".join(cmd) + "\n  " + p.stderr.strip()[-400:], flush=True)
    return j


def peer(mode, obj, cam_flags, frames, threads, extra=()):
    env = dict(os.environ, MESA_SHADER_CACHE_DISABLE="true", LP_NUM_THREADS=str(threads))
    args = (["--rt-packet", "16"] if mode == "rt" else []) + list(extra)
    j = run([PEER, "--mode", mode, "--obj", obj] + args + cam_flags + ["--size", "1280x720", "--frames", str(frames)], env)
    return j["frame_ms_median"] if j else None


def write_lights(scene, path):
    """The scene's lights and ambient as a peer_render --lights file (our default ambient is 0.2)."""
    amb = scene.get("ambient", {})
    with open(path, "w") as f:
        f.write('{"ambient": %s, "lights": [\n%s\n]}\n' % (json.dumps(amb if "color" in amb else amb.get("intensity", 0.2)),
                                                           ",\n".join(" " + json.dumps(l) for l in scene.get("lights", []))))


def cam_flags(c, light=True):
    f = lambda v: ",".join("%.9g" % x for x in v)
    out = ["--eye", f(c["position"]), "--target", f(c["target"]), "--up", f(c.get("up", [0, 1, 0])),
           "--fovy", "%.9g" % c.get("fov_y", 60), "--near", "%.9g" % c.get("near", 0.1), "--far", "%.9g" % c.get("far", 100)]
    return out + (["--light-dir", SUN] if light else [])


def ours_bench(binary, src, cam, frames, threads, culling, extra=()):
    j = run([binary, "bench-render"] + src + cam + ["--size", "1280x720", "--frames", str(frames), "--threads", str(threads),
                                                    "--culling", culling] + list(extra))
    return j


def homes(a, rows):
    binary = os.path.join(a.build, "roomrender")
    bench = os.path.join(a.build, "bench", "bench_culling")
    work = tempfile.mkdtemp(prefix="culling-homes-")
    xmls = sorted(glob.glob(os.path.join(SHARED, "data", "floorplans", "sweethome3d", "*.xml")))
    if a.quick:
        xmls = xmls[:2]
    for xml in xmls:
        name = os.path.splitext(os.path.basename(xml))[0]
        req, obj = os.path.join(work, name + ".json"), os.path.join(work, name + ".obj")
        with open(req, "w") as f:
            subprocess.run([binary, "import", xml, "--furniture", "models"], stdout=f, stderr=subprocess.DEVNULL, check=True)
        subprocess.run([binary, "export", req, "--obj", obj], capture_output=True, check=True)
        for threads in a.threads:
            before = load()
            per_cam = {}
            for r in range(a.rounds):
                out = os.path.join(work, "%s.t%d.r%d.json" % (name, threads, r))
                # Ours first in round 0 to learn the cameras; later rounds alternate the order.
                ours = run([bench, "frames", "--request", req, "--inside", str(a.inside), "--threads", str(threads),
                            "--frames", str(a.frames), "--light-dir", SUN, "--seed", str(a.seed), "--out", out])
                if not ours:
                    break
                for k, cam in enumerate(ours):
                    p = peer("gl-flat", obj, cam_flags(cam["camera"]), a.frames, threads)
                    d = per_cam.setdefault(k, {"kind": cam["kind"], "camera": cam["camera"], "polygons": cam["polygons"],
                                               "peer": [], "on": [], "off": [], "counts_on": cam["on"], "counts_off": cam["off"]})
                    if p:
                        d["peer"].append(p)
                        d["on"].append(cam["on"]["frame_ms"])
                        d["off"].append(cam["off"]["frame_ms"])
            for k, d in sorted(per_cam.items()):
                if not d["peer"]:
                    continue
                ratios_on = [o / p for o, p in zip(d["on"], d["peer"])]
                ratios_off = [o / p for o, p in zip(d["off"], d["peer"])]
                row = {"scene": "sh3d_" + name, "group": "home", "mode": "flat", "camera_kind": d["kind"], "camera_index": k,
                       "camera": d["camera"], "threads": threads, "polygons": d["polygons"],
                       "peer_ms": statistics.median(d["peer"]), "on_ms": statistics.median(d["on"]),
                       "off_ms": statistics.median(d["off"]), "ratio_on": statistics.median(ratios_on),
                       "ratio_off": statistics.median(ratios_off),
                       "projected_on": d["counts_on"]["polygons_projected"], "projected_off": d["counts_off"]["polygons_projected"],
                       "objects_occluded": d["counts_on"]["objects_occluded"], "nodes_tested": d["counts_on"]["nodes_tested"],
                       "cull_ms": d["counts_on"]["cull_ms"], "load_before": before, "load_after": load()}
                rows.append(row)
            homes_rows = [r for r in rows if r["scene"] == "sh3d_" + name and r["threads"] == threads]
            if homes_rows:
                print("%-34s t%d flat: ratio on %.2f (off %.2f) median over %d cameras; projected %.1f %% of %d; load %s"
                      % (name, threads, statistics.median(r["ratio_on"] for r in homes_rows),
                         statistics.median(r["ratio_off"] for r in homes_rows), len(homes_rows),
                         100 * statistics.median(r["projected_on"] / r["polygons"] for r in homes_rows),
                         homes_rows[0]["polygons"], load()), flush=True)
        # With the home's own lights: our Phong (no shadows) against llvmpipe's N-light Phong, observer camera.
        lights = os.path.join(work, name + ".lights.json")
        scene = json.load(open(req))["scene"]
        write_lights(scene, lights)
        cam = cam_flags(json.load(open(req))["camera"], light=False)
        for threads in a.threads:
            before, pr, on, off = load(), [], [], []
            for r in range(a.rounds):
                p = peer("gl", obj, cam, a.frames, threads, ["--lights", lights, "--shadow-size", "0"])
                o1 = ours_bench(binary, ["--request", req], cam, a.frames, threads, "on", ["--shading", "phong", "--shadows", "false"])
                o0 = ours_bench(binary, ["--request", req], cam, a.frames, threads, "off", ["--shading", "phong", "--shadows", "false"])
                if p and o1 and o0:
                    pr.append(p), on.append(o1["frame_ms_median"]), off.append(o0["frame_ms_median"])
            if pr:
                rows.append({"scene": "sh3d_" + name, "group": "home", "mode": "lights", "camera_kind": "observer", "threads": threads,
                             "peer_ms": statistics.median(pr), "on_ms": statistics.median(on), "off_ms": statistics.median(off),
                             "ratio_on": statistics.median([o / p for o, p in zip(on, pr)]),
                             "ratio_off": statistics.median([o / p for o, p in zip(off, pr)]), "load_before": before, "load_after": load()})
                print("%-34s t%d lights (Phong, %d lights): on %.1f off %.1f llvmpipe %.1f ms" % (
                    name, threads, len(scene.get("lights", [])), rows[-1]["on_ms"], rows[-1]["off_ms"], rows[-1]["peer_ms"]), flush=True)


def objs(a, rows):
    binary = os.path.join(a.build, "roomrender")
    for name, (obj, cam) in OBJ_CAMS.items():
        path = obj if os.path.isabs(obj) else os.path.join(SCN, obj)
        if not os.path.exists(path) or (a.quick and name in ("soup_1e6", "conference")):
            continue
        frames = max(3, a.frames // 2) if name in ("soup_1e6", "conference") else a.frames
        flags = cam.split()
        for threads in a.threads:
            before = load()
            pr, er, on, off, counts = [], [], [], [], {}
            for r in range(a.rounds):
                p = peer("gl-flat", path, flags, frames, threads)
                e = peer("rt", path, flags, frames, threads)
                o1 = ours_bench(binary, ["--obj", path], flags, frames, threads, "on")
                o0 = ours_bench(binary, ["--obj", path], flags, frames, threads, "off")
                if p and o1 and o0:
                    pr.append(p), on.append(o1["frame_ms_median"]), off.append(o0["frame_ms_median"])
                    counts = {"on": o1["counts"], "off": o0["counts"], "cull_ms": o1["stage_ms_median"].get("cull")}
                if e:
                    er.append(e)
            if not pr:
                continue
            row = {"scene": name, "group": "soup" if name.startswith("soup") else "obj", "mode": "flat", "threads": threads,
                   "polygons": counts["on"]["polygons"], "peer_ms": statistics.median(pr),
                   "embree_ms": statistics.median(er) if er else None, "on_ms": statistics.median(on),
                   "off_ms": statistics.median(off), "ratio_on": statistics.median([o / p for o, p in zip(on, pr)]),
                   "ratio_off": statistics.median([o / p for o, p in zip(off, pr)]),
                   "projected_on": counts["on"]["polygons_projected"], "projected_off": counts["off"]["polygons_projected"],
                   "objects_occluded": counts["on"]["objects_occluded"], "nodes_tested": counts["on"]["nodes_tested"],
                   "cull_ms": counts["cull_ms"], "load_before": before, "load_after": load()}
            rows.append(row)
            print("%-34s t%d flat: on %.1f off %.1f llvmpipe %.1f embree %s ms, ratio on %.2f; projected %d of %d; load %s" % (
                name, threads, row["on_ms"], row["off_ms"], row["peer_ms"],
                "%.1f" % row["embree_ms"] if row["embree_ms"] else "-", row["ratio_on"], row["projected_on"], row["polygons"],
                load()), flush=True)


def plot(rows, path, threads):
    """Log-log SVG: flat frame ms against triangles for the soups."""
    pts = sorted((r for r in rows if r["group"] == "soup" and r["threads"] == threads), key=lambda r: r["polygons"])
    if len(pts) < 2:
        return
    series = [("ours, culling on", "on_ms", "#c0392b"), ("ours, culling off", "off_ms", "#e67e22"),
              ("llvmpipe", "peer_ms", "#2980b9"), ("Embree (primary + shadow ray)", "embree_ms", "#27ae60")]
    xs = [math.log10(r["polygons"]) for r in pts]
    ys = [math.log10(r[k]) for r in pts for _, k, _ in series if r.get(k)]
    x0, x1, y0, y1 = math.floor(min(xs)), math.ceil(max(xs)), math.floor(min(ys)), math.ceil(max(ys))
    W, H, L, B = 640, 420, 70, 50
    sx = lambda x: L + (x - x0) / (x1 - x0) * (W - L - 20)
    sy = lambda y: H - B - (y - y0) / (y1 - y0) * (H - B - 20)
    out = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" font-family="sans-serif" font-size="12">' % (W, H),
           '<rect width="100%" height="100%" fill="white"/>']
    for e in range(x0, x1 + 1):
        out.append('<line x1="%.1f" y1="%d" x2="%.1f" y2="%d" stroke="#ddd"/><text x="%.1f" y="%d" text-anchor="middle">1e%d</text>'
                   % (sx(e), 20, sx(e), H - B, sx(e), H - B + 16, e))
    for e in range(y0, y1 + 1):
        out.append('<line x1="%d" y1="%.1f" x2="%d" y2="%.1f" stroke="#ddd"/><text x="%d" y="%.1f" text-anchor="end">%g ms</text>'
                   % (L, sy(e), W - 20, sy(e), L - 6, sy(e) + 4, 10 ** e))
    out.append('<text x="%d" y="%d" text-anchor="middle">triangles (soups 10^3..10^6, 1280x720, flat, %d threads)</text>'
               % ((W + L) // 2, H - 12, threads))
    for i, (label, key, colour) in enumerate(series):
        p = [(sx(math.log10(r["polygons"])), sy(math.log10(r[key]))) for r in pts if r.get(key)]
        out.append('<polyline fill="none" stroke="%s" stroke-width="2" points="%s"/>' % (colour, " ".join("%.1f,%.1f" % q for q in p)))
        out += ['<circle cx="%.1f" cy="%.1f" r="3" fill="%s"/>' % (q[0], q[1], colour) for q in p]
        out.append('<text x="%d" y="%d" fill="%s">%s</text>' % (L + 10, 36 + 16 * i, colour, label))
    out.append("</svg>")
    open(path, "w").write("\n".join(out) + "\n")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--frames", type=int, default=7)
    ap.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--inside", type=int, default=10)
    ap.add_argument("--seed", type=int, default=2029)
    ap.add_argument("--quick", action="store_true", help="two homes, no 1e6 soup or conference room")
    ap.add_argument("--only", choices=["homes", "objs"])
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results", "culling.json"))
    a = ap.parse_args()
    if not os.path.exists(PEER):
        sys.exit("no peer harness at %s (see ../shared/peers/README.md)" % PEER)
    rows, start = [], time.time()
    result = {"load_before": load(), "rounds": a.rounds, "frames": a.frames, "threads": a.threads, "seed": a.seed,
              "inside_cameras": a.inside, "rows": rows}
    if a.only != "objs":
        homes(a, rows)
    if a.only != "homes":
        objs(a, rows)
    result["load_after"], result["seconds"] = load(), round(time.time() - start)
    json.dump(result, open(a.out, "w"), indent=1)
    plot(rows, os.path.splitext(a.out)[0] + "_scaling.svg", max(a.threads))
    print("wrote %s (%d rows, %d s, load %s -> %s)" % (a.out, len(rows), result["seconds"], result["load_before"], result["load_after"]))


if __name__ == "__main__":
    main()
