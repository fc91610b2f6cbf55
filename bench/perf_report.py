"""docs/performance.md and its SVG plots from the results bench/perf.py measured (standard library only).
Every number in the document comes from the results dict; targets are the ones issue 8 sets."""
import math
import os

EXPECTED_PIPELINES = ["zbuffer", "painter", "bsp"]
EXPECTED_SHADINGS = ["flat", "gouraud", "phong"]
PEER_COLOURS = {"llvmpipe Lambert": "#1f77b4", "llvmpipe Phong+shadow": "#d62728"}
OUR_COLOURS = ["#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf", "#bcbd22", "#7f7f7f"]
PEER_NAMES = {"lambert": "llvmpipe Lambert", "phong_shadow": "llvmpipe Phong+shadow"}


def fmt(ms):
    return "—" if ms is None else ("%.1f" % ms if ms >= 10 else "%.2f" % ms)


def target_for(entry, run):
    """The issue's target ratio against llvmpipe for this run, or None."""
    if run["pipeline"] != "zbuffer":
        return None
    if entry["kind"] == "room" and (run["shading"], run["shadows"]) in (("flat", False), ("phong", True)):
        return 0.5
    if entry["kind"] == "soup" and entry["triangles"] >= 100_000 and (run["shading"], run["shadows"]) in (
            ("flat", False), ("phong", True)):
        return 1.0
    return None


def ratio_rows(results):
    rows = []
    for e in results["scenes"]:
        for run in e["ours"]:
            peer = e["peer"].get(run["peer_mode"], {})
            ours_ms, peer_ms = run.get("frame_ms_median"), peer.get("frame_ms_median")
            ratio = ours_ms / peer_ms if ours_ms is not None and peer_ms else None
            target = target_for(e, run)
            if run.get("note"):
                verdict = run["note"]
            elif "error" in run:
                verdict = "failed: " + run["error"]
            elif target is None or ratio is None:
                verdict = ""
            else:
                verdict = "met (≤ %.1f×)" % target if ratio <= target else "**not met** (≤ %.1f×)" % target
            rows.append((e, run, peer_ms, ours_ms, ratio, verdict))
        for mode, peer in e["peer"].items():  # the peer's numbers stay on record when ours has no such mode
            if not any(r["peer_mode"] == mode for r in e["ours"]):
                stub = {"pipeline": "—", "shading": "(not in this build)", "shadows": False, "peer_mode": mode}
                rows.append((e, stub, peer.get("frame_ms_median"), None, None, peer.get("error", "")))
    return rows


def bsp_painter_rows(results):
    """Painter and BSP against our own z-buffer in the same mode: the issue asks within 1.5× on rooms."""
    rows = []
    for e in results["scenes"]:
        if e["kind"] != "room":
            continue
        zb = {(r["shading"], r["shadows"]): r.get("frame_ms_median") for r in e["ours"] if r["pipeline"] == "zbuffer"}
        for r in e["ours"]:
            base = zb.get((r["shading"], r["shadows"]))
            if r["pipeline"] != "zbuffer" and base and r.get("frame_ms_median") is not None:
                rows.append((e, r, r["frame_ms_median"] / base))
    return rows


def svg_plot(path, title, x_label, series, y_label="median frame time (ms)"):
    """A log-log line plot. series: [(name, [(x, y), ...])]; points with y None are skipped."""
    w, h, left, right, top, bottom = 760, 440, 70, 220, 40, 50
    pts = [(x, y) for _, s in series for x, y in s if y]
    if not pts:
        return False
    lx = (math.floor(math.log10(min(p[0] for p in pts))), math.ceil(math.log10(max(p[0] for p in pts))))
    ly = (math.floor(math.log10(min(p[1] for p in pts))), math.ceil(math.log10(max(p[1] for p in pts))))
    lx = (lx[0], max(lx[1], lx[0] + 1))
    ly = (ly[0], max(ly[1], ly[0] + 1))
    sx = lambda x: left + (math.log10(x) - lx[0]) / (lx[1] - lx[0]) * (w - left - right)
    sy = lambda y: h - bottom - (math.log10(y) - ly[0]) / (ly[1] - ly[0]) * (h - top - bottom)
    out = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" viewBox="0 0 %d %d" '
           'font-family="sans-serif" font-size="12">' % (w, h, w, h),
           '<rect width="100%" height="100%" fill="white"/>',
           '<text x="%d" y="22" font-size="15" font-weight="bold">%s</text>' % (left, title)]
    for d in range(lx[0], lx[1] + 1):
        x = sx(10 ** d)
        out.append('<line x1="%.1f" y1="%d" x2="%.1f" y2="%d" stroke="#ddd"/>' % (x, top, x, h - bottom))
        out.append('<text x="%.1f" y="%d" text-anchor="middle">10<tspan dy="-5" font-size="9">%d</tspan></text>'
                   % (x, h - bottom + 18, d))
    for d in range(ly[0], ly[1] + 1):
        y = sy(10 ** d)
        out.append('<line x1="%d" y1="%.1f" x2="%d" y2="%.1f" stroke="#ddd"/>' % (left, y, w - right, y))
        out.append('<text x="%d" y="%.1f" text-anchor="end">%g</text>' % (left - 6, y + 4, 10 ** d))
    out.append('<rect x="%d" y="%d" width="%d" height="%d" fill="none" stroke="#444"/>'
               % (left, top, w - left - right, h - top - bottom))
    out.append('<text x="%d" y="%d" text-anchor="middle">%s</text>' % ((left + w - right) / 2, h - 10, x_label))
    out.append('<text transform="translate(16 %d) rotate(-90)" text-anchor="middle">%s</text>'
               % ((top + h - bottom) / 2, y_label))
    ours = 0  # the same series has the same colour in every plot: peers fixed, ours in order
    for i, (name, s) in enumerate(series):
        colour = PEER_COLOURS.get(name) or OUR_COLOURS[ours % len(OUR_COLOURS)]
        ours += name not in PEER_COLOURS
        good = [(x, y) for x, y in s if y]
        if not good:
            continue
        out.append('<polyline fill="none" stroke="%s" stroke-width="2" points="%s"/>'
                   % (colour, " ".join("%.1f,%.1f" % (sx(x), sy(y)) for x, y in good)))
        out += ['<circle cx="%.1f" cy="%.1f" r="3.5" fill="%s"/>' % (sx(x), sy(y), colour) for x, y in good]
        ly_legend = top + 10 + 20 * i
        out.append('<line x1="%d" y1="%d" x2="%d" y2="%d" stroke="%s" stroke-width="2"/>'
                   % (w - right + 12, ly_legend, w - right + 32, ly_legend, colour))
        out.append('<text x="%d" y="%d">%s</text>' % (w - right + 38, ly_legend + 4, name))
    out.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")
    return True


def triangle_series(results):
    soups = sorted((e for e in results["scenes"] if e["kind"] == "soup"), key=lambda e: e["triangles"])
    series = {}
    for e in soups:
        for mode in ("lambert", "phong_shadow"):
            series.setdefault(PEER_NAMES[mode], []).append((e["triangles"], e["peer"][mode].get("frame_ms_median")))
        for r in e["ours"]:
            name = "%s %s%s" % (r["pipeline"], r["shading"], " +shadows" if r["shadows"] else "")
            series.setdefault(name, []).append((e["triangles"], r.get("frame_ms_median")))
    return sorted(series.items(), key=lambda kv: (not kv[0].startswith("llvmpipe"), kv[0]))


def write_report(results, doc_path):
    svg_dir = os.path.join(os.path.dirname(doc_path), "performance")
    os.makedirs(svg_dir, exist_ok=True)
    m, listing = results["machine"], results["listing"]
    L = ["# Performance: roomrender against Mesa's llvmpipe", "",
         "Generated by `bench/perf.sh` (do not edit by hand; the raw numbers are in "
         "`bench/results/performance.json`).", "",
         "- run: %s, commit `%s`" % (m["date"], m["commit"]),
         "- machine: %s, %s cores, Linux %s; load average %s at the start, %s at the end. The machine is shared, "
         "so absolute times drift between runs: compare the ratios, which were measured in one run, minutes apart."
         % (m["cpu"], m["cores"], m["kernel"], " ".join(m["loadavg_start"]), " ".join(m["loadavg_end"])),
         "- peer: %s through OSMesa (`bench/peer/osmesa_bench.cpp`), GL core profile, every frame cleared, drawn "
         "and read back into memory (`glReadPixels` + `glFinish`); its own thread pool." % m.get("peer_renderer"),
         "- ours: `roomrender bench-render --request` (`--obj` for the conference room): each frame is one "
         "`render_frame` call (colour and id buffers allocated and filled; no PNG encode, as the peer encodes none), "
         "the zbuffer drawing its 64×64 tiles on as many threads as cores. Parsing and tessellation are excluded "
         "(tessellation is reported as setup). Painter and BSP rebuild their order or tree every frame (no cache) "
         "and are measured only on scenes of up to 20,000 triangles.",
         "- both: the same triangles (the OBJ is the request's own tessellation), the same camera, 1280×720 unless "
         "stated, one untimed warm-up frame, then K timed frames (K = 20, 10 or 5 as the scene grows). Each scene "
         "is measured in %d interleaved rounds (peer, ours, peer, ours, …); a time is the median of the rounds' "
         "median frame times, min–max span every frame of every round." % results["scenes"][0].get("rounds", 1), ""]
    missing_p = [p for p in EXPECTED_PIPELINES if p not in listing["pipelines"]]
    missing_s = [s for s in EXPECTED_SHADINGS if s not in listing["shadings"]]
    L += ["This build has pipelines %s and shadings %s." % (", ".join("`%s`" % p for p in listing["pipelines"]),
                                                            ", ".join("`%s`" % s for s in listing["shadings"]))]
    if missing_p or missing_s:
        L += ["Not measured because this build does not have them (not faked): %s. Re-run `bench/perf.sh` after "
              "they are merged; the script iterates the build's own tables." %
              ", ".join(["pipeline `%s`" % p for p in missing_p] + ["shading `%s`" % s for s in missing_s] +
                        (["Phong + shadow maps"] if "phong" in missing_s else []))]
    L += ["", "## Same scene on both renderers", "",
          "Share of pixels where roomrender's id buffer and the peer's (polygon id = OBJ `f` line) name the same "
          "polygon, zbuffer + flat against depth + Lambert. It checks that both saw the same triangles from the "
          "same camera; the rest are depth ties resolved at different precision.", "",
          "| scene | camera | triangles | same id |", "|---|---|---:|---:|"]
    for e in results["scenes"]:
        a = e.get("id_agreement")
        L.append("| %s | %s | %s | %s |" % (e["scene"], e["camera"], f"{e['triangles']:,}",
                                            "—" if a is None else "%.3f %%" % (100 * a)))
    L += ["", "## Ratios to llvmpipe", "",
          "Median frame time, ours / llvmpipe (lower is better). Without shadows ours is compared with the peer's "
          "depth + Lambert (one directional light), Phong + shadows with the peer's Phong + 2048² shadow map "
          "(PCF 1). Targets (issue 8): `zbuffer` flat ≤ 0.5× on the room scenes, `zbuffer` Phong + shadows ≤ 0.5×, "
          "≤ 1.0× on the 10^5 and 10^6 soups.", "",
          "| scene | camera | triangles | ours: pipeline, shading | llvmpipe mode | llvmpipe ms | ours ms (min–max) "
          "| ratio | target |", "|---|---|---:|---|---|---:|---:|---:|---|"]
    for e, r, peer_ms, ours_ms, ratio, verdict in ratio_rows(results):
        mode = "%s, %s%s" % (r["pipeline"], r["shading"], " + shadows" if r["shadows"] else "")
        if r["pipeline"] == "—":
            mode = "none in this build"
        spread = "" if ours_ms is None else " (%s–%s)" % (fmt(r["frame_ms_min"]), fmt(r["frame_ms_max"]))
        L.append("| %s | %s | %s | %s | %s | %s | %s%s | %s | %s |" % (
            e["scene"], e["camera"], f"{e['triangles']:,}", mode, r["peer_mode"], fmt(peer_ms), fmt(ours_ms),
            spread, "—" if ratio is None else "%.2f×" % ratio, verdict))
    bp = bsp_painter_rows(results)
    if bp:
        L += ["", "Painter and BSP against our own z-buffer in the same mode (target: within 1.5× on the rooms):", "",
              "| scene | camera | pipeline | shading | ratio to zbuffer |", "|---|---|---|---|---:|"]
        L += ["| %s | %s | %s | %s%s | %.2f× |" % (e["scene"], e["camera"], r["pipeline"], r["shading"],
                                                  " + shadows" if r["shadows"] else "", q) for e, r, q in bp]
    if results.get("threads"):
        L += ["", "Thread scaling of our zbuffer (`bench-render --threads N`, same run; the image is byte-identical "
              "for any N). Other work on this shared 2-core machine limits what a second thread can win:", "",
              "| scene | camera | shading | 1 thread ms | 2 threads ms | speed-up |", "|---|---|---|---:|---:|---:|"]
        for t in results["threads"]:
            one, two = t["ms"].get("1"), t["ms"].get("2")
            L.append("| %s | %s | %s%s | %s | %s | %s |" % (t["scene"], t["camera"], t["shading"],
                     " + shadows" if t["shadows"] else "", fmt(one), fmt(two), "%.2f×" % (one / two) if one and two else "—"))
    L += ["", "## Where our time goes: per-stage medians (ms)", "",
          "Profiles (perf) of these frames, and what would close the gaps: "
          "[performance-profile.md](performance-profile.md).", "",
          "Stages are `render_frame`'s StageTimings (wall clock of each stage); setup is tessellation, once per run.",
          "Unstaged is what `render_frame` spends outside every stage (allocating and clearing the colour and id "
          "buffers; the zbuffer's depth and visibility buffers are reused across frames): each frame's total less its stages, then the median.",
          "", "| scene | camera | pipeline | shading | shadows | setup | shadow | build | sort | traverse | raster "
          "| shade | unstaged | frame |", "|---|---|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for e in results["scenes"]:
        for r in e["ours"]:
            st = r.get("stage_ms_median", {})
            stages = ("shadow", "build", "sort", "traverse", "raster", "shade")
            unstaged = st.get("other")
            L.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
                e["scene"], e["camera"], r["pipeline"], r["shading"], "yes" if r["shadows"] else "no",
                fmt(r.get("setup_ms")), *(fmt(st.get(k)) for k in stages), fmt(unstaged), fmt(st.get("total"))))
    L += ["", "## Scaling", ""]
    if svg_plot(os.path.join(svg_dir, "triangles.svg"), "Frame time against triangle count (random soups, 1280×720)",
                "triangles", triangle_series(results)):
        L += ["![frame time against triangle count](performance/triangles.svg)", "",
              "Random soups with the same total area at every size (about two layers of overdraw), so the slope "
              "is the cost per triangle.", ""]
    for p in results.get("pixels", []):
        name = "pixels_%s_%s.svg" % (p["scene"], p["camera"])
        series = [(PEER_NAMES["lambert"], [(q["pixels"], q["peer_ms"]) for q in p["points"]]),
                  ("zbuffer flat", [(q["pixels"], q["ours_ms"]) for q in p["points"]])]
        title = "Frame time against pixel count (%s, %s, %s triangles)" % (p["scene"], p["camera"], f"{p['triangles']:,}")
        if svg_plot(os.path.join(svg_dir, name), title, "pixels", series):
            L += ["![%s](performance/%s)" % (title, name), "",
                  "| size | llvmpipe ms | zbuffer flat ms | ratio |", "|---|---:|---:|---:|"]
            L += ["| %s | %s | %s | %s |" % (q["size"], fmt(q["peer_ms"]), fmt(q["ours_ms"]),
                                             "%.2f×" % (q["ours_ms"] / q["peer_ms"]) if q["ours_ms"] and q["peer_ms"] else "—")
                  for q in p["points"]]
            L.append("")
    L += ["## Scenes", "",
          "Made by `bench_gen_scenes` (bench/gen_scenes.cpp) as room-format requests; each OBJ is written from the "
          "request's own tessellation, so both renderers draw identical polygons, fanned into identical triangles.", "",
          "- `cylinders`: examples/four_cylinders.json, four open 60-quad tubes (480 triangles).",
          "- `apartment`: 12 m × 8 m, six rooms (living room, kitchen, bathroom, two bedrooms, study), nine walls with "
          "T joints, seven doors (with and without leaves), eleven translucent windows, a tiled floor and furniture; "
          "cameras `birds_eye` (above the south wall, looking down into every room) and `eye_level` (1.6 m, in the "
          "living room, looking through the kitchen doorway).",
          "- `soup_N`: N random triangles (seeded splitmix64) in a 10 m cube, edge length ∝ N^-1/2.", "",
          "The peer draws every triangle opaque and without back-face culling (an OBJ says neither which faces bound "
          "a closed solid nor which are translucent); roomrender skips the back faces of closed solids (walls, boxes) "
          "and blends the window panes.", "",
          "- `conference`: the conference room mesh of ../shared/data/meshes/conference (McGuire's archive; see "
          "../shared/SOURCES.md), read by both renderers from its OBJ (`bench-render --obj`), camera in a corner.",
          "- `sh3d_*`: Sweet Home 3D homes of ../shared/data/floorplans/sweethome3d, imported with `roomrender import` "
          "(camera: the file's observer camera) and exported with `roomrender export --obj` for the peer.",
          "" if not results.get("shared_note") else "Third-party scenes: " + results["shared_note"] + ".", ""]
    with open(doc_path, "w") as f:
        f.write("\n".join(L))
