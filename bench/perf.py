#!/usr/bin/env python3
"""Times `roomrender bench-render` against the peers of ../shared/peers (Mesa's llvmpipe and Embree 3,
`peer_render`) on side_by_side.py's OBJ scenes and cameras plus the Sweet Home 3D homes, at 1 and 2
threads, in interleaved rounds of one run; writes the raw results (JSON) and the report (perf_report.py).
Python 3 standard library only. Called by bench/perf.sh, which builds the peers and the scenes first.

Scenes and cameras come from side_by_side.py itself (the homes are imported as it does, with their
furniture models), so this harness and the targets'
yardstick cannot drift apart. Every round runs every variant once per thread count, thread counts in
alternating order, so slow drift of the machine's load cancels in the per-round ratios.
"""
import argparse
import glob
import importlib.util
import json
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import perf_report

# name -> (renderer, what it runs). Ours always draw with the zbuffer pipeline, as the performance targets do,
# and with occlusion culling off: the targets time the hot loops, not what culling skips. One variant with
# culling on shows what a user gets beside it.
VARIANTS = {
    "llvmpipe_flat": ("peer", ["--mode", "gl-flat"]),
    "llvmpipe_phong_shadow": ("peer", ["--mode", "gl"]),
    "embree": ("peer", ["--mode", "rt", "--rt-packet", "16"]),
    "flat": ("ours", ["--pipeline", "zbuffer", "--shading", "flat", "--shadows", "false", "--culling", "off"]),
    "gouraud": ("ours", ["--pipeline", "zbuffer", "--shading", "gouraud", "--shadows", "false", "--culling", "off"]),
    "phong": ("ours", ["--pipeline", "zbuffer", "--shading", "phong", "--shadows", "false", "--culling", "off"]),
    # The peer redraws its shadow map every frame; so do we (the cache would serve the warm-up's maps).
    "phong_shadow": ("ours", ["--pipeline", "zbuffer", "--shading", "phong", "--shadows", "true",
                              "--shadow-cache", "off", "--culling", "off"]),
    "flat_culled": ("ours", ["--pipeline", "zbuffer", "--shading", "flat", "--shadows", "false", "--culling", "on"]),
}
# Quick mode: one object, one generated room, one imported home (the three code paths of the scene list).
QUICK_SCENES = ["cylinders", "apartment_interior", "sh3d_Studio"]
# Painter and BSP against zbuffer on the example apartment from eye level (the BSP tree cached, as a
# warm server has it); the camera stands in the living room at 1.6 m.
PRIORITY_REQUEST = "examples/apartment.json"
PRIORITY_CAMERA = ["--eye", "2.5,1.6,1.5", "--target", "6.5,1.3,5.5", "--up", "0,1,0", "--fovy", "60",
                   "--near", "0.05", "--far", "50", "--light-dir", "0.45,1,0.3"]
PRIORITY_VARIANTS = {"zbuffer": ["--pipeline", "zbuffer"], "painter": ["--pipeline", "painter"],
                     "bsp": ["--pipeline", "bsp", "--bsp-cache", "on"]}


def log(message):
    print("perf: " + message, file=sys.stderr, flush=True)


def load_side_by_side(peers_dir, peers_build, scenes_dir):
    """side_by_side.py as a module; it reads PEERS_BUILD and PEERS_SCENES when imported."""
    os.environ["PEERS_BUILD"], os.environ["PEERS_SCENES"] = peers_build, scenes_dir
    path = os.path.join(peers_dir, "tools", "side_by_side.py")
    spec = importlib.util.spec_from_file_location("side_by_side", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def scene_kind(name):
    if name.startswith("soup"):
        return "soup"
    return "object" if name == "cylinders" else "room"


def run_json(command, timeout, env=None):
    """Runs a command that prints one JSON line; returns (dict, None) or (None, reason)."""
    try:
        done = subprocess.run(command, capture_output=True, text=True, timeout=timeout, env=env)
    except subprocess.TimeoutExpired:
        return None, "timeout after %d s" % timeout
    lines = [l for l in done.stdout.splitlines() if l.strip().startswith("{")]
    if done.returncode != 0 or not lines:
        return None, (done.stderr.strip() or "exit %d" % done.returncode)[-300:]
    return json.loads(lines[-1]), None


class Runner:
    def __init__(self, args, sbs):
        self.args, self.sbs = args, sbs
        self.load_samples = []

    def command(self, variant, obj, camera, threads, frames, size):
        who, flags = VARIANTS[variant]
        env = dict(os.environ, MESA_SHADER_CACHE_DISABLE="true")
        if who == "peer":
            env["LP_NUM_THREADS"] = str(threads)
            cmd = [self.sbs.PEER, *flags, "--obj", obj, *camera, "--threads", str(threads)]
        else:
            cmd = [self.args.roomrender, "bench-render", "--obj", obj, *camera, *flags, "--threads", str(threads)]
        return cmd + ["--size", size, "--frames", str(frames)], env

    def run(self, variant, obj, camera, threads, frames, size):
        cmd, env = self.command(variant, obj, camera, threads, frames, size)
        load = os.getloadavg()[0]
        self.load_samples.append(load)
        result, error = run_json(cmd, self.args.timeout, env)
        if result is None:
            return {"error": error, "load1": load}
        out = {"ms": result["frame_ms_median"], "min_ms": result["frame_ms_min"],
               "max_ms": result["frame_ms_max"], "load1": load, "triangles": result.get("triangles")}
        for key in ("renderer", "api_version", "frames_other_cpu_ms", "frames_wall_ms", "shadow", "polygons", "simd"):
            if key in result:
                out[key] = result[key]
        if variant == "phong_shadow" and result.get("shadow") != "rendered":
            out["note"] = "the shadow pass did not run"
        return out


def same_scene_check(runner, name, obj, camera, size, work):
    """Id agreement of our zbuffer flat frame and llvmpipe's (OBJ face ids), by the peers' idcompare: it
    shows both renderers drew the same triangles from the same camera."""
    peer_prefix, ours_ids = os.path.join(work, name + "-peer"), os.path.join(work, name + "-ours.ids")
    peer_cmd = [runner.sbs.PEER, "--mode", "id", "--face-ids", "--obj", obj, *camera, "--size", size,
                "--frames", "1", "--out", peer_prefix]
    ours_cmd, _ = runner.command("flat", obj, camera, 2, 1, size)
    for cmd in (peer_cmd, ours_cmd + ["--ids", ours_ids]):
        if run_json(cmd, runner.args.timeout)[0] is None:
            return {"error": "id render failed: " + " ".join(cmd[:2])}
    idcompare = os.path.join(os.path.dirname(runner.sbs.PEER), "idcompare")
    result, error = run_json([idcompare, peer_prefix + ".ids", ours_ids], runner.args.timeout)
    return result or {"error": error}


def add_homes(sbs, binary, homes_dir):
    """The nine Sweet Home 3D homes as side_by_side.add_homes makes them (imported by roomrender,
    exported to OBJ with polygon k = face k, each home's observer camera), but with the furniture's
    own models (`--furniture models`) instead of boxes: the homes as people see them."""
    work = tempfile.mkdtemp(prefix="perf-homes-")
    for xml in sorted(glob.glob(os.path.join(homes_dir, "*.xml"))):
        name = "sh3d_" + os.path.splitext(os.path.basename(xml))[0]
        req, obj = os.path.join(work, name + ".json"), os.path.join(work, name + ".obj")
        with open(req, "w") as f:
            if subprocess.run([binary, "import", xml, "--furniture", "models"], stdout=f,
                              stderr=subprocess.DEVNULL).returncode:
                continue
        if subprocess.run([binary, "export", req, "--obj", obj], capture_output=True).returncode:
            continue
        c = json.load(open(req)).get("camera", {})
        j = lambda v: ",".join("%g" % x for x in v)
        sbs.CAM[name] = "--eye %s --target %s --up %s --fovy %g --near %g --far %g --light-dir 0.4,1,0.3" % (
            j(c["position"]), j(c["target"]), j(c.get("up", [0, 1, 0])), c.get("fov_y", 60), c.get("near", 0.1),
            c.get("far", 100))
        sbs.SCENES.append((name, obj, name))


def measure_scene(runner, name, obj, camera, rounds, threads, frames, size, variants):
    """`rounds` interleaved rounds; in each, every thread count (alternating which goes first) runs
    every variant once. runs[variant][threads] is the per-round list (None where a run failed)."""
    runs = {v: {str(t): [] for t in threads} for v in variants}
    for r in range(rounds):
        for t in (threads if r % 2 == 0 else threads[::-1]):
            for v in variants:
                log("%s round %d/%d threads %d %s" % (name, r + 1, rounds, t, v))
                runs[v][str(t)].append(runner.run(v, obj, camera, t, frames, size))
    return runs


def measure_priority(runner, rounds, frames, size):
    """zbuffer, painter and bsp (warm tree) on the example apartment at the default thread count."""
    out = {name: [] for name in PRIORITY_VARIANTS}
    for r in range(rounds):
        for name, flags in PRIORITY_VARIANTS.items():
            log("priority round %d/%d %s" % (r + 1, rounds, name))
            cmd = [runner.args.roomrender, "bench-render", "--request", PRIORITY_REQUEST, *PRIORITY_CAMERA, *flags,
                   "--shading", "flat", "--shadows", "false", "--size", size, "--frames", str(frames)]
            result, error = run_json(cmd, runner.args.timeout)
            out[name].append({"ms": result["frame_ms_median"]} if result else {"error": error})
    return {"request": PRIORITY_REQUEST, "camera": " ".join(PRIORITY_CAMERA), "shading": "flat", "runs": out}


def machine_info(roomrender):
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
    git = lambda *a: subprocess.run(["git", *a], capture_output=True, text=True).stdout.strip()
    # Dirty means tracked sources differ from the commit; this script's own outputs do not count.
    dirty = git("status", "--porcelain", "--untracked-files=no", "--", ".", ":!bench/results", ":!docs/performance.md",
                ":!docs/performance")
    return {"cpu": cpu, "cores": os.cpu_count(), "kernel": platform.release(),
            "commit": git("rev-parse", "--short", "HEAD") + ("+dirty" if dirty else ""),
            "roomrender": os.path.abspath(roomrender),
            "roomrender_version": subprocess.run([roomrender, "--version"], capture_output=True,
                                                 text=True).stdout.strip(),
            "date": time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime())}


def write_results(results, args, runner):
    results["load"]["end"] = list(os.getloadavg())
    results["load"]["samples_1min"] = runner.load_samples
    results["results_path"] = os.path.relpath(args.results)
    os.makedirs(os.path.dirname(os.path.abspath(args.results)), exist_ok=True)
    with open(args.results, "w") as f:
        json.dump(results, f, indent=1)
        f.write("\n")
    perf_report.write_report(results, args.doc)


def select_scenes(sbs, args):
    """The wanted scenes whose OBJ exists, and the names of the wanted ones that do not."""
    wanted = args.scenes.split(",") if args.scenes else (QUICK_SCENES if args.quick else None)
    scenes = [(n, o, c) for n, o, c in sbs.SCENES if not wanted or n in wanted]
    return [s for s in scenes if os.path.exists(s[1])], [s[0] for s in scenes if not os.path.exists(s[1])]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--roomrender", required=True)
    ap.add_argument("--peers", required=True, help="the peers' source (../shared/peers; read-only)")
    ap.add_argument("--peers-build", required=True, help="where peer_render and idcompare were built")
    ap.add_argument("--scenes-dir", required=True, help="where scenes/gen_obj.py wrote the OBJ scenes")
    ap.add_argument("--results", default="bench/results/performance.json")
    ap.add_argument("--doc", default="docs/performance.md")
    ap.add_argument("--quick", action="store_true", help="smoke run: 3 small scenes, 1 round, 5 frames, 640x360")
    ap.add_argument("--rounds", type=int, help="interleaved rounds (default 3; 1 with --quick)")
    ap.add_argument("--frames", type=int, help="timed frames per run (default 15; 5 with --quick)")
    ap.add_argument("--size", help="WxH (default 1280x720; 640x360 with --quick)")
    ap.add_argument("--threads", default="1,2", help="thread counts, comma-separated")
    ap.add_argument("--scenes", default="", help="comma-separated scene names (default: all; 3 with --quick)")
    ap.add_argument("--no-homes", action="store_true", help="skip the Sweet Home 3D homes")
    ap.add_argument("--timeout", type=int, default=900, help="seconds per run")
    args = ap.parse_args()
    rounds = args.rounds or (1 if args.quick else 3)
    frames = args.frames or (5 if args.quick else 15)
    size = args.size or ("640x360" if args.quick else "1280x720")
    threads = [int(t) for t in args.threads.split(",")]

    sbs = load_side_by_side(args.peers, args.peers_build, args.scenes_dir)
    homes_dir = os.path.join(os.path.dirname(sbs.DATA), "floorplans", "sweethome3d")
    homes_wanted = not args.no_homes
    before = len(sbs.SCENES)
    if homes_wanted:  # imports with this roomrender, furniture models included, exports OBJ
        add_homes(sbs, args.roomrender, homes_dir)
    home_scenes = sbs.SCENES[before:]
    scenes, missing = select_scenes(sbs, args)
    results = {"format": 2, "quick": args.quick, "machine": machine_info(args.roomrender),
               "settings": {"size": size, "rounds": rounds, "frames": frames, "threads": threads,
                            "variants": {v: " ".join(f) for v, (_, f) in VARIANTS.items()}},
               "load": {"start": list(os.getloadavg())}, "scenes": [], "missing": missing}
    if homes_wanted:
        imported = {n for n, _, _ in home_scenes}
        all_homes = sorted("sh3d_" + os.path.splitext(f)[0] for f in os.listdir(homes_dir) if f.endswith(".xml")) \
            if os.path.isdir(homes_dir) else []
        results["missing"] += [h + " (import or export failed)" for h in all_homes
                               if h not in imported and (not args.quick or h in QUICK_SCENES)]
        if not all_homes:
            results["missing"].append("Sweet Home 3D homes (%s absent)" % homes_dir)
    runner = Runner(args, sbs)
    work = tempfile.mkdtemp(prefix="roomrender-perf-")
    try:
        for name, obj, cam in scenes:
            camera = sbs.CAM[cam].split()
            # side_by_side's frame counts: a third for the 10^6 soup and the 331k-triangle conference room.
            n = frames if "1e6" not in name and name != "conference" else max(3, frames // 3)
            entry = {"name": name, "kind": scene_kind(name), "obj": obj, "camera": sbs.CAM[cam], "frames": n,
                     "same_scene": same_scene_check(runner, name, obj, camera, size, work)}
            entry["runs"] = measure_scene(runner, name, obj, camera, rounds, threads, n, size, list(VARIANTS))
            entry["triangles"] = next((r.get("triangles") for r in entry["runs"]["flat"][str(threads[-1])]
                                       if r.get("triangles")), None)
            results["scenes"].append(entry)
            # A long run that is stopped still leaves every finished scene on record.
            results["partial"] = "%d of %d scenes done, interrupted or still running" % (len(results["scenes"]),
                                                                                          len(scenes))
            write_results(results, args, runner)
        if not args.quick and os.path.exists(PRIORITY_REQUEST):
            results["priority"] = measure_priority(runner, rounds, frames, size)
    finally:
        shutil.rmtree(work, ignore_errors=True)
        for _, obj, _ in home_scenes:  # add_homes wrote them into a temp dir of its own
            shutil.rmtree(os.path.dirname(obj), ignore_errors=True)
    results.pop("partial", None)
    write_results(results, args, runner)
    print(perf_report.ratio_table_text(results))
    log("wrote %s and %s" % (args.results, args.doc))


if __name__ == "__main__":
    main()
