#!/usr/bin/env python3
"""Soak benchmark: does the server hold steady under sustained mixed traffic?

16 keep-alive connections (--connections) send requests back to back for 2 minutes (--seconds)
against the real server (a fresh `roomrender serve` on a free loopback port, or --port P for one
already running). Each connection cycles through a fixed mix, valid and invalid:

  render        POST /v1/render, examples/studio.json at 320x240 flat          -> 200
  render_json   the same with Accept: application/json (counts, warnings)      -> 200
  livez         GET /livez                                                     -> 200
  pipelines     GET /v1/pipelines                                              -> 200
  bad_json      POST /v1/render with a body that is not JSON                   -> 400
  bad_field     POST /v1/render with options.width = -5                        -> 422
  no_route      GET /v1/nothing-here                                           -> 404

A sampler reads process_resident_memory_bytes from /metrics once a second on a connection of its own.
Reported: for the 30 s after a 30 s warm-up and for the last 30 s of the run, the throughput
(answers/s), the p99 and median latency (request written -> answer read), the RSS at the end of
each window, and apart the renders answered 200 (rate, p99) and the 503s, with the change from the first window to the last (goal: each within 10 %); the count
of each status per request kind, answers other than expected (503s from load shedding counted
apart) and connection errors. Results go to bench/results/soak.json (under --label) and
bench/results/soak.md. Standard library only (http.client): one client process, so at high rates the
client, not the server, may set the throughput; it is the same client in both windows.

usage: bench/soak.py [--binary build/roomrender] [--port P] [--seconds 120] [--warmup 30]
                     [--window 30] [--connections 16] [--label main]
"""
import argparse
import collections
import http.client
import json
import os
import statistics
import subprocess
import sys
import threading
import time

from bench_server import start_server

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
HOST = "127.0.0.1"
GOAL_DRIFT = 0.10


def requests_mix():
    """[(kind, method, path, body, headers, expected status)] in the order each connection cycles."""
    with open(os.path.join(ROOT, "examples", "studio.json")) as f:
        studio = json.load(f)
    studio.setdefault("options", {}).update({"width": 320, "height": 240, "shading": "flat"})
    bad = json.loads(json.dumps(studio))
    bad["options"]["width"] = -5
    js = {"Content-Type": "application/json"}
    render = json.dumps(studio).encode()
    return [
        ("render", "POST", "/v1/render", render, js, 200),
        ("livez", "GET", "/livez", None, {}, 200),
        ("bad_json", "POST", "/v1/render", b'{"scene": {"walls": [', js, 400),
        ("render_json", "POST", "/v1/render", render, dict(js, Accept="application/json"), 200),
        ("bad_field", "POST", "/v1/render", json.dumps(bad).encode(), js, 422),
        ("pipelines", "GET", "/v1/pipelines", None, {}, 200),
        ("no_route", "GET", "/v1/nothing-here", None, {}, 404),
    ]


class Client(threading.Thread):
    """One keep-alive connection sending the mix back to back until `stop_at`; records
    (end time, latency s, kind, status or error) per request."""

    def __init__(self, port, mix, offset, stop_at):
        super().__init__(daemon=True)
        self.port, self.mix, self.offset, self.stop_at = port, mix, offset, stop_at
        self.records = []

    def run(self):
        conn = None
        i = self.offset
        while time.monotonic() < self.stop_at:
            kind, method, path, body, headers, _ = self.mix[i % len(self.mix)]
            i += 1
            if conn is None:
                conn = http.client.HTTPConnection(HOST, self.port, timeout=30)
            t0 = time.monotonic()
            try:
                conn.request(method, path, body=body, headers=headers)
                res = conn.getresponse()
                res.read()
                outcome = res.status
                if res.getheader("Connection", "").lower() == "close":
                    conn.close()
                    conn = None
            except (OSError, http.client.HTTPException) as e:
                outcome = type(e).__name__
                conn.close()
                conn = None
            t1 = time.monotonic()
            self.records.append((t1, t1 - t0, kind, outcome))
        if conn is not None:
            conn.close()


class Sampler(threading.Thread):
    """RSS from /metrics every second: [(time, MiB)]."""

    def __init__(self, port, stop_at):
        super().__init__(daemon=True)
        self.port, self.stop_at = port, stop_at
        self.samples = []
        self.failures = 0

    def run(self):
        while time.monotonic() < self.stop_at + 0.5:
            t = time.monotonic()
            try:
                conn = http.client.HTTPConnection(HOST, self.port, timeout=10)
                conn.request("GET", "/metrics")
                text = conn.getresponse().read().decode()
                conn.close()
                rss = next(float(l.split()[-1]) / 2**20 for l in text.splitlines()
                           if l.startswith("process_resident_memory_bytes"))
                self.samples.append((t, rss))
            except (OSError, http.client.HTTPException, StopIteration, ValueError):
                self.failures += 1
            time.sleep(max(0.0, 1.0 - (time.monotonic() - t)))


def percentile(values, p):
    if not values:
        return None
    s = sorted(values)
    return s[min(len(s) - 1, int(round(p / 100.0 * (len(s) - 1))))]


def window(records, samples, start, end):
    """Throughput, latencies and the last RSS sample of [start, end) (times relative to the run)."""
    inside = [r for r in records if start <= r[0] < end]
    lat = [r[1] for r in inside]
    rendered = [r[1] for r in inside if r[2].startswith("render") and r[3] == 200]
    rss = [m for t, m in samples if t < end]
    return {"from_s": start, "to_s": end, "answers": len(lat), "per_s": len(lat) / (end - start),
            "p99_ms": percentile(lat, 99) * 1000 if lat else None,
            "median_ms": statistics.median(lat) * 1000 if lat else None,
            "renders_per_s": len(rendered) / (end - start),
            "render_p99_ms": percentile(rendered, 99) * 1000 if rendered else None,
            "shed_503": sum(1 for r in inside if r[3] == 503),
            "rss_mib": rss[-1] if rss else None}


def drift(a, b):
    return None if a in (None, 0) or b is None else (b - a) / a


def summarize(records, samples, seconds, warmup, window_s, mix):
    expected = {m[0]: m[5] for m in mix}
    by_kind = collections.defaultdict(collections.Counter)
    unexpected = shed = errors = 0
    for _, _, kind, outcome in records:
        by_kind[kind][str(outcome)] += 1
        if isinstance(outcome, str):
            errors += 1
        elif outcome == 503:
            shed += 1
        elif outcome != expected[kind]:
            unexpected += 1
    first = window(records, samples, warmup, warmup + window_s)
    last = window(records, samples, seconds - window_s, seconds)
    changes = {k: drift(first[k], last[k]) for k in ("per_s", "p99_ms", "rss_mib")}
    return {"after_warmup": first, "end": last, "change": changes,
            "flat": all(c is not None and abs(c) <= GOAL_DRIFT for c in changes.values()),
            "per_10s": [window(records, samples, s, s + 10)["per_s"] for s in range(0, int(seconds), 10)],
            "statuses": {k: dict(c) for k, c in sorted(by_kind.items())},
            "total": len(records), "unexpected": unexpected, "shed_503": shed, "errors": errors}


def fmt(v, spec=".1f"):
    return "–" if v is None else format(v, spec)


def pct(v):
    return "–" if v is None else f"{v * 100:+.1f} %"


def markdown(results):
    out = ["# Soak benchmark", "",
           "Written by `bench/soak.py`; loopback; a fixed mix of valid and invalid requests (render, render as "
           "JSON, /livez, /v1/pipelines, bad JSON 400, bad field 422, unknown route 404) on keep-alive "
           "connections back to back. Windows: the --window seconds (30) after the warm-up, and the last ones. "
           f"Goal: throughput, p99 and RSS each within {GOAL_DRIFT * 100:.0f} % from the first window to the last.", ""]
    for label, run in results.items():
        s = run["summary"]
        a, e, c = s["after_warmup"], s["end"], s["change"]
        out += [f"## {label}", "",
                f"{run['binary']}, {run['when']}, {run['connections']} connections, {run['seconds']:.0f} s "
                f"({run['warmup']:.0f} s warm-up), load {run['load']}", "",
                "| window | answers/s | median ms | p99 ms | RSS MiB | renders (200)/s | render p99 ms | 503s |",
                "|---|---|---|---|---|---|---|---|",
                *[f"| {w['from_s']:.0f}–{w['to_s']:.0f} s | {w['per_s']:.0f} | {fmt(w['median_ms'])} | {fmt(w['p99_ms'])} | "
                  f"{fmt(w['rss_mib'])} | {w['renders_per_s']:.0f} | {fmt(w['render_p99_ms'])} | {w['shed_503']} |" for w in (a, e)],
                f"| change | {pct(c['per_s'])} | | {pct(c['p99_ms'])} | {pct(c['rss_mib'])} | | | |", "",
                f"Flat within {GOAL_DRIFT * 100:.0f} %: **{'yes' if s['flat'] else 'no'}**. {s['total']} answers; "
                f"other than expected: {s['unexpected']}; 503 (shed): {s['shed_503']}; connection errors: {s['errors']}; "
                f"/metrics reads failed: {run['metrics_failures']}.", "",
                "Answers/s per 10 s: " + ", ".join(f"{x:.0f}" for x in s["per_10s"]), "",
                "Statuses: " + "; ".join(f"{k} " + ", ".join(f"{st} ×{n}" for st, n in v.items())
                                         for k, v in s["statuses"].items()), ""]
    return "\n".join(out)


def write_results(path_json, path_md, label, run):
    results = {}
    if os.path.exists(path_json):
        with open(path_json) as f:
            results = json.load(f)
    results[label] = run
    with open(path_json, "w") as f:
        json.dump(results, f, indent=1)
    with open(path_md, "w") as f:
        f.write(markdown(results) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--binary", default=os.path.join(ROOT, "build", "roomrender"))
    parser.add_argument("--port", type=int, help="soak this already-running server (loopback) instead")
    parser.add_argument("--seconds", type=float, default=120.0)
    parser.add_argument("--warmup", type=float, default=30.0)
    parser.add_argument("--window", type=float, default=30.0, help="length of the two measured windows")
    parser.add_argument("--connections", type=int, default=16)
    parser.add_argument("--label", default="run")
    parser.add_argument("--out", default=os.path.join(ROOT, "bench", "results", "soak.json"))
    parser.add_argument("--md", default=os.path.join(ROOT, "bench", "results", "soak.md"))
    args = parser.parse_args()
    if args.seconds < args.warmup + 2 * args.window:
        sys.exit("--seconds must leave two --window windows after the warm-up")
    mix = requests_mix()
    server = None
    if args.port:
        port, binary = args.port, f"server already running on port {args.port}"
    else:
        server, port = start_server(args.binary)
        binary = f"`{os.path.relpath(args.binary, ROOT)}`"
    try:
        t0 = time.monotonic()
        stop_at = t0 + args.seconds
        clients = [Client(port, mix, i, stop_at) for i in range(args.connections)]
        sampler = Sampler(port, stop_at)
        for t in [sampler, *clients]:
            t.start()
        for t in [*clients, sampler]:
            t.join(timeout=args.seconds + 60)
    finally:
        if server is not None:
            server.terminate()
            server.wait(timeout=30)
    records = [(r[0] - t0, *r[1:]) for c in clients for r in c.records]
    samples = [(t - t0, m) for t, m in sampler.samples]
    run = {"binary": binary, "when": time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime()),
           "load": " ".join(f"{x:.1f}" for x in os.getloadavg()), "connections": args.connections,
           "seconds": args.seconds, "warmup": args.warmup, "metrics_failures": sampler.failures,
           "rss_samples": [[round(t, 1), round(m, 1)] for t, m in samples],
           "window": args.window,
           "summary": summarize(records, samples, args.seconds, args.warmup, args.window, mix)}
    write_results(args.out, args.md, args.label, run)
    print(markdown({args.label: run}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
