"""Run time against error: bench/results/accuracy.{json -> csv}, the Markdown sections of
docs/accuracy.md ("Run time against error" and the texture table) and its SVG plots
(docs/accuracy/*.svg), from what bench_accuracy measured. Each section is rewritten only when the run
holds scenes of its classes, so a run of the textured class alone leaves the other section as it was.
Standard library only. Every number written comes from the JSON; nothing is typed in here.
  python3 bench/accuracy_report.py RESULTS.json --csv OUT.csv --doc docs/accuracy.md --svg-dir docs/accuracy"""
import argparse
import csv
import math
import os
import re

CLASSES = [("classic", "Classic test scenes (intersecting and overlapping solids, triangle soup)"),
           ("rooms", "Rooms (examples and the generated apartment)"),
           ("sh3d", "Sweet Home 3D example homes"),
           ("r2v", "R2V apartment plans"),
           ("interiors", "Real interiors (OBJ meshes)")]
COLOURS = {"zbuffer": "#1f77b4", "painter": "#d62728", "bsp": "#2ca02c", "shading": "#9467bd", "reference": "#000000"}
ERROR_KEYS = ["visibility_all", "visibility_non_edge", "rmse", "psnr_db", "shadow_disagreement",
              "shadow_disagreement_band", "shadow_disagreement_away", "shadow_band_pixels", "shadow_band_differing",
              "shadow_away_pixels", "shadow_away_differing", "texture_pixels", "texture_rmse", "texture_psnr_db"]
BEGIN, END = "<!-- accuracy-bench:begin -->", "<!-- accuracy-bench:end -->"
TEXTURE_BEGIN, TEXTURE_END = "<!-- texture-bench:begin -->", "<!-- texture-bench:end -->"
TEXTURE_CLASS = "textures"
FILTERS = ["nearest", "bilinear", "trilinear", "anisotropic"]


def family(row):
    if row["group"] == "shading":
        return "shading"
    return row["options"]["pipeline"]


def write_csv(results, path):
    fields = ["scene", "class", "config", "group", "status", "frames", "frame_ms", "build_ms", "reference_ms"]
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(fields + ERROR_KEYS + ["options"])
        for r in results["runs"]:
            e = r.get("errors", {})
            w.writerow([r.get(k, "") for k in fields] + [e.get(k, "") for k in ERROR_KEYS] + [_compact(r["options"])])


def _compact(options):
    return re.sub(r"\s+", "", str(options)).replace("'", "")


def aggregate(runs):
    """One point per config over the scenes of a class: geometric-mean frame time, mean errors."""
    points = {}
    for r in runs:
        if r["group"] == "reference" or r["status"] != "ok" or "errors" not in r:
            continue
        p = points.setdefault(r["config"], {"config": r["config"], "family": family(r), "group": r["group"],
                                            "ms": [], "build": [], "scenes": 0, **{k: [] for k in ERROR_KEYS}})
        p["ms"].append(r["frame_ms"])
        p["build"].append(r.get("build_ms", 0))
        p["scenes"] += 1
        for k in ERROR_KEYS:
            if r["errors"].get(k) is not None:
                p[k].append(r["errors"][k])
    out = []
    for p in points.values():
        geo = lambda v: math.exp(sum(math.log(max(x, 1e-6)) for x in v) / len(v)) if v else None
        mean = lambda v: sum(v) / len(v) if v else None
        q = {"config": p["config"], "family": p["family"], "group": p["group"], "scenes": p["scenes"],
             "ms": geo(p["ms"]), "build_ms": geo([b for b in p["build"] if b > 0])}
        for k in ERROR_KEYS:
            q[k] = mean(p[k])
        # PSNR of identical images is infinite (null in the JSON): the mean is over the finite ones.
        q["psnr_db"] = mean([v for v in p["psnr_db"] if v is not None and math.isfinite(v)])
        out.append(q)
    out.sort(key=lambda q: q["ms"])
    for i, q in enumerate(out):
        q["number"] = i + 1  # the point's label in the plots and its row in the table
    return out


def pareto(points, key):
    """Points no other point beats on both time and error (ties on both keep the first)."""
    front, best = [], math.inf
    for p in sorted((p for p in points if p[key] is not None), key=lambda p: (p["ms"], p[key])):
        if p[key] < best:
            front.append(p)
            best = p[key]
    return front


def svg_scatter(path, title, points, key, y_label, reference_ms=None):
    """Run time (x, log) against an error (y, linear from 0); the Pareto front drawn as a step line and
    its points ringed; each point labelled with its config. reference_ms: the reference's own time."""
    w, h, left, right, top, bottom = 980, 560, 80, 270, 40, 50
    pts = [p for p in points if p[key] is not None and p["ms"]]
    if not pts:
        return False
    xs = [p["ms"] for p in pts] + ([reference_ms] if reference_ms else [])
    lx = (math.floor(math.log10(min(xs))), math.ceil(math.log10(max(xs))))
    lx = (lx[0], max(lx[1], lx[0] + 1))
    y_max = max(p[key] for p in pts) or 1.0
    y_max = _nice_ceiling(y_max)
    sx = lambda x: left + (math.log10(x) - lx[0]) / (lx[1] - lx[0]) * (w - left - right)
    sy = lambda y: h - bottom - y / y_max * (h - top - bottom)
    out = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" viewBox="0 0 %d %d" '
           'font-family="sans-serif" font-size="11">' % (w, h, w, h),
           '<rect width="100%" height="100%" fill="white"/>',
           '<text x="%d" y="22" font-size="14" font-weight="bold">%s</text>' % (left, _xml(title))]
    for d in range(lx[0], lx[1] + 1):
        x = sx(10 ** d)
        out.append('<line x1="%.1f" y1="%d" x2="%.1f" y2="%d" stroke="#ddd"/>' % (x, top, x, h - bottom))
        out.append('<text x="%.1f" y="%d" text-anchor="middle">%g</text>' % (x, h - bottom + 16, 10 ** d))
    for i in range(6):
        v = y_max * i / 5
        out.append('<line x1="%d" y1="%.1f" x2="%d" y2="%.1f" stroke="#ddd"/>' % (left, sy(v), w - right, sy(v)))
        out.append('<text x="%d" y="%.1f" text-anchor="end">%.3g</text>' % (left - 6, sy(v) + 4, v))
    out.append('<rect x="%d" y="%d" width="%d" height="%d" fill="none" stroke="#444"/>'
               % (left, top, w - left - right, h - top - bottom))
    out.append('<text x="%d" y="%d" text-anchor="middle">frame time, ms (log; geometric mean over the class)</text>'
               % ((left + w - right) / 2, h - 12))
    out.append('<text transform="translate(18 %d) rotate(-90)" text-anchor="middle">%s</text>'
               % ((top + h - bottom) / 2, _xml(y_label)))
    front = pareto(pts, key)
    steps = []
    for a, b in zip(front, front[1:] + [None]):
        steps.append((sx(a["ms"]), sy(a[key])))
        steps.append((sx(b["ms"]) if b else w - right, sy(a[key])))
    out.append('<polyline fill="none" stroke="#f0a000" stroke-width="2" stroke-dasharray="5,3" points="%s"/>'
               % " ".join("%.1f,%.1f" % s for s in steps))
    if reference_ms:
        out.append('<line x1="%.1f" y1="%d" x2="%.1f" y2="%d" stroke="#000" stroke-dasharray="2,3"/>'
                   % (sx(reference_ms), top, sx(reference_ms), h - bottom))
        out.append('<text x="%.1f" y="%d" font-size="10">reference %.3g ms</text>'
                   % (sx(reference_ms) + 3, top + 12, reference_ms))
    placed = []  # label boxes so far: a label that would overlap one moves up a line
    for p in sorted(pts, key=lambda p: (p["ms"], -p[key])):
        x, y = sx(p["ms"]), sy(p[key])
        if p in front:
            out.append('<circle cx="%.1f" cy="%.1f" r="7" fill="none" stroke="#f0a000" stroke-width="2"/>' % (x, y))
        out.append('<circle cx="%.1f" cy="%.1f" r="3.5" fill="%s"/>' % (x, y, COLOURS[p["family"]]))
        lx_, ly_ = x + 5, y - 5
        while any(abs(lx_ - a) < 14 and abs(ly_ - b) < 10 for a, b in placed):
            ly_ -= 10
        placed.append((lx_, ly_))
        out.append('<text x="%.1f" y="%.1f" font-size="9" fill="#333">%d</text>' % (lx_, ly_, p["number"]))
    legend = [(f, c) for f, c in COLOURS.items() if f != "reference" and any(p["family"] == f for p in pts)]
    legend.append(("Pareto front", "#f0a000"))
    for i, (name, colour) in enumerate(legend):
        y = top + 14 + 16 * i
        out.append('<circle cx="%d" cy="%d" r="4" fill="%s"/>' % (w - right + 18, y - 4, colour))
        out.append('<text x="%d" y="%d">%s</text>' % (w - right + 28, y, name if name != "shading" else "zbuffer shading/shadows"))
    for i, p in enumerate(sorted(points, key=lambda p: p["number"])):
        out.append('<text x="%d" y="%d" font-size="9">%d %s</text>'
                   % (w - right + 12, top + 30 + 16 * len(legend) + 11 * i, p["number"], _xml(p["config"])))
    out.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")
    return True


def _nice_ceiling(v):
    e = 10 ** math.floor(math.log10(v))
    for m in (1, 2, 2.5, 5, 10):
        if v <= m * e:
            return m * e
    return 10 * e


def _xml(text):
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def pct(v):
    return "—" if v is None else "%.3f %%" % (100 * v)


def num(v, fmt="%.2f"):
    return "—" if v is None else fmt % v


def best_settings(points):
    """The fastest visibility config whose mean non-edge error is at most 0.1 %, and the fastest
    shading config within 1 dB of the class's best PSNR (with and without shadows)."""
    lines = []
    exact = [p for p in points if p["group"] == "visibility" and p["visibility_non_edge"] is not None
             and p["visibility_non_edge"] <= 1e-3]
    if exact:
        b = min(exact, key=lambda p: p["ms"])
        lines.append("visibility: **%s** (%s ms, non-edge error %s)" % (b["config"], num(b["ms"]), pct(b["visibility_non_edge"])))
    for shadows, name in ((False, "shading without shadows"), (True, "shading with shadows")):
        cands = [p for p in points if p["psnr_db"] is not None and ("shadows" in p["config"]) == shadows
                 and (p["group"] == "shading" or p["config"] == "zbuffer")]
        if cands:
            top = max(p["psnr_db"] for p in cands)
            b = min((p for p in cands if p["psnr_db"] >= top - 1.0), key=lambda p: p["ms"])
            lines.append("%s: **%s** (%s ms, PSNR %s dB; best %s dB)" % (name, b["config"], num(b["ms"]),
                                                                     num(b["psnr_db"], "%.1f"), num(top, "%.1f")))
    return lines


def class_section(results, cls, title, svg_dir, doc_dir):
    runs = [r for r in results["runs"] if r["class"] == cls]
    scenes = [s for s in results["scenes"] if s["class"] == cls]
    if not scenes:
        return ["### %s" % title, "", "No scene of this class was available in this run.", ""]
    points = aggregate(runs)
    refs = [r["frame_ms"] for r in runs if r["group"] == "reference" and r["status"] == "ok" and r["frame_ms"]]
    ref_ms = math.exp(sum(math.log(v) for v in refs) / len(refs)) if refs else None
    L = ["### %s" % title, "", "Scenes (%d): %s." % (len(scenes), ", ".join("`%s`" % s["name"] for s in scenes)), ""]
    vis_front = {p["config"] for p in pareto(points, "visibility_non_edge")}
    rmse_front = {p["config"] for p in pareto(points, "rmse")}
    L += ["| # | config | frame ms | BSP build ms | visibility error, all | visibility error, non-edge | RMSE | PSNR dB | "
          "shadow disagreement | within 2 px of shadow edges | away from them | Pareto (vis / shading) | scenes |",
          "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|"]
    for p in points:
        marks = ("V" if p["config"] in vis_front else "") + ("S" if p["config"] in rmse_front else "")
        L.append("| %d | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %d |" % (
            p["number"], p["config"], num(p["ms"]), num(p["build_ms"], "%.1f"), pct(p["visibility_all"]),
            pct(p["visibility_non_edge"]), num(p["rmse"]), num(p["psnr_db"], "%.1f"),
            pct(p["shadow_disagreement"]), pct(p["shadow_disagreement_band"]), pct(p["shadow_disagreement_away"]),
            marks or "", p["scenes"]))
    L.append("")
    for key, label, suffix in (("visibility_non_edge", "visibility error, non-edge pixels (share)", "visibility"),
                               ("rmse", "shading error: RMSE of 8-bit RGB", "shading")):
        name = "%s_%s.svg" % (cls, suffix)
        if svg_scatter(os.path.join(svg_dir, name), "%s: run time against %s" % (title, suffix), points, key, label,
                       ref_ms):
            L += ["![%s, %s](%s)" % (title, suffix, os.path.relpath(os.path.join(svg_dir, name), doc_dir)), ""]
    L += ["Best setting for this class (by rule: the fastest configuration whose mean non-edge visibility error is "
          "at most 0.1 %; the fastest shading configuration within 1 dB of the class's best PSNR): "
          + "; ".join(best_settings(points)) + ".", ""]
    return L


def pivot(results, configs, cell):
    """Scenes (rows) by configs (columns); cell(errors) formats one run's measure."""
    by = {(r["scene"], r["config"]): r for r in results["runs"]}
    L = ["| scene | class | " + " | ".join(configs) + " |", "|---|---|" + "---:|" * len(configs)]
    for s in results["scenes"]:
        cells = []
        for c in configs:
            r = by.get((s["name"], c))
            if r is None:
                cells.append("—")
            elif "errors" not in r:
                cells.append(r["status"])
            else:
                cells.append(cell(r["errors"]))
        L.append("| %s | %s | %s |" % (s["name"], s["class"], " | ".join(cells)))
    return L + [""]


def psnr_cell(errors):
    """The JSON has no infinity: identical images carry RMSE 0 and a null PSNR."""
    if errors.get("psnr_db") is not None:
        return "%.1f" % errors["psnr_db"]
    return "inf" if errors.get("rmse") == 0 else "—"


def header(results, commit):
    a, b = results["machine_start"], results["machine_end"]
    L = ["## Run time against error", "",
         "Generated by `bench/accuracy.sh` (`bench/accuracy.cpp`, report `bench/accuracy_report.py`); every run is "
         "in `bench/results/accuracy.json` and `.csv`. Do not edit this section by hand.", "",
         "- run: %s, commit `%s`; %d×%d pixels" % (results["date"], commit, results["width"], results["height"]),
         "- machine: %s, `nproc` %s; load average at the start %s, at the end %s (shared by several engineers: "
         "absolute times drift, compare within one run)" % (a["cpu"], a["nproc"], " ".join(a["loadavg"].split()[:3]), " ".join(b["loadavg"].split()[:3])),
         "- run time: wall clock of `render_frame` (parsing, import and tessellation excluded), the median of up to "
         "%d frames after one warm-up frame (3 frames when a frame takes over 250 ms, 1 over 1 s). The BSP tree is "
         "built on the warm-up frame (**BSP build ms**, a cache miss) and the timed frames reuse it from the cache, "
         "as the service does: the plotted BSP time is the cached-tree frame time. A run is abandoned after %g s "
         "(status `timeout`)." % (results["max_frames"], results["timeout_s"]),
         "- errors: against the `reference` pipeline on the same scene, camera and options (the same lights, "
         "shading mode and shadows on/off; the reference casts exact shadow rays, so shadow-map size and PCF do "
         "not change it). Visibility error = share of pixels whose polygon id differs, over all pixels and over "
         "pixels off the reference's id edges; RMSE/PSNR of the 8-bit RGB image; shadow disagreement = share of "
         "pixels whose lit state differs. Per class, a point is one configuration: the geometric mean of its frame "
         "times and the mean of its errors over the class's scenes; the Pareto front (no other point is both "
         "faster and more accurate) is ringed and joined by the dashed line. A class's mean PSNR leaves out scenes "
         "where the images are identical (infinite PSNR); its RMSE does not.", ""]
    L += ["| scene | class | source | polygons | lights | camera | fewer options |", "|---|---|---|---:|---:|---|---|"]
    for s in results["scenes"]:
        lights = "%d%s" % (s["lights"], " (added)" if s["light_added"] else "")
        fewer = (["2 BSP settings (large)"] if s["large"] else []) + \
            (["3 shadow settings"] if s["few_shadow_settings"] else [])
        L.append("| %s | %s | %s | %d | %s | %s | %s |" % (s["name"], s["class"], s["source"], s["polygons"], lights,
                                                          s["camera"], ", ".join(fewer)))
    return L + [""]


def quoted(results):
    vis = ["zbuffer", "painter-mean", "painter-min", "painter-max", "painter-newell", "bsp w=1/4/-1 eps=1e-07"]
    shade = ["zbuffer", "gouraud", "phong", "flat shadows 2048 pcf1", "gouraud shadows 2048 pcf1", "phong shadows 2048 pcf1"]
    L = ["### Every scene: visibility error over non-edge pixels", "",
         "`zbuffer` is flat shading without shadows; the BSP column is the default weights and band.", ""]
    L += pivot(results, vis, lambda e: pct(e["visibility_non_edge"]))
    L += ["### Every scene: shading PSNR (dB) against the reference with the same lights", "",
          "Columns without shadows compare with the reference without shadows; with shadows (2048² map), with "
          "exact shadow rays. `inf`: identical images.", ""]
    L += pivot(results, shade, psnr_cell)
    return L


def only_classes(results, keep):
    """The results restricted to the scenes (and runs) whose class keep() accepts."""
    return dict(results, scenes=[x for x in results["scenes"] if keep(x["class"])],
                runs=[r for r in results["runs"] if keep(r["class"])])


def texture_section(results, commit, results_path):
    """The textured class: texture PSNR per scene and filter, with the pixels it is taken over and the
    frame times, between TEXTURE_BEGIN and TEXTURE_END."""
    by = {(r["scene"], r["config"]): r for r in results["runs"]}
    a = results["machine_start"]
    L = [TEXTURE_BEGIN,
         "Generated by `bench/accuracy.sh` (the textured class) into `%s`: run %s, commit `%s`, %d×%d pixels, "
         "load average %s at the start. Zbuffer, Phong, no shadows; PSNR in dB over the textured pixels away "
         "from edges, then the median frame time in ms." % (
             results_path, results["date"], commit, results["width"], results["height"],
             " ".join(a["loadavg"].split()[:3])), "",
         "| scene | textured pixels | " + " | ".join(FILTERS) + " | reference ms |",
         "|---|---:|" + "---:|" * (len(FILTERS) + 1)]
    for s in results["scenes"]:
        cells, pixels = [], "—"
        for f in FILTERS:
            r = by.get((s["name"], "texture " + f))
            if r is None:
                cells.append("—")
            elif "errors" not in r:
                cells.append(r["status"])
            else:
                e = r["errors"]
                pixels = "%d" % e["texture_pixels"]
                psnr = "inf" if e.get("texture_psnr_db") is None else "%.2f" % e["texture_psnr_db"]
                cells.append("%s (%.1f ms)" % (psnr, r["frame_ms"]))
        ref = [r["frame_ms"] for r in results["runs"] if r["scene"] == s["name"] and r["group"] == "reference"]
        L.append("| %s | %s | %s | %s |" % (s["name"], pixels, " | ".join(cells), "%.0f" % ref[0] if ref else "—"))
    return L + [TEXTURE_END]


def replace_between(text, begin, end, section):
    if begin in text and end in text:
        return text[:text.index(begin)] + section.rstrip("\n") + text[text.index(end) + len(end):]
    return text.rstrip("\n") + "\n\n" + section  # after whatever is there


def write_doc(results, doc_path, svg_dir, commit, results_path):
    os.makedirs(svg_dir, exist_ok=True)
    doc_dir = os.path.dirname(os.path.abspath(doc_path))
    text = open(doc_path).read() if os.path.exists(doc_path) else "# Accuracy\n\n"
    main = only_classes(results, lambda c: c != TEXTURE_CLASS)
    if main["scenes"]:
        L = [BEGIN] + header(main, commit)
        for cls, title in CLASSES:
            L += class_section(main, cls, title, os.path.abspath(svg_dir), doc_dir)
        L += quoted(main) + [END]
        text = replace_between(text, BEGIN, END, "\n".join(L) + "\n")
    textured = only_classes(results, lambda c: c == TEXTURE_CLASS)
    if textured["scenes"]:
        text = replace_between(text, TEXTURE_BEGIN, TEXTURE_END,
                               "\n".join(texture_section(textured, commit, results_path)) + "\n")
    with open(doc_path, "w") as f:
        f.write(text)


def main():
    import json
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("results")
    ap.add_argument("--csv")
    ap.add_argument("--doc")
    ap.add_argument("--svg-dir")
    ap.add_argument("--commit", default="unknown")
    a = ap.parse_args()
    with open(a.results) as f:
        results = json.load(f)
    if a.csv:
        write_csv(results, a.csv)
    if a.doc:
        write_doc(results, a.doc, a.svg_dir or os.path.join(os.path.dirname(a.doc), "accuracy"), a.commit,
                  os.path.relpath(a.results))


if __name__ == "__main__":
    main()
