"""The performance report and its SVG plots from the results dict bench/perf.py writes (standard library
only). Every number in the document comes from that dict; the performance targets are the tables below.
A ratio is the median over interleaved rounds of (this round's median frame / that round's), so slow
drift of the machine's load cancels; medians in ms are the median over rounds of each run's median."""
import os
import statistics

import perf_plot

LABELS = {"llvmpipe_flat": "llvmpipe depth+Lambert", "llvmpipe_phong_shadow": "llvmpipe Phong+shadow map",
          "embree": "Embree primary+shadow rays", "flat": "ours flat", "gouraud": "ours Gouraud",
          "phong": "ours Phong", "phong_shadow": "ours Phong+shadows", "flat_culled": "ours flat, culling on"}
ROOM_SOUPS = ("soup_1e5", "soup_1e6")
# One colour per renderer and mode in every plot: peers in blue/red/green, ours in the rest.
COLOURS = dict(zip(LABELS.values(),
                   ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f"]))


def measured_variants(results):
    """The variants of LABELS every scene of this run has (an older run lacks the later ones)."""
    return [v for v in LABELS if all(v in s["runs"] for s in results["scenes"])]


def flat_target(scene):
    if scene["kind"] == "room":
        return 0.4
    return 0.8 if scene["name"] in ROOM_SOUPS else None


# (key, label, numerator, denominator, target: scene -> bound or None). Lower is better.
RATIOS = [
    ("ps_vs_llvmpipe", "Phong+shadows / llvmpipe Phong+shadow map", "phong_shadow", "llvmpipe_phong_shadow",
     lambda s: 0.5),
    ("ps_vs_embree", "Phong+shadows / Embree primary+shadow rays", "phong_shadow", "embree", lambda s: 1.0),
    ("flat_vs_llvmpipe", "flat / llvmpipe depth+Lambert", "flat", "llvmpipe_flat", flat_target),
    ("gouraud_vs_flat", "Gouraud / our flat", "gouraud", "flat", lambda s: 1.2),
    ("phong_vs_flat", "Phong (no shadows) / our flat", "phong", "flat", lambda s: 1.5),
]
# (variant, target: scene -> bound or None) for "1 thread / 2 threads"; higher is better.
SPEEDUPS = [("flat", lambda s: 1.7 if s["kind"] == "room" else None),
            ("phong_shadow", lambda s: 1.7 if s["kind"] == "room" else None),
            ("llvmpipe_flat", lambda s: None), ("llvmpipe_phong_shadow", lambda s: None), ("embree", lambda s: None)]
PRIORITY_TARGETS = [("bsp", 1.0), ("painter", 1.5)]


def fmt_ms(ms):
    return "—" if ms is None else ("%.1f" % ms if ms >= 10 else "%.2f" % ms)


def fmt_x(x):
    return "—" if x is None else "%.2f×" % x


def median_ms(rounds):
    good = [r["ms"] for r in rounds if r.get("ms")]
    return statistics.median(good) if good else None


def paired(a_rounds, b_rounds):
    """Median over rounds of a/b, only rounds where both ran."""
    q = [a["ms"] / b["ms"] for a, b in zip(a_rounds, b_rounds) if a.get("ms") and b.get("ms")]
    return statistics.median(q) if q else None


def top_threads(results):
    return str(max(results["settings"]["threads"]))


def ratio_of(scene, key, threads):
    _, _, num, den, _ = next(r for r in RATIOS if r[0] == key)
    return paired(scene["runs"][num].get(threads, []), scene["runs"][den].get(threads, []))


def speedup_of(scene, variant, results):
    t = sorted(results["settings"]["threads"])
    if len(t) < 2:
        return None
    runs = scene["runs"][variant]
    return paired(runs.get(str(t[0]), []), runs.get(str(t[-1]), []))


def verdict(value, bound, higher_is_better=False):
    if bound is None or value is None:
        return ""
    ok = value >= bound if higher_is_better else value <= bound
    return "met" if ok else "**not met**"


def target_rows(results):
    """One row per performance target: (target, scenes evaluated, scenes met, worst value and scene)."""
    t, rows = top_threads(results), []
    for key, label, _, _, target in RATIOS:
        checked = [(ratio_of(s, key, t), s, target(s)) for s in results["scenes"] if target(s) is not None]
        bounds = sorted({b for _, _, b in checked})
        for b in bounds:
            group = [(v, s) for v, s, bb in checked if bb == b and v is not None]
            which = "room scenes" if key == "flat_vs_llvmpipe" and b == 0.4 else \
                "10^5, 10^6 soups" if key == "flat_vs_llvmpipe" else "every scene"
            worst = max(group, key=lambda vs: vs[0]) if group else None
            rows.append(("%s ≤ %.1f× (%s, %s threads)" % (label, b, which, t), len(group),
                         sum(v <= b for v, _ in group), worst, all(v <= b for v, _ in group) and bool(group)))
    for variant, target in SPEEDUPS[:2]:
        group = [(speedup_of(s, variant, results), s) for s in results["scenes"] if target(s) is not None]
        group = [(v, s) for v, s in group if v is not None]
        worst = min(group, key=lambda vs: vs[0]) if group else None
        rows.append(("%s: 1 thread / 2 threads ≥ 1.7× (room scenes)" % LABELS[variant], len(group),
                     sum(v >= 1.7 for v, _ in group), worst, all(v >= 1.7 for v, _ in group) and bool(group)))
    prio = results.get("priority")
    for name, bound in PRIORITY_TARGETS:
        if not prio:
            label = "%s / zbuffer ≤ %.1f× (examples/apartment.json, eye level)" % (name, bound)
            rows.append((label, 0, 0, None, False))
        else:
            v = paired(prio["runs"][name], prio["runs"]["zbuffer"])
            rows.append(("%s / zbuffer ≤ %.1f× (%s, eye level%s)" % (name, bound, prio["request"],
                         ", warm tree" if name == "bsp" else ""), 1 if v else 0, int(bool(v and v <= bound)),
                         (v, {"name": "apartment.json"}) if v else None, bool(v and v <= bound)))
    return rows


def ratio_table_text(results):
    """The ratio table as plain text, for the console at the end of a run."""
    head = ["scene", "thr"] + [k for k, *_ in RATIOS] + ["speed-up flat", "speed-up P+S"]
    width = max([22] + [len(s["name"]) for s in results["scenes"]])
    row = lambda cells: " ".join(c.ljust(width) if i == 0 else "%14s" % c for i, c in enumerate(cells))
    lines = [row(head)]
    for s in results["scenes"]:
        for t in results["settings"]["threads"]:
            cells = [s["name"], str(t)] + [fmt_x(ratio_of(s, k, str(t))) for k, *_ in RATIOS]
            cells += [fmt_x(speedup_of(s, v, results)) for v, _ in SPEEDUPS[:2]]
            lines.append(row(cells))
    return "\n".join(lines)


def header(results):
    m, st, load = results["machine"], results["settings"], results["load"]
    samples = load.get("samples_1min") or [0.0]
    # The peers report the CPU time other processes took during their timed frames: the load they met.
    other = [r["frames_other_cpu_ms"] / r["frames_wall_ms"] for s in results["scenes"] for v in s["runs"].values()
             for rounds in v.values() for r in rounds if r.get("frames_wall_ms")]
    renderers = {}
    for s in results["scenes"]:
        for v in ("llvmpipe_flat", "embree"):
            for rounds in s["runs"][v].values():
                for r in rounds:
                    renderers.setdefault(v, r.get("renderer"))
    L = ["# Performance: roomrender against llvmpipe and Embree", ""]
    if statistics.median(samples) > m["cores"]:
        L += ["> **Loaded machine:** the median 1-minute load average was %.1f on %s cores, from other work. Ratios "
              "are paired per round and so hold up better than times, but treat verdicts near their bound as "
              "undecided and repeat the run on a quiet machine." % (statistics.median(samples), m["cores"]), ""]
    if results.get("partial"):
        L += ["> **Partial run:** %s. The tables hold the scenes measured so far." % results["partial"], ""]
    if results.get("quick"):
        L += ["> **Quick smoke run on a loaded, shared machine: not a measurement.** It checks that the harness "
              "works end to end (few scenes, one round, few frames, small frames). Run `bench/perf.sh` without "
              "`QUICK=1` for the numbers the performance targets are judged on.", ""]
    L += ["Generated by `bench/perf.sh` from `%s` (do not edit by hand)."
          % results.get("results_path", "the results JSON"),
          "",
          "- run: %s, harness at commit `%s`; measured binary `%s`%s" % (
              m["date"], m["commit"], m["roomrender"],
              " (%s)" % m["roomrender_version"] if m.get("roomrender_version") else ""),
          "- machine: %s, %s cores, Linux %s" % (m["cpu"], m["cores"], m["kernel"]),
          "- load average (1, 5, 15 min): %s at the start, %s at the end; 1-minute load sampled before each "
          "of %d runs: median %.2f, range %.2f–%.2f." % (
              " ".join("%.2f" % x for x in load["start"]), " ".join("%.2f" % x for x in load["end"]), len(samples),
              statistics.median(samples), min(samples), max(samples)) +
          (" During the peers' timed frames other processes used %.2f cores (median; range %.2f–%.2f)."
           % (statistics.median(other), min(other), max(other)) if other else "") +
          " The machine is shared: compare ratios (both sides of a ratio ran back to back in the same round), "
          "not absolute times.",
          "- frames: %s; rounds: %d, interleaved: each round every variant at every thread count (%s; the order of "
          "thread counts alternates between rounds); %d timed frames after one warm-up (a third as many on the "
          "10^6 soup and the conference room)." % (st["size"], st["rounds"], ", ".join(map(str, st["threads"])),
                                                   st["frames"]),
          "- peers (`../shared/peers`, `peer_render`): %s; %s. llvmpipe threads by `LP_NUM_THREADS`, Embree's by "
          "`--threads`, ours by `bench-render --threads`." % (renderers.get("llvmpipe_flat"), renderers.get("embree")),
          "- ours: `roomrender bench-render --obj` on the same OBJ and camera, zbuffer pipeline, shadow cache off "
          "(the peers draw their shadows every frame), no PNG encode (the peers encode none).", ""]
    return L


def targets_section(results):
    L = ["## Targets", "", "Judged at %s threads (the machine's cores)." % top_threads(results), "",
         "| target | scenes | met | worst | verdict |", "|---|---:|---:|---|---|"]
    for label, n, met, worst, ok in target_rows(results):
        w = "%s (%s)" % (fmt_x(worst[0]), worst[1]["name"]) if worst else "—"
        state = "not measured in this run" if not n else "met" if ok else "**not met**"
        L.append("| %s | %d | %d | %s | %s |" % (label, n, met, w, state))
    return L + [""]


def ratios_section(results):
    L = ["## Ratios", "", "Ours / peer or ours / our flat, median over rounds; lower is better. A mark follows a "
         "ratio that has a target at that thread count.", "",
         "| scene | triangles | threads | " + " | ".join(label for _, label, *_ in RATIOS) + " |",
         "|---|---:|---:|" + "---:|" * len(RATIOS)]
    top = top_threads(results)
    for s in results["scenes"]:
        for t in map(str, results["settings"]["threads"]):
            cells = []
            for key, _, _, _, target in RATIOS:
                v = ratio_of(s, key, t)
                mark = verdict(v, target(s)) if t == top else ""
                cells.append(fmt_x(v) + (" " + mark if mark else ""))
            L.append("| %s | %s | %s | %s |" % (s["name"], f"{s['triangles']:,}" if s.get("triangles") else "—", t,
                                                " | ".join(cells)))
    t = sorted(results["settings"]["threads"])
    if len(t) >= 2:
        L += ["", "Speed-up from %d to %d threads (%d-thread frame / %d-thread frame, median over rounds; higher is "
              "better; target ≥ 1.7× for ours on the room scenes):" % (t[0], t[-1], t[0], t[-1]), "",
              "| scene | " + " | ".join(LABELS[v] for v, _ in SPEEDUPS) + " |", "|---|" + "---:|" * len(SPEEDUPS)]
        for s in results["scenes"]:
            cells = []
            for v, target in SPEEDUPS:
                x = speedup_of(s, v, results)
                mark = verdict(x, target(s), higher_is_better=True)
                cells.append(fmt_x(x) + (" " + mark if mark else ""))
            L.append("| %s | %s |" % (s["name"], " | ".join(cells)))
    prio = results.get("priority")
    if prio:
        zb = prio["runs"]["zbuffer"]
        L += ["", "Painter and BSP (tree cached) against zbuffer, flat, `bench-render --request %s` from eye level "
              "(`%s`), default threads:" % (prio["request"], prio["camera"]), "",
              "| pipeline | median ms | / zbuffer |", "|---|---:|---:|"]
        for name, rounds in prio["runs"].items():
            L.append("| %s | %s | %s |" % (name, fmt_ms(median_ms(rounds)), fmt_x(paired(rounds, zb))))
    return L + [""]


def medians_section(results):
    variants = measured_variants(results)
    L = ["## Median frame times (ms)", "", "| scene | threads | " + " | ".join(LABELS[v] for v in variants) + " |",
         "|---|---:|" + "---:|" * len(variants)]
    notes = set()
    for s in results["scenes"]:
        for t in map(str, results["settings"]["threads"]):
            cells = []
            for v in variants:
                rounds = s["runs"][v].get(t, [])
                cells.append(fmt_ms(median_ms(rounds)))
                notes |= {"%s %s: %s" % (s["name"], LABELS[v], r.get("error") or r.get("note"))
                          for r in rounds if r.get("error") or r.get("note")}
            L.append("| %s | %s | %s |" % (s["name"], t, " | ".join(cells)))
    if notes:
        L += ["", "Failed or incomplete runs:", ""] + ["- " + n.replace("\n", " ") for n in sorted(notes)]
    L += ["", "Same scene on both sides: share of pixels whose id differs between our zbuffer flat frame and "
          "llvmpipe's (OBJ face ids, the peers' `idcompare`); *interior* leaves out pixels on an id edge.", "",
          "| scene | mismatch | interior mismatch |", "|---|---:|---:|"]
    for s in results["scenes"]:
        c = s.get("same_scene", {})
        pct = lambda k: "%.3f %%" % (100 * c[k]) if k in c else c.get("error", "—")[:80]
        L.append("| %s | %s | %s |" % (s["name"], pct("mismatch_fraction"), pct("interior_mismatch_fraction")))
    return L + [""]


def plots_section(results, svg_dir, doc_dir):
    os.makedirs(svg_dir, exist_ok=True)
    rel = os.path.relpath(svg_dir, doc_dir)
    top, L = top_threads(results), ["## Plots", ""]
    names = [s["name"] for s in results["scenes"]]
    variants = measured_variants(results)
    frame_series = [(LABELS[v], [median_ms(s["runs"][v].get(top, [])) for s in results["scenes"]]) for v in variants]
    ratio_series = [(label, [ratio_of(s, k, top) for s in results["scenes"]]) for k, label, *_ in RATIOS]
    speed_series = [(LABELS[v], [speedup_of(s, v, results) for s in results["scenes"]]) for v, _ in SPEEDUPS]
    plots = [("frames.svg", "Median frame time per scene, %s threads" % top,
              perf_plot.category_plot("Median frame time per scene, %s threads" % top, names, frame_series,
                                      "median frame time (ms)", colours=COLOURS)),
             ("ratios.svg", "Ratios per scene, %s threads" % top,
              perf_plot.category_plot("Ratios per scene, %s threads (lower is better; dashed: 1×)" % top, names,
                                      ratio_series, "ratio", reference=1.0)),
             ("speedup.svg", "Speed-up from 1 to %s threads" % top,
              perf_plot.category_plot("Speed-up from 1 to %s threads (higher is better; dashed: 1.7× target)" % top,
                                      names, speed_series, "1-thread frame / 2-thread frame", reference=1.7,
                                      colours=COLOURS))]
    soups = sorted((s for s in results["scenes"] if s["kind"] == "soup" and s.get("triangles")),
                   key=lambda s: s["triangles"])
    if len(soups) >= 2:
        series = [(LABELS[v], [(s["triangles"], median_ms(s["runs"][v].get(top, []))) for s in soups]) for v in variants]
        title = "Frame time against triangle count (random soups, %s threads)" % top
        svg = perf_plot.xy_plot(title, series, "triangles", "median frame time (ms)", COLOURS)
        plots.append(("soups.svg", title, svg))
    for file, title, svg in plots:
        if svg is None:
            continue
        with open(os.path.join(svg_dir, file), "w") as f:
            f.write(svg)
        L += ["![%s](%s/%s)" % (title, rel, file), ""]
    return L


def write_report(results, doc_path):
    doc_dir = os.path.dirname(os.path.abspath(doc_path))
    svg_dir = os.path.join(doc_dir, os.path.splitext(os.path.basename(doc_path))[0])
    missing = results.get("missing") or []
    L = header(results) + targets_section(results) + ratios_section(results) + medians_section(results)
    L += plots_section(results, svg_dir, doc_dir)
    L += ["## Scenes", "", "Scenes and cameras are `../shared/peers/tools/side_by_side.py`'s (its `SCENES` and `CAM`), "
          "OBJs from `../shared/peers/scenes/gen_obj.py`; the conference room is ../shared/data/meshes/conference; "
          "the `sh3d_*` homes are imported by this roomrender, exported with `roomrender export --obj` and seen from "
          "each home's observer camera (side_by_side's `add_homes`). `cylinders` is no room: the flat and thread "
          "targets for room scenes do not apply to it, nor to the 10^4 soup's flat ratio.", ""]
    if missing:
        L += ["Not measured (absent or failed): " + ", ".join(missing) + ".", ""]
    with open(doc_path, "w") as f:
        f.write("\n".join(L))
