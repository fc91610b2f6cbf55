#!/usr/bin/env python3
"""Stored-scene throughput against one server: N distinct scenes stored with POST /v1/scenes from C
keep-alive connections at once, then each read back R times with GET /v1/scenes/{id} (shuffled).
In: the server's base URL. Out: one JSON line {writes, reads, concurrency, write_per_s,
write_p50_ms, write_p99_ms, read_per_s, read_p50_ms, read_p99_ms, errors}. Used by bench/store_rate.sh.
Usage: bench/store_rate.py URL [--scenes N] [--reads-per-scene R] [--concurrency C] [--seed S]
"""
import argparse
import http.client
import json
import random
import statistics
import threading
import time
import urllib.parse


def scene(rng, i, seed):
    solids = [{"type": "box", "id": "floor", "color": "#808080", "center": [0, 0], "size": [8, 0.1, 8]}]
    for k in range(4):
        solids.append({"type": "box", "id": f"b{seed}_{i}_{k}", "color": "#%06x" % rng.randrange(1 << 24),
                       "center": [round(rng.uniform(-3, 3), 3), round(rng.uniform(-3, 3), 3)],
                       "size": [round(rng.uniform(0.2, 1.5), 3)] * 3})
    return json.dumps({"version": 1, "background": "#202428", "solids": solids}).encode()


def run(base, jobs, concurrency):
    """jobs: [(method, path, body)]; returns (latencies in s, seconds, answers as (status, body))."""
    url = urllib.parse.urlsplit(base)
    latencies, answers = [None] * len(jobs), [None] * len(jobs)
    next_job, lock = [0], threading.Lock()

    def worker():
        conn = http.client.HTTPConnection(url.hostname, url.port, timeout=60)
        while True:
            with lock:
                j = next_job[0]
                next_job[0] += 1
            if j >= len(jobs):
                break
            method, path, body = jobs[j]
            started = time.perf_counter()
            try:
                conn.request(method, path, body=body, headers={"Content-Type": "application/json"} if body else {})
                answer = conn.getresponse()
                answers[j] = (answer.status, answer.read())
            except (OSError, http.client.HTTPException):
                conn.close()
                conn = http.client.HTTPConnection(url.hostname, url.port, timeout=60)
                answers[j] = (0, b"")
            latencies[j] = time.perf_counter() - started
        conn.close()

    threads = [threading.Thread(target=worker) for _ in range(concurrency)]
    started = time.perf_counter()
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    return latencies, time.perf_counter() - started, answers


def p99(values):
    return statistics.quantiles(values, n=100)[98]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("url")
    parser.add_argument("--scenes", type=int, default=1000)
    parser.add_argument("--reads-per-scene", type=int, default=4)
    parser.add_argument("--concurrency", type=int, default=4)
    parser.add_argument("--seed", type=int, default=int(time.time()))
    args = parser.parse_args()
    rng = random.Random(args.seed)
    writes = [("POST", "/v1/scenes", scene(rng, i, args.seed)) for i in range(args.scenes)]
    w_lat, w_s, w_ans = run(args.url, writes, args.concurrency)
    ids = [json.loads(body)["id"] for status, body in w_ans if status in (200, 201)]
    errors = sum(1 for status, _ in w_ans if status != 201)
    if not ids:
        raise SystemExit(f"store_rate: no scene stored; first answer {w_ans[0]}")
    reads = [("GET", f"/v1/scenes/{i}", None) for i in ids for _ in range(args.reads_per_scene)]
    rng.shuffle(reads)
    r_lat, r_s, r_ans = run(args.url, reads, args.concurrency)
    errors += sum(1 for status, _ in r_ans if status != 200)
    ms = lambda v: round(v * 1000, 2)
    print(json.dumps({"writes": len(writes), "reads": len(reads), "concurrency": args.concurrency,
                      "write_per_s": round(len(writes) / w_s, 1), "write_p50_ms": ms(statistics.median(w_lat)),
                      "write_p99_ms": ms(p99(w_lat)), "read_per_s": round(len(reads) / r_s, 1),
                      "read_p50_ms": ms(statistics.median(r_lat)), "read_p99_ms": ms(p99(r_lat)),
                      "errors": errors}))


if __name__ == "__main__":
    main()
