"""Shadow error within 2 pixels of the reference's shadow edges and away from them, from bench_accuracy's
JSON (its shadow configurations: maps at the bench's settings and exact shadow rays): the section of
docs/accuracy.md between its accuracy-shadows markers, with a table per scene class, one per scene and,
given a run of an earlier commit (--before), the Sweet Home 3D homes before and after at the map
defaults. Standard library only; every number written comes from the JSONs.
  python3 bench/accuracy_shadows.py AFTER.json [--before BEFORE.json] [--doc docs/accuracy.md]
      [--csv OUT.csv] [--commit C] [--before-commit C]"""
import argparse
import json
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import accuracy_report  # noqa: E402  (CLASSES, write_csv)

BEGIN, END = "<!-- accuracy-shadows:begin -->", "<!-- accuracy-shadows:end -->"
MAP_DEFAULTS = "phong shadows 2048 pcf1"  # options.shadow's defaults: a 2048² map, hard lookups
RAYS = "phong shadows rays"


def shadow_runs(results):
    """The runs with shadows that were measured against the reference, with the band/away split."""
    return [r for r in results["runs"] if r["group"] == "shading" and "shadows" in r["config"]
            and r["status"] == "ok" and r.get("errors", {}).get("shadow_disagreement_band") is not None]


def config_key(label):
    """Maps by size, then PCF, then shading mode; rays last."""
    m = re.match(r"(\w+) shadows (\d+) pcf(\d+)$", label)
    if not m:
        return (1, 0, 0, label)
    return (0, int(m.group(2)), int(m.group(3)), m.group(1))


def half_holds(before, after):
    """The homes' target: after at most half of before (0 before leaves only 0 after)."""
    return after <= 0.5 * before


def pct(v):
    return "—" if v is None else "%.4f %%" % (100 * v)


def share_px(errors, where):
    """'0.0123 % (28 px)': the share of the band's (or away) pixels whose lit state differs, and how many."""
    share = errors.get("shadow_disagreement_" + where)
    count = errors.get("shadow_%s_differing" % where)
    return pct(share) + ("" if count is None else " (%d px)" % count)


def class_table(runs, scenes):
    """Rows per configuration: the mean band and away shares over the class's scenes and the worst scene."""
    by_config = {}
    for r in runs:
        by_config.setdefault(r["config"], []).append(r)
    L = ["| config | scenes | within 2 px of shadow edges (mean) | away from them (mean) | away, worst scene | "
         "away, differing pixels (sum) | all pixels (mean) |", "|---|---:|---:|---:|---|---:|---:|"]
    for config in sorted(by_config, key=config_key):
        rs = by_config[config]
        mean = lambda k: sum(r["errors"][k] for r in rs) / len(rs)
        worst = max(rs, key=lambda r: r["errors"]["shadow_disagreement_away"])
        counts = [r["errors"].get("shadow_away_differing") for r in rs]
        L.append("| %s | %d of %d | %s | %s | %s (`%s`) | %s | %s |" % (
            config, len(rs), len(scenes), pct(mean("shadow_disagreement_band")), pct(mean("shadow_disagreement_away")),
            pct(worst["errors"]["shadow_disagreement_away"]), worst["scene"],
            "—" if None in counts else "%d" % sum(counts), pct(mean("shadow_disagreement"))))
    return L + [""]


def scene_table(results, runs, configs):
    """Scenes (rows) by configurations (band and away columns)."""
    by = {(r["scene"], r["config"]): r for r in runs}
    head = ["| scene | class |"] + [" %s: band | %s: away |" % (c, c) for c in configs]
    L = ["".join(head), "|---|---|" + "---:|---:|" * len(configs)]
    for s in results["scenes"]:
        cells = []
        for c in configs:
            r = by.get((s["name"], c))
            cells += ["—", "—"] if r is None else [share_px(r["errors"], "band"), share_px(r["errors"], "away")]
        L.append("| %s | %s | %s |" % (s["name"], s["class"], " | ".join(cells)))
    return L + [""]


def homes_rows(before, after, config=MAP_DEFAULTS):
    """Per Sweet Home 3D home in both runs: (scene, before errors, after errors, rays errors or None)."""
    b = {r["scene"]: r["errors"] for r in shadow_runs(before) if r["config"] == config and r["class"] == "sh3d"}
    a = {r["scene"]: r["errors"] for r in shadow_runs(after) if r["config"] == config and r["class"] == "sh3d"}
    rays = {r["scene"]: r["errors"] for r in shadow_runs(after) if r["config"] == RAYS and r["class"] == "sh3d"}
    return [(s, b[s], a[s], rays.get(s)) for s in sorted(a) if s in b]


def homes_table(rows):
    L = ["| home | away, before | away, after | after / before | after ≤ half of before | band, before | "
         "band, after | rays: away | rays: band |", "|---|---:|---:|---:|---|---:|---:|---:|---:|"]
    for scene, b, a, rays in rows:
        ba, aa = b["shadow_disagreement_away"], a["shadow_disagreement_away"]
        ratio = "—" if ba == 0 else "%.2f" % (aa / ba)
        L.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
            scene, share_px(b, "away"), share_px(a, "away"), ratio, "yes" if half_holds(ba, aa) else "**no**",
            share_px(b, "band"), share_px(a, "band"), "—" if rays is None else share_px(rays, "away"),
            "—" if rays is None else share_px(rays, "band")))
    held = sum(half_holds(b["shadow_disagreement_away"], a["shadow_disagreement_away"]) for _, b, a, _ in rows)
    rays_zero = [s for s, _, _, r in rows if r is not None and r["shadow_disagreement_away"] == 0]
    L += ["", "After ≤ half of before away from the edges: %d of %d homes. Rays 0 away from the edges: %d of %d homes."
          % (held, len(rows), len(rays_zero), len(rows)), ""]
    return L


def run_line(results, commit, what):
    a, b = results["machine_start"], results["machine_end"]
    return "- %s: %s, commit `%s`; %d×%d pixels; load average at the start %s, at the end %s" % (
        what, results["date"], commit, results["width"], results["height"], " ".join(a["loadavg"].split()[:3]),
        " ".join(b["loadavg"].split()[:3]))


def section(after, commit, before=None, before_commit=None):
    runs = shadow_runs(after)
    L = [BEGIN, "", run_line(after, commit, "run")]
    if before is not None:
        L.append(run_line(before, before_commit, "before"))
    L.append("")
    for cls, title in accuracy_report.CLASSES:
        scenes = [s for s in after["scenes"] if s["class"] == cls]
        L += ["#### %s" % title, ""]
        if not scenes:
            L += ["No scene of this class was available in this run.", ""]
            continue
        L += class_table([r for r in runs if r["class"] == cls], scenes)
    rays_runs = [r for r in runs if r["config"] == RAYS]
    nonzero = [r["scene"] for r in rays_runs if r["errors"]["shadow_disagreement_away"] != 0]
    L += ["Rays away from the edges: 0 on %d of %d scenes%s." % (
        len(rays_runs) - len(nonzero), len(rays_runs), "" if not nonzero else " (not 0: %s)" % ", ".join(nonzero)), ""]
    L += ["#### Every scene: map at its defaults and rays", ""]
    L += scene_table(after, runs, [MAP_DEFAULTS, RAYS])
    if before is not None:
        L += ["#### Sweet Home 3D homes before and after (map at its defaults: %s)" % MAP_DEFAULTS, ""]
        L += homes_table(homes_rows(before, after))
    return "\n".join(L + [END])


def write_doc(path, text):
    doc = open(path).read()
    if BEGIN in doc and END in doc:
        doc = doc[:doc.index(BEGIN)] + text + doc[doc.index(END) + len(END):]
    elif accuracy_report.BEGIN in doc:  # before the run-time section
        i = doc.index(accuracy_report.BEGIN)
        doc = doc[:i] + text + "\n\n" + doc[i:]
    else:
        doc = doc.rstrip("\n") + "\n\n" + text + "\n"
    with open(path, "w") as f:
        f.write(doc)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("results")
    ap.add_argument("--before")
    ap.add_argument("--doc")
    ap.add_argument("--csv")
    ap.add_argument("--commit", default="unknown")
    ap.add_argument("--before-commit", default="unknown")
    a = ap.parse_args()
    after = json.load(open(a.results))
    before = json.load(open(a.before)) if a.before else None
    if a.csv:
        accuracy_report.write_csv(after, a.csv)
    text = section(after, a.commit, before, a.before_commit)
    if a.doc:
        write_doc(a.doc, text)
    else:
        print(text)


if __name__ == "__main__":
    main()
