#!/usr/bin/env python3
"""Edge error and frame time of anti-aliasing (docs/antialiasing.md): for each example scene in a
matched setup (ambient light only at intensity 1, no lights, flat shading, every pane opaque, so
each polygon has one flat colour), renders the 256-sample reference (the ground truth), then in
interleaved rounds our pipelines at S = 1/4/8/16 (`roomrender bench-render`) and llvmpipe at 1 and
4x MSAA (bench/peer/osmesa_bench --mode ambient), each with one thread. Edge error is
`roomrender compare TRUTH.png TEST.png --edges TRUTH.ids` (mean and p99 over the edge pixels).
Writes --out-json, --out-csv and the generated report --out-md. Python 3 standard library only;
bench/antialias.sh builds the tools and calls it.
"""
import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
import tempfile

SCENES = ["tetrahedron", "tri_intersecting", "cube_pyramid_cylinder", "cubes_45_pyramid_cylinder",
          "cylinders_8_16_32", "four_cylinders", "rows", "studio", "apartment"]
OURS = [("zbuffer", s) for s in (1, 4, 8, 16)] + [("bsp", s) for s in (1, 4, 8, 16)] + \
       [("painter", s) for s in (1, 4, 8, 16)]
PEER = [1, 4]
# The reference at S rays (ideal supersampling on the same patterns): the floor for S's edge error.
# Timed once, one frame: it is not a contender for speed.
REFERENCE = [4, 8, 16]


def log(message):
    print("antialias: " + message, file=sys.stderr, flush=True)


def run_json(cmd, env=None):
    done = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=600)
    if done.returncode != 0:
        raise RuntimeError(" ".join(cmd) + ": " + (done.stderr.strip() or done.stdout.strip()))
    return json.loads(done.stdout.strip().splitlines()[-1])


def matched_request(path, width, height):
    """The request with no lights, ambient intensity 1, flat shading, no shadows, opaque panes (and the
    painter's exact `newell` order, for when the painter pipeline draws it)."""
    with open(path) as f:
        request = json.load(f)

    def opaque(node):
        if isinstance(node, dict):
            for key, value in node.items():
                if key == "opacity":
                    node[key] = 1.0
                else:
                    opaque(value)
        elif isinstance(node, list):
            for value in node:
                opaque(value)

    scene = request["scene"]
    scene["lights"] = []
    scene.setdefault("ambient", {})["intensity"] = 1.0
    opaque(scene)
    request.setdefault("options", {}).update({"width": width, "height": height, "shading": "flat", "shadows": False,
                                              "painter": {"key": "newell"}})
    return request


class Bench:
    def __init__(self, args, work):
        self.args, self.work = args, work

    def ours(self, scene, pipeline, samples, out_png, frames=None):
        cmd = [self.args.roomrender, "bench-render", "--request", scene["request"], "--pipeline", pipeline,
               "--antialias", str(samples), "--threads", "1", "--frames", str(frames or self.args.frames),
               "--out", out_png]
        if pipeline == "bsp":
            cmd += ["--bsp-cache", "on"]
        return run_json(cmd)["frame_ms_median"]

    def peer(self, scene, samples, out_png):
        cam = scene["camera"]
        cmd = [self.args.peer, "--obj", scene["obj"], "--mode", "ambient", "--face-colors", scene["faces"],
               "--background", cam["background"], "--eye", cam["eye"], "--target", cam["target"], "--up", cam["up"],
               "--fovy", str(cam["fovy"]), "--near", str(cam["near"]), "--far", str(cam["far"]),
               "--size", cam["size"], "--samples", str(samples), "--frames", str(self.args.frames), "--out", out_png]
        env = dict(os.environ, LP_NUM_THREADS="1", MESA_SHADER_CACHE_DISABLE="true")
        result = run_json(cmd, env)
        return result["frame_ms_median"], result["renderer"]

    def edge(self, scene, png):
        line = run_json([self.args.roomrender, "compare", scene["truth_png"], png, "--edges", scene["truth_ids"]])
        return line["edge"]

    def prepare(self, name):
        d = os.path.join(self.work, name)
        os.makedirs(d)
        request = matched_request(os.path.join(self.args.source, "examples", name + ".json"), self.args.width,
                                  self.args.height)
        scene = {"name": name, "request": os.path.join(d, "request.json"), "obj": os.path.join(d, "scene.obj"),
                 "faces": os.path.join(d, "faces.txt"), "truth_png": os.path.join(d, "truth.png"),
                 "truth_ids": os.path.join(d, "truth.ids"), "dir": d}
        with open(scene["request"], "w") as f:
            json.dump(request, f)
        scene["camera"] = run_json([self.args.peer_scene, scene["request"], d])
        run_json([self.args.roomrender, "render", scene["request"], "--pipeline", "reference",
                          "--reference-samples", "256", "-o", scene["truth_png"], "--ids", scene["truth_ids"]])
        return scene

    def run_scene(self, name):
        scene = self.prepare(name)
        variants = [("roomrender", p, s) for p, s in OURS] + [("llvmpipe", "msaa", s) for s in PEER]
        times = {v: [] for v in variants}
        rows = []
        renderer = None
        for round_index in range(self.args.rounds):
            order = variants if round_index % 2 == 0 else list(reversed(variants))
            for who, pipeline, samples in order:
                png = os.path.join(scene["dir"], "%s-%s-%d.png" % (who, pipeline, samples))
                if who == "roomrender":
                    times[(who, pipeline, samples)].append(self.ours(scene, pipeline, samples, png))
                else:
                    ms, renderer = self.peer(scene, samples, png)
                    times[(who, pipeline, samples)].append(ms)
        for samples in REFERENCE:
            png = os.path.join(scene["dir"], "roomrender-reference-%d.png" % samples)
            times[("roomrender", "reference", samples)] = [self.ours(scene, "reference", samples, png, frames=1)]
            variants.append(("roomrender", "reference", samples))
        for who, pipeline, samples in variants:
            png = os.path.join(scene["dir"], "%s-%s-%d.png" % (who, pipeline, samples))
            edge = self.edge(scene, png)
            rows.append({"scene": name, "renderer": who, "pipeline": pipeline, "samples": samples,
                         "frame_ms_median": statistics.median(times[(who, pipeline, samples)]),
                         "frame_ms_rounds": times[(who, pipeline, samples)],
                         "edge_pixels": edge["pixels"], "edge_mean": edge["mean"], "edge_p99": edge["p99"]})
        return rows, renderer


def goals(rows):
    """Per scene: zbuffer S=4 against llvmpipe 4x MSAA (error below, time <= 1.0x), S=8 error <= half."""
    out = []
    for name in SCENES:
        by = {(r["renderer"], r["pipeline"], r["samples"]): r for r in rows if r["scene"] == name}
        peer = by.get(("llvmpipe", "msaa", 4))
        z4, z8 = by.get(("roomrender", "zbuffer", 4)), by.get(("roomrender", "zbuffer", 8))
        r4, r8 = by.get(("roomrender", "reference", 4)), by.get(("roomrender", "reference", 8))
        if not (peer and z4 and z8):
            continue
        out.append({"scene": name, "peer_edge_mean": peer["edge_mean"], "s4_edge_mean": z4["edge_mean"],
                    "reference4_edge_mean": r4["edge_mean"] if r4 else None,
                    "reference8_edge_mean": r8["edge_mean"] if r8 else None,
                    "s8_edge_mean": z8["edge_mean"], "s4_time_ratio": z4["frame_ms_median"] / peer["frame_ms_median"],
                    "s4_error_below": z4["edge_mean"] < peer["edge_mean"],
                    "s4_time_ok": z4["frame_ms_median"] <= peer["frame_ms_median"],
                    "s8_error_half": z8["edge_mean"] <= 0.5 * peer["edge_mean"]})
    return out


def markdown(report):
    lines = ["# Anti-aliasing benchmark (generated by bench/antialias.sh; do not edit)", "",
             "Matched setup (ambient only, one flat colour per face, opaque panes), %dx%d, one thread each, "
             "median of %d rounds of %d frames, interleaved. Edge error: mean / p99 colour error (8-bit units, mean "
             "of R, G, B) on the edge pixels of the 256-sample reference (docs/antialiasing.md). Peer: %s. Commit %s, "
             "load %s at start, %s at end." % (report["width"], report["height"], report["rounds"], report["frames"],
                                                report["peer_renderer"], report["commit"], report["load_start"],
                                                report["load_end"]), "",
             "| scene | renderer | pipeline | S | frame ms | edge mean | edge p99 |", "|---|---|---|---|---|---|---|"]
    for r in report["rows"]:
        lines.append("| %s | %s | %s | %d | %.2f | %.2f | %.1f |" % (r["scene"], r["renderer"], r["pipeline"], r["samples"],
                                                                    r["frame_ms_median"], r["edge_mean"], r["edge_p99"]))
    lines += ["", "Goals (zbuffer against llvmpipe 4x MSAA): S=4 edge error below, S=4 frame <= 1.0x, S=8 edge "
              "error <= half. The reference at 4 and 8 rays (ideal supersampling on the same patterns) is the floor "
              "for S's edge error.", "",
              "| scene | llvmpipe 4x mean | S=4 mean | S=8 mean | reference 4 / 8 mean | S=4 time ratio | S=4 below | "
              "S=4 time ok | S=8 half |", "|---|---|---|---|---|---|---|---|---|"]
    for g in report["goals"]:
        lines.append("| %s | %.2f | %.2f | %.2f | %.2f / %.2f | %.2f | %s | %s | %s |" % (
            g["scene"], g["peer_edge_mean"], g["s4_edge_mean"], g["s8_edge_mean"], g["reference4_edge_mean"] or 0.0,
            g["reference8_edge_mean"] or 0.0, g["s4_time_ratio"],
            "yes" if g["s4_error_below"] else "no", "yes" if g["s4_time_ok"] else "no",
            "yes" if g["s8_error_half"] else "no"))
    return "\n".join(lines) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--roomrender", required=True)
    parser.add_argument("--peer", required=True, help="osmesa_bench")
    parser.add_argument("--peer-scene", required=True, help="bench_antialias_peer_scene")
    parser.add_argument("--source", default=".")
    parser.add_argument("--scenes", nargs="*", default=SCENES)
    parser.add_argument("--width", type=int, default=320)
    parser.add_argument("--height", type=int, default=240)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--frames", type=int, default=5)
    parser.add_argument("--out-json", default="bench/results/antialias.json")
    parser.add_argument("--out-csv", default="bench/results/antialias.csv")
    parser.add_argument("--out-md", default="docs/antialiasing-bench.md")
    args = parser.parse_args()
    commit = subprocess.run(["git", "-C", args.source, "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True).stdout.strip()
    report = {"width": args.width, "height": args.height, "rounds": args.rounds, "frames": args.frames,
              "commit": commit, "load_start": "%.2f" % os.getloadavg()[0], "rows": [], "peer_renderer": None}
    with tempfile.TemporaryDirectory(prefix="rr-antialias-") as work:
        bench = Bench(args, work)
        for name in args.scenes:
            log(name)
            rows, renderer = bench.run_scene(name)
            report["rows"] += rows
            report["peer_renderer"] = renderer
    report["load_end"] = "%.2f" % os.getloadavg()[0]
    report["goals"] = goals(report["rows"])
    with open(args.out_json, "w") as f:
        json.dump(report, f, indent=1)
    with open(args.out_csv, "w", newline="") as f:
        fields = ["scene", "renderer", "pipeline", "samples", "frame_ms_median", "edge_pixels", "edge_mean", "edge_p99"]
        writer = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(report["rows"])
    with open(args.out_md, "w") as f:
        f.write(markdown(report))
    log("wrote %s, %s, %s" % (args.out_json, args.out_csv, args.out_md))


if __name__ == "__main__":
    main()
