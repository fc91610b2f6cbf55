#!/usr/bin/env python3
"""bench/perf.sh's report code on a tiny recorded run (tests/bench/perf_tiny.json: four scenes at
160x90, two rounds of one frame, painter and BSP included): every ratio the performance targets name
is computed and judged, the tables list every scene, and each plot is well-formed SVG with a legend.
No timing and no peers: it checks the arithmetic and the writing, not any renderer. Exit 0 = pass."""
import json
import os
import statistics
import sys
import tempfile
import xml.etree.ElementTree as ET

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "bench"))
import perf_report  # noqa: E402

failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


def expected_ratio(scene, num, den, threads):
    """The ratio computed here independently: per round ours / peer, then the median."""
    a, b = scene["runs"][num][threads], scene["runs"][den][threads]
    return statistics.median(x["ms"] / y["ms"] for x, y in zip(a, b) if x.get("ms") and y.get("ms"))


def main():
    results = json.load(open(os.path.join(HERE, "perf_tiny.json")))
    with tempfile.TemporaryDirectory() as out:
        doc = os.path.join(out, "performance.md")
        perf_report.write_report(results, doc)
        text = open(doc).read()
        rows = {line.split("|")[1].strip(): line for line in text.splitlines() if line.startswith("| ")}
        for scene in results["scenes"]:
            check(scene["name"] in text, "scene %s missing from the report" % scene["name"])
            for key, label, num, den, _ in perf_report.RATIOS:
                want = perf_report.fmt_x(expected_ratio(scene, num, den, "2"))
                got = perf_report.fmt_x(perf_report.ratio_of(scene, key, "2"))
                check(want == got, "%s %s: %s, expected %s" % (scene["name"], key, got, want))
                check(label in text, "ratio column %r missing" % label)
        # Every performance target has a row in the targets table, each with a verdict.
        targets = [l for l in text.split("## Targets")[1].split("## Ratios")[0].splitlines() if l.startswith("| ") and
                   "verdict" not in l]
        check(len(targets) == 10,
              "expected 10 target rows (6 ratios, 2 speed-ups, painter, bsp), got %d" % len(targets))
        check(all(l.rstrip(" |").endswith(("met", "met**", "not measured in this run")) for l in targets),
              "a target row without a verdict")
        # The room scene's flat ratio is judged against 0.4, the 10^4 soup's is not judged.
        room = next(s for s in results["scenes"] if s["kind"] == "room")
        check(perf_report.flat_target(room) == 0.4, "room flat target")
        check(perf_report.flat_target(next(s for s in results["scenes"] if s["name"] == "soup_1e4")) is None,
              "the 10^4 soup has no flat target")
        check("Quick smoke run" not in text, "a full run must not carry the quick banner")
        check("load average" in text and "%.2f" % results["load"]["start"][0] in text, "load average missing")
        for name in ("frames", "ratios", "speedup", "soups"):
            path = os.path.join(out, "performance", name + ".svg")
            check(os.path.exists(path), name + ".svg not written")
            if os.path.exists(path):
                root = ET.parse(path).getroot()
                texts = " ".join(t.text or "" for t in root.iter("{http://www.w3.org/2000/svg}text"))
                check("ours flat" in texts or "flat / llvmpipe" in texts, name + ".svg has no legend")
                check(name == "speedup" or "log scale" in texts, name + ".svg should have a log axis")
        check("![" in text and "performance/frames.svg" in text, "plots not linked from the report")
        check(perf_report.ratio_table_text(results).count("\n") == 2 * len(results["scenes"]),
              "console table rows")
        results["quick"] = True
        perf_report.write_report(results, doc)
        check("Quick smoke run" in open(doc).read(), "a quick run must say so")
    for f in failures:
        print("FAIL:", f)
    print("perf_report_smoke: %d checks failed" % len(failures) if failures else "perf_report_smoke: ok")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
