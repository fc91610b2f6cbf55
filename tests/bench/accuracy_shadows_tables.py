#!/usr/bin/env python3
"""bench/accuracy_shadows.py on two hand-made runs (no renderer): three homes and a room measured
before and after, with shares and pixel counts chosen so every answer is known: the per-class means
and worst scene, the per-home ratio and its "after at most half of before" verdict (met, missed,
and 0 before and after), the rays counts, and the doc section replaced between its markers.
Exit 0 = pass."""
import os
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "bench"))
import accuracy_shadows as acs  # noqa: E402

failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


def errors(band, away, band_px=1000, away_px=100000):
    return {"shadow_disagreement": (band * band_px + away * away_px) / (band_px + away_px),
            "shadow_disagreement_band": band, "shadow_disagreement_away": away,
            "shadow_band_pixels": band_px, "shadow_band_differing": round(band * band_px),
            "shadow_away_pixels": away_px, "shadow_away_differing": round(away * away_px)}


def run(scene, cls, config, e):
    return {"scene": scene, "class": cls, "config": config, "group": "shading", "status": "ok", "errors": e}


def results(runs, scenes):
    machine = {"loadavg": "1.00 2.00 3.00 1/100 1"}
    return {"date": "2026-01-01T00:00:00Z", "width": 640, "height": 360, "machine_start": machine,
            "machine_end": machine, "scenes": [{"name": n, "class": c} for n, c in scenes],
            "runs": runs + [{"scene": "sh3d_A", "class": "sh3d", "config": "phong", "group": "shading",
                             "status": "ok", "errors": {"shadow_disagreement_band": None}},
                            {"scene": "sh3d_A", "class": "sh3d", "config": "reference", "group": "reference",
                             "status": "ok"}]}


def main():
    scenes = [("sh3d_A", "sh3d"), ("sh3d_B", "sh3d"), ("sh3d_C", "sh3d"), ("room", "rooms")]
    d, r = acs.MAP_DEFAULTS, acs.RAYS
    before = results([run("sh3d_A", "sh3d", d, errors(0.05, 0.0010)),
                      run("sh3d_B", "sh3d", d, errors(0.04, 0.0020)),
                      run("sh3d_C", "sh3d", d, errors(0.03, 0.0))], scenes)
    after = results([run("sh3d_A", "sh3d", d, errors(0.04, 0.0005)),   # exactly half: met
                     run("sh3d_B", "sh3d", d, errors(0.02, 0.0011)),   # 0.55 of before: missed
                     run("sh3d_C", "sh3d", d, errors(0.01, 0.0)),      # 0 and 0: met
                     run("sh3d_A", "sh3d", r, errors(0.002, 0.0)),
                     run("sh3d_B", "sh3d", r, errors(0.001, 0.0)),
                     run("sh3d_C", "sh3d", r, errors(0.0, 0.00002)),   # 2 pixels away: not 0
                     run("sh3d_A", "sh3d", "phong shadows 512 pcf1", errors(0.1, 0.004)),
                     run("room", "rooms", d, errors(0.01, 0.0003))], scenes)

    check(len(acs.shadow_runs(after)) == 8, "the run without a split and the reference are left out")
    check([acs.config_key(c)[0] for c in (d, "phong shadows 512 pcf1", r)] == [0, 0, 1], "rays sort last")
    check(sorted([d, r, "phong shadows 512 pcf1"], key=acs.config_key) == ["phong shadows 512 pcf1", d, r],
          "maps by size, then rays")

    rows = acs.homes_rows(before, after)
    check([s for s, _, _, _ in rows] == ["sh3d_A", "sh3d_B", "sh3d_C"], "one row per home in both runs")
    verdicts = [acs.half_holds(b["shadow_disagreement_away"], a["shadow_disagreement_away"]) for _, b, a, _ in rows]
    check(verdicts == [True, False, True], "half rule: %s" % verdicts)
    table = "\n".join(acs.homes_table(rows))
    check("| sh3d_A | 0.1000 % (100 px) | 0.0500 % (50 px) | 0.50 | yes |" in table, "home A's row:\n" + table)
    check("| sh3d_B | 0.2000 % (200 px) | 0.1100 % (110 px) | 0.55 | **no** |" in table, "home B's row:\n" + table)
    check("| sh3d_C | 0.0000 % (0 px) | 0.0000 % (0 px) | — | yes |" in table, "home C's row:\n" + table)
    check("2 of 3 homes" in table and "Rays 0 away from the edges: 2 of 3 homes" in table, "summary:\n" + table)

    sh3d = [x for x in acs.shadow_runs(after) if x["class"] == "sh3d"]
    ct = "\n".join(acs.class_table(sh3d, scenes[:3]))
    # Map defaults over the three homes: band (4 + 2 + 1) / 3 %, away (0.05 + 0.11 + 0) / 3 %, worst B, 160 px.
    check(("| " + d + " | 3 of 3 | 2.3333 % | 0.0533 % | 0.1100 % (`sh3d_B`) | 160 |") in ct, "class row:\n" + ct)
    check(ct.index("512 pcf1") < ct.index(d) < ct.index(r), "class table order:\n" + ct)

    text = acs.section(after, "abc", before, "def")
    check("Rays away from the edges: 0 on 2 of 3 scenes (not 0: sh3d_C)." in text, "rays line")
    check("#### Sweet Home 3D homes before and after" in text and "commit `def`" in text, "before part")
    check("No scene of this class was available in this run." in text, "absent classes said so")
    with tempfile.TemporaryDirectory() as out:
        doc = os.path.join(out, "accuracy.md")
        with open(doc, "w") as f:
            f.write("# Accuracy\n\nintro\n\n%s\nold\n%s\n\ntail\n" % (acs.BEGIN, acs.END))
        acs.write_doc(doc, text)
        acs.write_doc(doc, text)  # twice: replaced, not appended
        body = open(doc).read()
        check(body.count(acs.BEGIN) == 1 and "old" not in body and body.endswith("\n\ntail\n"), "doc markers")

    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
