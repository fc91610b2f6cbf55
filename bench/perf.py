#!/usr/bin/env python3
"""Runs roomrender's bench-render and the llvmpipe peer (bench/peer/osmesa_bench.cpp) on the scenes of
bench_gen_scenes' manifest, in one run on one machine, and writes the raw results
(bench/results/performance.json) and docs/performance.md with SVG scaling plots. Python 3 standard
library only. Called by bench/perf.sh, which builds the binaries and the scenes first.

Modes: every pipeline x shading that `roomrender bench-render --list` reports, without shadows, is
compared with the peer's depth + Lambert; every pipeline with Phong + shadows (when the build has
Phong) with the peer's Phong + 2048^2 shadow map. Modes the build lacks are listed, never faked.
"""
import argparse
import glob
import json
import os
import platform
import statistics
import subprocess
import sys
import time

import perf_report

PRIORITY_MAX_TRIANGLES = 20_000
SIZES = ["320x180", "640x360", "1280x720", "1920x1080", "2560x1440"]


def frames_for(triangles):
    """Fewer frames for the big soups: a 10^6 frame takes about half a second on either renderer."""
    return 20 if triangles <= 20_000 else 10 if triangles <= 200_000 else 5


def run_json(command, timeout):
    """Runs a command that prints one JSON line; returns (dict, None) or (None, reason)."""
    try:
        done = subprocess.run(command, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None, "timeout after %d s" % timeout
    if done.returncode != 0:
        return None, (done.stderr.strip() or "exit %d" % done.returncode)[:300]
    return json.loads(done.stdout.strip().splitlines()[-1]), None


def camera_flags(camera, light_dir, size):
    v = lambda xs: ",".join(repr(float(x)) for x in xs)
    return ["--eye", v(camera["eye"]), "--target", v(camera["target"]), "--up", v(camera["up"]),
            "--fovy", repr(camera["fovy"]), "--near", repr(camera["near"]), "--far", repr(camera["far"]),
            "--size", size, "--light-dir", v(light_dir)]


class Bench:
    def __init__(self, args):
        self.args = args
        self.out_dir = os.path.join(os.path.dirname(args.manifest), "out")
        os.makedirs(self.out_dir, exist_ok=True)

    def ours(self, scene, camera, size, pipeline, shading, shadows, frames, ids=None, threads=None):
        source = ["--obj", scene["obj"]] if scene.get("obj_input") else ["--request", scene["request"]]
        cmd = [self.args.roomrender, "bench-render", *source,
               *camera_flags(camera, scene["light_dir"], size), "--pipeline", pipeline, "--shading", shading,
               "--shadows", "true" if shadows else "false", "--frames", str(frames)]
        # The peer redraws its shadow map every frame; so do we here, for a like-for-like ratio (the
        # service's shadow cache would otherwise serve every timed frame from the warm-up's maps).
        if shadows:
            cmd += ["--shadow-cache", "off"]
        if ids:
            cmd += ["--ids", ids]
        if threads:
            cmd += ["--threads", str(threads)]
        return run_json(cmd, self.args.timeout)

    def peer(self, scene, camera, size, mode, frames, ids=None):
        cmd = [self.args.peer, "--obj", scene["obj"], *camera_flags(camera, scene["light_dir"], size),
               "--mode", mode, "--frames", str(frames)]
        if ids:
            cmd += ["--ids", ids]
        return run_json(cmd, self.args.timeout)


def id_agreement(path_a, path_b):
    """Share of pixels where both renderers show the same polygon id (both files: roomrender's format)."""
    with open(path_a, "rb") as fa, open(path_b, "rb") as fb:
        a, b = fa.read(), fb.read()
    if len(a) != len(b) or len(a) < 8:
        return None
    n = (len(a) - 8) // 4
    same = sum(1 for i in range(8, len(a), 4) if a[i:i + 4] == b[i:i + 4])
    return same / n


def combine_rounds(runs):
    """One result from the same measurement repeated in interleaved rounds: the median of the round
    medians (so a burst of load from other work on the machine moves it less), min of the minima,
    max of the maxima; the rest (counts, names) from the last round."""
    good = [r for r in runs if r is not None]
    if not good:
        return None
    out = dict(good[-1])
    out["rounds"] = [r["frame_ms_median"] for r in good]
    out["frame_ms_median"] = statistics.median(out["rounds"])
    out["frame_ms_min"] = min(r["frame_ms_min"] for r in good)
    out["frame_ms_max"] = max(r["frame_ms_max"] for r in good)
    if "stage_ms_median" in out:
        out["stage_ms_median"] = {k: statistics.median([r["stage_ms_median"][k] for r in good]) for k in out["stage_ms_median"]}
    return out


def our_modes(listing):
    """(pipeline, shading, shadows, peer mode) for every mode the build can be asked for."""
    modes = [(p, s, False, "lambert") for p in listing["pipelines"] for s in listing["shadings"]]
    if "phong" in listing["shadings"]:
        modes += [(p, "phong", True, "phong_shadow") for p in listing["pipelines"]]
    return modes


def measure_scene(bench, scene, camera, modes, rounds, log):
    """Peer and ours for every mode on one scene and camera at 1280x720: `rounds` interleaved rounds
    of (peer, then ours in every mode the peer mode stands for), combined by combine_rounds."""
    size, frames = "1280x720", frames_for(scene["triangles"])
    tag = "%s-%s" % (scene["name"], camera["name"])
    entry = {"scene": scene["name"], "camera": camera["name"], "kind": scene["kind"],
             "triangles": scene["triangles"], "polygons": scene["polygons"], "size": size,
             "frames": frames, "rounds": rounds, "peer": {}, "ours": []}
    for peer_mode in ("lambert", "phong_shadow"):
        # Painter and BSP redo their sort or tree every frame (bench-render runs without the cache), which
        # takes minutes on the big meshes: they are measured on scenes up to PRIORITY_MAX_TRIANGLES.
        mine = [m for m in modes if m[3] == peer_mode and (m[0] == "zbuffer" or scene["triangles"] <= PRIORITY_MAX_TRIANGLES)]
        peer_runs, our_runs, errors = [], {m: [] for m in mine}, {}
        for round_index in range(rounds):
            last = round_index + 1 == rounds  # id buffers are written once, in the last round
            peer_ids = os.path.join(bench.out_dir, tag + "-peer.ids") if peer_mode == "lambert" and last else None
            log("peer %s %s round %d" % (tag, peer_mode, round_index + 1))
            result, errors["peer"] = bench.peer(scene, camera, size, peer_mode, frames, peer_ids)
            peer_runs.append(result)
            for m in mine:
                pipeline, shading, shadows, _ = m
                ids = None
                if last and (pipeline, shading, shadows) == ("zbuffer", "flat", False):
                    ids = os.path.join(bench.out_dir, tag + "-ours.ids")
                log("ours %s %s %s shadows=%s round %d" % (tag, pipeline, shading, shadows, round_index + 1))
                result, errors[m] = bench.ours(scene, camera, size, pipeline, shading, shadows, frames, ids)
                our_runs[m].append(result)
                if ids and result and peer_ids and peer_runs[-1]:
                    entry["id_agreement"] = id_agreement(ids, peer_ids)
        entry["peer"][peer_mode] = combine_rounds(peer_runs) or {"error": errors["peer"]}
        for m in mine:
            pipeline, shading, shadows, _ = m
            run = {"pipeline": pipeline, "shading": shading, "shadows": shadows, "peer_mode": peer_mode}
            result = combine_rounds(our_runs[m])
            run.update(result or {"error": errors[m]})
            if shadows and result and result.get("shadow") != "rendered":
                run["note"] = "the shadow pass did not run on this build"
            entry["ours"].append(run)
    return entry


def measure_pixels(bench, scene, camera, rounds, log):
    """Frame time against pixel count: zbuffer flat and the peer's depth + Lambert at each size, in
    interleaved rounds like measure_scene."""
    points = []
    for size in SIZES:
        frames = frames_for(scene["triangles"])
        ours, peer = [], []
        for round_index in range(rounds):
            log("pixels %s-%s %s round %d" % (scene["name"], camera["name"], size, round_index + 1))
            ours.append(bench.ours(scene, camera, size, "zbuffer", "flat", False, frames)[0])
            peer.append(bench.peer(scene, camera, size, "lambert", frames)[0])
        ours, peer = combine_rounds(ours), combine_rounds(peer)
        w, h = (int(x) for x in size.split("x"))
        points.append({"size": size, "pixels": w * h,
                       "ours_ms": ours and ours["frame_ms_median"], "peer_ms": peer and peer["frame_ms_median"]})
    return {"scene": scene["name"], "camera": camera["name"], "triangles": scene["triangles"], "points": points}


def shared_scenes(bench, args, log):
    """The conference room (its OBJ, read by both renderers) and the Sweet Home 3D homes (imported with
    `roomrender import`, exported to OBJ for the peer), from ../shared; ([], note) when it is absent."""
    root = args.shared
    if not root or not os.path.isdir(root):
        return [], "skipped: the third-party data directory %s is absent" % (root or "(none given)")
    work = os.path.join(os.path.dirname(args.manifest), "shared")
    os.makedirs(work, exist_ok=True)
    scenes = []
    conference = os.path.join(root, "meshes", "conference", "conference.obj")
    if os.path.exists(conference):
        # Units are centimetres; the camera stands in a corner looking along the table.
        scenes.append({"name": "conference", "kind": "room", "obj": conference, "obj_input": True,
                       "light_dir": [0.3, 1.0, 0.2],
                       "cameras": [{"name": "corner", "eye": [1400, 400, 300], "target": [-400, 100, -500],
                                    "up": [0, 1, 0], "fovy": 60.0, "near": 1.0, "far": 5000.0}]})
    for xml in sorted(glob.glob(os.path.join(root, "floorplans", "sweethome3d", "*.xml")))[:args.homes]:
        name = "sh3d_" + os.path.splitext(os.path.basename(xml))[0]
        request, obj = os.path.join(work, name + ".json"), os.path.join(work, name + ".obj")
        log("import %s" % xml)
        with open(request, "w") as f:
            if subprocess.run([args.roomrender, "import", xml], stdout=f, stderr=subprocess.DEVNULL).returncode:
                log("import of %s failed; skipped" % xml)
                continue
        subprocess.run([args.roomrender, "export", request, "--obj", obj], check=True, capture_output=True)
        cam = json.load(open(request)).get("camera", {})
        scenes.append({"name": name, "kind": "room", "request": request, "obj": obj, "light_dir": [0.4, 1.0, 0.3],
                       "cameras": [{"name": "observer", "eye": cam.get("position", [0, 1.6, 0]),
                                    "target": cam.get("target", [1, 1.6, 0]), "up": [0, 1, 0],
                                    "fovy": float(cam.get("fov_y", 60.0)), "near": float(cam.get("near", 0.1)),
                                    "far": float(cam.get("far", 100.0))}]})
    for s in scenes:  # polygon and triangle counts from one small frame of ours
        probe, _ = bench.ours(s, s["cameras"][0], "64x36", "zbuffer", "flat", False, 1)
        s["polygons"], s["triangles"] = (probe["polygons"], probe["triangles"]) if probe else (0, 0)
    return scenes, None


def measure_threads(bench, scene, camera, modes, rounds, log):
    """Our zbuffer at 1 and 2 threads, interleaved rounds; the peer is not involved."""
    rows = []
    for pipeline, shading, shadows, _ in modes:
        if pipeline != "zbuffer" or (shading, shadows) not in (("flat", False), ("phong", True)):
            continue
        runs = {1: [], 2: []}
        for round_index in range(rounds):
            for threads in (1, 2):
                log("threads %s %s %s=%d round %d" % (scene["name"], camera["name"], shading, threads, round_index + 1))
                runs[threads].append(bench.ours(scene, camera, "1280x720", pipeline, shading, shadows,
                                                frames_for(scene["triangles"]), threads=threads)[0])
        rows.append({"scene": scene["name"], "camera": camera["name"], "shading": shading, "shadows": shadows,
                     "ms": {str(t): (combine_rounds(r) or {}).get("frame_ms_median") for t, r in runs.items()}})
    return rows


def machine_info(roomrender):
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    # Dirty means tracked sources differ from the commit; this script's own outputs do not count.
    dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no", "--", ".", ":!bench/results",
                            ":!docs/performance.md", ":!docs/performance"], capture_output=True, text=True).stdout.strip()
    return {"cpu": cpu, "cores": os.cpu_count(), "kernel": platform.release(), "commit": commit + ("+dirty" if dirty else ""),
            "date": time.strftime("%Y-%m-%d %H:%M:%S %Z"), "loadavg_start": open("/proc/loadavg").read().split()[:3]}


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--roomrender", required=True)
    ap.add_argument("--peer", required=True)
    ap.add_argument("--manifest", required=True)
    ap.add_argument("--results", default="bench/results/performance.json")
    ap.add_argument("--doc", default="docs/performance.md")
    ap.add_argument("--timeout", type=int, default=900, help="seconds per run")
    ap.add_argument("--pipelines", default="", help="comma-separated subset of the build's pipelines")
    ap.add_argument("--skip-pixels", action="store_true")
    ap.add_argument("--rounds", type=int, default=3, help="interleaved rounds of peer and ours per scene")
    ap.add_argument("--shared", default="", help="third-party data (../shared/data): conference room, Sweet Home 3D")
    ap.add_argument("--homes", type=int, default=9, help="how many Sweet Home 3D homes to measure")
    args = ap.parse_args()
    log = lambda message: print("perf: " + message, file=sys.stderr, flush=True)

    listing = json.loads(subprocess.run([args.roomrender, "bench-render", "--list"], capture_output=True,
                                        text=True, check=True).stdout)
    if args.pipelines:
        listing["pipelines"] = [p for p in listing["pipelines"] if p in args.pipelines.split(",")]
    manifest = json.load(open(args.manifest))
    bench = Bench(args)
    modes = our_modes(listing)
    results = {"machine": machine_info(args.roomrender), "listing": listing, "scenes": [], "pixels": []}
    extra, results["shared_note"] = shared_scenes(bench, args, log)
    for scene in manifest["scenes"] + extra:
        for camera in scene["cameras"]:
            results["scenes"].append(measure_scene(bench, scene, camera, modes, args.rounds, log))
    if not args.skip_pixels:
        by_name = {s["name"]: s for s in manifest["scenes"]}
        for name, camera_name in (("apartment", "eye_level"), ("soup_100000", "default")):
            if name in by_name:
                scene = by_name[name]
                camera = next(c for c in scene["cameras"] if c["name"] == camera_name)
                results["pixels"].append(measure_pixels(bench, scene, camera, args.rounds, log))
    by_name = {s["name"]: s for s in manifest["scenes"]}
    results["threads"] = []
    for name, camera_name in (("apartment", "eye_level"), ("apartment", "birds_eye")):
        if name in by_name:
            scene = by_name[name]
            camera = next(c for c in scene["cameras"] if c["name"] == camera_name)
            results["threads"] += measure_threads(bench, scene, camera, modes, args.rounds, log)
    results["machine"]["loadavg_end"] = open("/proc/loadavg").read().split()[:3]
    results["machine"]["peer_renderer"] = next(
        (s["peer"]["lambert"].get("renderer") for s in results["scenes"] if "renderer" in s["peer"]["lambert"]), None)
    os.makedirs(os.path.dirname(args.results), exist_ok=True)
    with open(args.results, "w") as f:
        json.dump(results, f, indent=1)
        f.write("\n")
    perf_report.write_report(results, args.doc)
    log("wrote %s and %s" % (args.results, args.doc))


if __name__ == "__main__":
    main()
