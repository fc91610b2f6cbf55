#!/usr/bin/env python3
"""Textured frames side by side with llvmpipe: the accuracy suite's textured scenes (suite.cpp,
add_textured), unlit (ambient 1, no lights: a pixel is material colour x filtered texel), drawn by
`roomrender bench-render` (zbuffer, Phong, no shadows) and by bench/peer/osmesa_bench (--mode
textured) from the same polygons, texture coordinates, mip chains and camera, with trilinear and
anisotropic filtering. Rounds interleave one peer run and one of ours (the order alternating by
round) so machine drift cancels; each run reports its median frame. Both images are scored by
`roomrender compare` against the reference pipeline's render of the same request: the texture PSNR
over the reference's textured pixels away from edges where the test drew the same polygon.

  bench/textured_peer.py [--build build] [--roomrender BINARY] [--rounds 5] [--frames 10] [--threads N]
                         [--out bench/results/textured_peer.json]

Needs a build with -DROOMRENDER_PEER_BENCH=ON (osmesa_bench, bench_textured_peer_scene, roomrender).
Prints a Markdown table (docs/benchmarks.md, "Textured frames against llvmpipe")."""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

FILTERS = ["trilinear", "anisotropic"]


def run_json(cmd, stream="stdout"):
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"failed: {' '.join(cmd)}\n{done.stderr}")
    text = done.stdout if stream == "stdout" else done.stderr
    return [json.loads(line) for line in text.splitlines() if line.startswith("{")]


def texture_psnr(roomrender, scene_dir, test_png, test_ids):
    line = run_json([roomrender, "compare", f"{scene_dir}/reference.png", test_png, "--edges",
                     f"{scene_dir}/reference.ids", "--request", f"{scene_dir}/request.json",
                     "--test-ids", test_ids])[-1]
    return line["texture"]


def nearest_check(roomrender, peer, scene):
    """Both renderers with nearest filtering, once, compared with each other on the textured pixels
    away from edges: 0, or nearly (a point on a texel boundary may round to either side in GL's
    float interpolation), when the texture coordinates, v's direction and the texel centres match."""
    d = scene["dir"]
    subprocess.run([peer, "--obj", f"{d}/scene.obj", "--mode", "textured", "--textures", "nearest",
                    *scene["peer_flags"], "--frames", "1", "--out", f"{d}/peer.nearest.png", "--ids",
                    f"{d}/peer.nearest.ids"], check=True, capture_output=True)
    subprocess.run([roomrender, "bench-render", "--request", f"{d}/request.json", "--shading", "phong", "--shadows",
                    "false", "--texture-filter", "nearest", "--frames", "1", "--out", f"{d}/ours.nearest.png",
                    "--ids", f"{d}/ours.nearest.ids"], check=True, capture_output=True)
    return run_json([roomrender, "compare", f"{d}/ours.nearest.png", f"{d}/peer.nearest.png", "--edges",
                     f"{d}/ours.nearest.ids", "--request", f"{d}/request.json", "--test-ids",
                     f"{d}/peer.nearest.ids"])[-1]["texture"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default="build")
    ap.add_argument("--roomrender", default=None, help="our binary (default: BUILD/roomrender)")
    ap.add_argument("--shared", default="../shared/data")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--frames", type=int, default=10)
    ap.add_argument("--warmup", type=int, default=2)
    ap.add_argument("--threads", type=int, default=0,
                    help="threads of both renderers (LP_NUM_THREADS for llvmpipe); 0: each one's default")
    ap.add_argument("--only", default="textured_")
    ap.add_argument("--work", default=None, help="directory for scenes and images (default: a new temporary one)")
    ap.add_argument("--out", default="bench/results/textured_peer.json")
    a = ap.parse_args()
    roomrender = a.roomrender or f"{a.build}/roomrender"
    peer = f"{a.build}/bench/osmesa_bench"
    work = a.work or tempfile.mkdtemp(prefix="textured_peer.")
    if a.threads:
        os.environ["LP_NUM_THREADS"] = str(a.threads)
    scenes = run_json([f"{a.build}/bench/bench_textured_peer_scene", "--outdir", work, "--shared", a.shared,
                       "--only", a.only])
    rows, checks = [], {}
    for scene in scenes:
        d = scene["dir"]
        checks[scene["scene"]] = nearest_check(roomrender, peer, scene)
        print(f"{scene['scene']:26} nearest, ours against llvmpipe: {checks[scene['scene']]}", file=sys.stderr)
        subprocess.run([roomrender, "render", f"{d}/request.json", "--pipeline", "reference", "-o",
                        f"{d}/reference.png", "--ids", f"{d}/reference.ids"], check=True, capture_output=True)
        for texture_filter in FILTERS:
            ours_png, peer_png = f"{d}/ours.{texture_filter}.png", f"{d}/peer.{texture_filter}.png"
            ours_cmd = [roomrender, "bench-render", "--request", f"{d}/request.json", "--pipeline", "zbuffer",
                        "--shading", "phong", "--shadows", "false", "--texture-filter", texture_filter,
                        "--frames", str(a.frames), "--warmup", str(a.warmup), "--out", ours_png, "--ids",
                        f"{d}/ours.{texture_filter}.ids"] + (["--threads", str(a.threads)] if a.threads else [])
            peer_cmd = [peer, "--obj", f"{d}/scene.obj", "--mode", "textured", "--textures", texture_filter,
                        *scene["peer_flags"], "--frames", str(a.frames), "--warmup", str(a.warmup),
                        "--out", peer_png, "--ids", f"{d}/peer.{texture_filter}.ids"]
            ours_ms, peer_ms, peer_line, ours_line = [], [], None, None
            for r in range(a.rounds):
                for side in (["peer", "ours"] if r % 2 == 0 else ["ours", "peer"]):
                    if side == "peer":
                        peer_line = run_json(peer_cmd)[-1]
                        peer_ms.append(peer_line["frame_ms_median"])
                    else:
                        ours_line = run_json(ours_cmd)[-1]
                        ours_ms.append(ours_line["frame_ms_median"])
            ours_tex = texture_psnr(roomrender, d, ours_png, f"{d}/ours.{texture_filter}.ids")
            peer_tex = texture_psnr(roomrender, d, peer_png, f"{d}/peer.{texture_filter}.ids")
            row = {"scene": scene["scene"], "filter": texture_filter, "faces": scene["faces"],
                   "ours_ms": statistics.median(ours_ms), "peer_ms": statistics.median(peer_ms),
                   "ours_ms_rounds": ours_ms, "peer_ms_rounds": peer_ms,
                   "ours_texture": ours_tex, "peer_texture": peer_tex,
                   "peer": {k: peer_line[k] for k in ("renderer", "gl_version", "lp_num_threads", "max_anisotropy",
                                                     "generated_mip_chains", "triangles")},
                   "ours": {k: ours_line[k] for k in ("threads", "simd", "triangles")}}
            row["ratio"] = row["ours_ms"] / row["peer_ms"]
            rows.append(row)
            print(f"{row['scene']:26} {texture_filter:11} ours {row['ours_ms']:8.2f} ms  peer {row['peer_ms']:8.2f} ms"
                  f"  ratio {row['ratio']:.2f}  psnr ours {ours_tex['psnr_db']:.2f} peer {peer_tex['psnr_db']:.2f}",
                  file=sys.stderr)
    os.makedirs(os.path.dirname(a.out) or ".", exist_ok=True)
    with open(a.out, "w") as f:
        json.dump({"rounds": a.rounds, "frames": a.frames, "warmup": a.warmup, "threads": a.threads, "work": work,
                   "nearest_ours_against_peer": checks, "rows": rows}, f, indent=1)
        f.write("\n")
    print("| scene | filter | ours ms | llvmpipe ms | ours / llvmpipe | texture PSNR ours | texture PSNR llvmpipe | pixels scored ours / llvmpipe |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| `{r['scene']}` | {r['filter']} | {r['ours_ms']:.1f} | {r['peer_ms']:.1f} | {r['ratio']:.2f} | "
              f"{r['ours_texture']['psnr_db']:.2f} dB | {r['peer_texture']['psnr_db']:.2f} dB | "
              f"{r['ours_texture']['pixels']:,} / {r['peer_texture']['pixels']:,} |")
    print(f"\nwrote {a.out}; images in {work}", file=sys.stderr)


if __name__ == "__main__":
    main()
