#!/usr/bin/env bash
# Smoke test of the accuracy benchmark (bench/accuracy.sh), so it does not rot: bench_accuracy on two
# tiny scenes (examples/tri_intersecting.json and bench_gen_scenes' 1000-triangle soup at 96x72, one
# frame, ../shared absent), then the report script. Checks every configuration ran and was measured, the known answers on this scene (zbuffer,
# BSP and painter-newell exact away from edges; painter-mean wrong: no order of whole triangles is
# right for two triangles that pierce each other; exact shadow rays decide as the reference away from
# its shadow edges), that the CSV, the doc section and plots exist, that --configs keeps only the
# configurations named, and that the shadow-error section (bench/accuracy_shadows.py) is written. Then
# the textured class alone (the grazing floor's checkerboard and the papered studio): one run per
# texture filter with its texture error, and a report of it that rewrites the texture table alone.
#   tests/bench/accuracy_smoke.sh BENCH_ACCURACY_EXE BENCH_GEN_SCENES_EXE SOURCE_DIR
set -euo pipefail
exe=$1 gen=$2 src=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$gen" --dir "$work/scenes" --out "$work/scenes/manifest.json" --soups 1000 >/dev/null
"$exe" --out "$work/a.json" --only tri_intersecting,gen_soup --size 96x72 --frames 1 --shared "$work/no-shared" \
  --gen-manifest "$work/scenes/manifest.json" 2>"$work/log"
grep -q "skipped: no $work/no-shared" "$work/log" || { cat "$work/log"; echo "no skip message for absent ../shared"; exit 1; }
python3 "$src/bench/accuracy_report.py" "$work/a.json" --csv "$work/a.csv" --doc "$work/accuracy.md" \
  --svg-dir "$work/svg" --commit smoke
"$exe" --out "$work/rays.json" --only tri_intersecting --size 96x72 --frames 1 --shared "$work/no-shared" \
  --configs "shadows rays" 2>/dev/null
python3 "$src/bench/accuracy_shadows.py" "$work/a.json" --before "$work/a.json" --doc "$work/accuracy.md" \
  --commit smoke --before-commit smoke
"$exe" --out "$work/tex.json" --only textured_ --size 96x72 --frames 1 --shared "$work/no-shared" 2>/dev/null
cp "$work/accuracy.md" "$work/before-textures.md"
python3 "$src/bench/accuracy_report.py" "$work/tex.json" --doc "$work/accuracy.md" --svg-dir "$work/svg" --commit smoke
python3 - "$work" <<'PY'
import csv, json, math, os, sys
work = sys.argv[1]
doc = json.load(open(os.path.join(work, "a.json")))
runs = {r["config"]: r for r in doc["runs"] if r["group"] != "reference" and r["scene"] == "tri_intersecting"}
assert [s["name"] for s in doc["scenes"]] == ["tri_intersecting", "gen_soup_1000"], doc["scenes"]
soup = [r for r in doc["runs"] if r["scene"] == "gen_soup_1000"]
assert len(soup) == len(runs) + 2 and all(r["status"] == "ok" for r in soup), soup  # + 2 reference rows
for name in ["zbuffer", "painter-mean", "painter-min", "painter-max", "painter-newell", "bsp w=1/4/-1 eps=1e-07",
             "gouraud", "phong", "phong shadows 2048 pcf1", "phong shadows 512 pcf1", "phong shadows 2048 pcf5",
             "phong shadows rays"]:
    r = runs[name]
    assert r["status"] == "ok" and r["frames"] == 1 and r["frame_ms"] > 0, r
    e = r["errors"]
    for k in ["visibility_all", "visibility_non_edge", "shadow_disagreement"]:
        assert e[k] is None or 0.0 <= e[k] <= 1.0, (name, k, e)
    assert e["rmse"] >= 0, (name, e)
for exact in ["zbuffer", "painter-newell", "bsp w=1/4/-1 eps=1e-07"]:
    assert runs[exact]["errors"]["visibility_non_edge"] == 0.0, (exact, runs[exact]["errors"])
assert runs["painter-mean"]["errors"]["visibility_non_edge"] > 0.01, runs["painter-mean"]["errors"]
assert runs["bsp w=1/4/-1 eps=1e-07"]["build_ms"] > 0, "the BSP build is reported apart from the frame"
for r in doc["runs"]:
    e = r.get("errors", {})
    if e.get("shadow_disagreement_band") is None:
        continue
    assert e["shadow_band_pixels"] + e["shadow_away_pixels"] == 96 * 72, (r["config"], e)
    for where in ["band", "away"]:
        n, d = e["shadow_%s_pixels" % where], e["shadow_%s_differing" % where]
        assert d <= n and math.isclose(e["shadow_disagreement_" + where], d / n if n else 0.0), (r["config"], e)
    if r["config"] == "phong shadows rays":  # the reference's own decisions away from its shadow edges
        assert e["shadow_away_differing"] == 0 and e["shadow_away_pixels"] > 0, (r["scene"], e)
rays_only = json.load(open(os.path.join(work, "rays.json")))["runs"]
assert [r["config"] for r in rays_only] == ["phong shadows rays", "reference"], rays_only
rows = list(csv.DictReader(open(os.path.join(work, "a.csv"))))
assert len(rows) == len(doc["runs"]), (len(rows), len(doc["runs"]))
md = open(os.path.join(work, "accuracy.md")).read()
assert "## Run time against error" in md and "tri_intersecting" in md
assert md.count("<!-- accuracy-shadows:begin -->") == 1 and md.index("accuracy-shadows:end") < md.index("accuracy-bench:begin")
assert "Rays away from the edges: 0 on 2 of 2 scenes." in md, md
for svg in ["classic_visibility.svg", "classic_shading.svg"]:
    assert open(os.path.join(work, "svg", svg)).read().startswith("<svg"), svg
tex = json.load(open(os.path.join(work, "tex.json")))
assert [s["name"] for s in tex["scenes"]] == ["textured_grazing_floor", "textured_papered_studio"], tex["scenes"]
floor_scene = tex["scenes"][0]  # lit by its ambient alone, its tiles a checkerboard without ../shared
assert floor_scene["lights"] == 0 and not floor_scene["light_added"] and "checkerboard" in floor_scene["source"], floor_scene
psnr = {}
for r in tex["runs"]:
    assert r["class"] == "textures" and r["status"] == "ok", r
    if r["group"] == "reference":
        continue
    e = r["errors"]
    assert r["group"] == "texture" and 0 < e["texture_pixels"] <= 96 * 72, r
    assert e["texture_psnr_db"] is None or math.isclose(e["texture_psnr_db"], 20 * math.log10(255 / e["texture_rmse"])), e
    psnr[(r["scene"], r["options"]["texture_filter"])] = e["texture_psnr_db"]
assert sorted(f for s, f in psnr if s == "textured_papered_studio") == ["anisotropic", "bilinear", "nearest", "trilinear"]
floor = {f: v for (s, f), v in psnr.items() if s == "textured_grazing_floor"}
assert floor["anisotropic"] > floor["trilinear"] > floor["nearest"], floor  # nearest aliases at a grazing angle
before = open(os.path.join(work, "before-textures.md")).read()
after = open(os.path.join(work, "accuracy.md")).read()
cut = lambda t: t[t.index("<!-- accuracy-bench:begin -->"):t.index("<!-- accuracy-bench:end -->")]
assert cut(before) == cut(after), "a run of the textured class alone rewrote the main section"
table = after[after.index("<!-- texture-bench:begin -->"):after.index("<!-- texture-bench:end -->")]
assert "| textured_grazing_floor |" in table and "| textured_papered_studio |" in table, table
print("accuracy smoke: %d runs checked" % (len(doc["runs"]) + len(tex["runs"])))

PY
