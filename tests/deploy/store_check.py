#!/usr/bin/env python3
"""Stores scenes and meshes through one URL and reads them back through another, for
tests/deploy/test_shared_store.sh. In: a base URL (nginx or a replica), a manifest file, tokens from
ROOMRENDER_TEST_TOKENS ("alice:TOKEN,bob:TOKEN"). Out: one summary line; exit 1 with the failures.
  reference URL MANIFEST N_SCENES N_MESHES   store generated content on a lone embedded-store server
                                             and record each item's id and canonical bytes (sha256)
  store URL MANIFEST      POST every item; ids must match the manifest; prints the replicas used
  check URL MANIFEST      GET every item; bytes must equal the manifest's (the embedded store's)
  race URL_A URL_B N      N fresh scenes, each stored at once by alice on A and bob on B: one
                          created, in both owners' lists; prints their ids
  release URL_A URL_B IDS each owner DELETEs: the scene stays for the other owner, then goes
  outage URL MANIFEST RENDER.json   the database is down or frozen: stores 503 + Retry-After
                          within 15 s, inline renders 200
  recovered URL MANIFEST  the database is back: a new scene stores (retried up to 30 s)
"""
import hashlib
import http.client
import json
import os
import random
import sys
import threading
import time
import urllib.parse

TIMEOUT = 30  # seconds per request; the outage checks use their own, shorter bound
OUTAGE_ANSWER_WITHIN = 15.0


def tokens():
    pairs = [p.split(":", 1) for p in os.environ["ROOMRENDER_TEST_TOKENS"].split(",")]
    return {name: token for name, token in pairs}


def request(base, method, path, body=None, content_type="application/json", token=None, timeout=TIMEOUT):
    """(status, headers dict with lower-case names, body bytes)."""
    url = urllib.parse.urlsplit(base)
    conn = http.client.HTTPConnection(url.hostname, url.port, timeout=timeout)
    headers = {"Content-Type": content_type} if body is not None else {}
    if token:
        headers["Authorization"] = "Bearer " + token
    try:
        conn.request(method, path, body=body, headers=headers)
        answer = conn.getresponse()
        return answer.status, {k.lower(): v for k, v in answer.getheaders()}, answer.read()
    finally:
        conn.close()


def make_mesh(rng, i):
    """A small pyramid with jittered apex: every index gives other content."""
    h = round(0.5 + i * 0.125 + rng.random() * 0.01, 4)
    return {"vertices": [[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1], [0.5, h, 0.5]],
            "faces": [[0, 1, 2, 3], [0, 4, 1], [1, 4, 2], [2, 4, 3], [3, 4, 0]]}


def make_scene(rng, i, mesh_ids, tag="s"):
    """A floor and a few boxes; every tenth scene places a stored mesh by ref."""
    solids = [{"type": "box", "id": "floor", "color": "#808080", "center": [0, 0], "size": [8, 0.1, 8]}]
    for k in range(1 + i % 4):
        solids.append({"type": "box", "id": f"{tag}{i}_{k}", "color": "#%06x" % rng.randrange(1 << 24),
                       "center": [round(rng.uniform(-3, 3), 3), round(rng.uniform(-3, 3), 3)],
                       "size": [round(rng.uniform(0.2, 1.5), 3)] * 3})
    if mesh_ids and i % 10 == 0:
        solids.append({"type": "mesh", "ref": mesh_ids[(i // 10) % len(mesh_ids)], "position": [1, 0, 1]})
    return {"version": 1, "background": "#202428", "solids": solids}


def store_item(base, kind, doc, token):
    status, headers, body = request(base, "POST", f"/v1/{kind}", json.dumps(doc).encode(), token=token)
    if status not in (200, 201):
        raise RuntimeError(f"POST /v1/{kind}: {status} {body[:300]!r}")
    return json.loads(body)["id"], headers.get("x-upstream", "")


def reference(base, manifest_path, n_scenes, n_meshes):
    rng = random.Random(21)
    token = tokens()["alice"]
    items = []
    for i in range(n_meshes):
        doc = make_mesh(rng, i)
        items.append({"kind": "meshes", "doc": doc, "id": store_item(base, "meshes", doc, token)[0]})
    mesh_ids = [it["id"] for it in items]
    for i in range(n_scenes):
        doc = make_scene(rng, i, mesh_ids)
        items.append({"kind": "scenes", "doc": doc, "id": store_item(base, "scenes", doc, token)[0]})
    for it in items:
        status, _, body = request(base, "GET", f"/v1/{it['kind']}/{it['id']}")
        if status != 200:
            raise RuntimeError(f"reference GET {it['kind']}/{it['id']}: {status}")
        it["sha256"] = hashlib.sha256(body).hexdigest()
    json.dump(items, open(manifest_path, "w"))
    print(f"store_check: reference holds {n_scenes} scenes and {n_meshes} meshes")


def store(base, manifest_path):
    items = json.load(open(manifest_path))
    token = tokens()["alice"]
    upstreams, wrong = set(), []
    for it in items:  # meshes first: the manifest lists them before the scenes that place them
        got, upstream = store_item(base, it["kind"], it["doc"], token)
        upstreams.add(upstream)
        if got != it["id"]:
            wrong.append(f"{it['kind']} {got} != {it['id']}")
    if wrong:
        sys.exit(f"store_check: FAIL: ids differ from the embedded store's: {wrong[:5]}")
    print(f"store_check: stored {len(items)} items through {len(upstreams)} replicas")
    if len(upstreams) < 2:
        sys.exit("store_check: FAIL: every store went to one replica, so reads elsewhere prove nothing")


def check(base, manifest_path):
    items = json.load(open(manifest_path))
    failures, upstreams = [], set()
    for it in items:
        status, headers, body = request(base, "GET", f"/v1/{it['kind']}/{it['id']}")
        upstreams.add(headers.get("x-upstream", ""))
        if status != 200:
            failures.append(f"{it['kind']}/{it['id']}: {status}")
        elif hashlib.sha256(body).hexdigest() != it["sha256"]:
            failures.append(f"{it['kind']}/{it['id']}: bytes differ")
    if failures:
        sys.exit(f"store_check: FAIL: {len(failures)} of {len(items)} not read back: {failures[:5]}")
    print(f"store_check: all {len(items)} items read back byte-identical through {len(upstreams)} replicas")


def race(base_a, base_b, n):
    who = tokens()
    rng = random.Random(2121)
    for i in range(n):
        doc = json.dumps(make_scene(rng, i, [], tag=f"race{time.time_ns()}_")).encode()
        barrier, answers = threading.Barrier(2), {}

        def put(name, base):
            barrier.wait()
            answers[name] = request(base, "POST", "/v1/scenes", doc, token=who[name])

        threads = [threading.Thread(target=put, args=a) for a in (("alice", base_a), ("bob", base_b))]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        statuses = sorted(a[0] for a in answers.values())
        receipts = [json.loads(a[2]) for a in answers.values() if a[0] in (200, 201)]
        if statuses != [200, 201] or len({r["id"] for r in receipts}) != 1:
            sys.exit(f"store_check: FAIL: race {i}: statuses {statuses}, receipts {receipts}")
        if sum(r["created"] for r in receipts) != 1:
            sys.exit(f"store_check: FAIL: race {i}: created flags {[r['created'] for r in receipts]}")
        sid = receipts[0]["id"]
        for name, base in (("alice", base_a), ("bob", base_b)):
            status, _, body = request(base, "GET", "/v1/scenes?limit=1000", token=who[name])
            listed = [s["id"] for s in json.loads(body)["scenes"]] if status == 200 else []
            if sid not in listed:
                sys.exit(f"store_check: FAIL: race {i}: {name}'s list ({status}) lacks {sid}")
        print(sid)  # the shell checks the database's rows for these ids
    print(f"store_check: {n} concurrent double stores: one created each, listed for both owners", file=sys.stderr)


def release(base_a, base_b, ids_path):
    """Each owner drops its reference: the scene stays while the other holds one, then goes."""
    who = tokens()
    for sid in open(ids_path).read().split():
        status, _, _ = request(base_b, "DELETE", f"/v1/scenes/{sid}", token=who["alice"])
        kept, _, _ = request(base_a, "GET", f"/v1/scenes/{sid}")
        if status != 204 or kept != 200:
            sys.exit(f"store_check: FAIL: {sid}: alice's DELETE {status}, then GET {kept} (bob still owns it)")
        status, _, _ = request(base_a, "DELETE", f"/v1/scenes/{sid}", token=who["bob"])
        gone, _, _ = request(base_b, "GET", f"/v1/scenes/{sid}")
        if status != 204 or gone != 404:
            sys.exit(f"store_check: FAIL: {sid}: bob's DELETE {status}, then GET {gone} (no owner left)")
    print("store_check: each owner's DELETE dropped only its own reference")


def timed(base, method, path, body=None, content_type="application/json", token=None):
    started = time.monotonic()
    try:
        status, headers, answer = request(base, method, path, body, content_type, token,
                                          timeout=OUTAGE_ANSWER_WITHIN)
    except OSError as e:  # no answer within the bound (socket.timeout is an OSError)
        status, headers, answer = 0, {}, repr(e).encode()
    return status, headers, answer, time.monotonic() - started


def outage(base, manifest_path, render_path):
    items = json.load(open(manifest_path))
    token = tokens()["alice"]
    rng = random.Random(time.time_ns())
    failures = []
    for i in range(5):
        doc = json.dumps(make_scene(rng, i, [], tag=f"outage{time.time_ns()}_")).encode()
        status, headers, _, took = timed(base, "POST", "/v1/scenes", doc, token=token)
        if status != 503 or "retry-after" not in headers:
            failures.append(f"new scene: {status}, Retry-After {headers.get('retry-after')}, {took:.1f} s")
        mesh = json.dumps(make_mesh(rng, 1000 + i)).encode()
        status, headers, _, took = timed(base, "POST", "/v1/meshes", mesh, token=token)
        if status != 503 or "retry-after" not in headers:
            failures.append(f"new mesh: {status}, Retry-After {headers.get('retry-after')}, {took:.1f} s")
    reads = {}
    for it in items[:20]:  # a replica may answer from its read-through cache: then with the same bytes
        status, headers, body, _ = timed(base, "GET", f"/v1/{it['kind']}/{it['id']}")
        reads[status] = reads.get(status, 0) + 1
        if status == 200 and hashlib.sha256(body).hexdigest() != it["sha256"]:
            failures.append(f"read of {it['id']} during the outage: bytes differ")
        elif status not in (200, 503) or (status == 503 and "retry-after" not in headers):
            failures.append(f"read of {it['id']} during the outage: {status}")
    render = open(render_path, "rb").read()
    for i in range(5):
        status, headers, body, took = timed(base, "POST", "/v1/render", render)
        if status != 200 or not body.startswith(b"\x89PNG"):
            failures.append(f"inline render {i}: {status} ({took:.1f} s)")
    status, _, body, _ = timed(base, "GET", "/readyz")
    if status != 503 or b"store_unavailable" not in body:
        failures.append(f"/readyz: {status} {body[:120]!r}")
    if failures:
        sys.exit(f"store_check: FAIL: with the database down: {failures[:6]}")
    print(f"store_check: database down: stores 503 + Retry-After, reads {reads}, /readyz 503, inline renders 200")


def recovered(base, manifest_path):
    token = tokens()["alice"]
    rng = random.Random(time.time_ns())
    doc = json.dumps(make_scene(rng, 7, [], tag=f"back{time.time_ns()}_")).encode()
    deadline, status = time.monotonic() + 30, None
    while time.monotonic() < deadline:
        status, _, _ = request(base, "POST", "/v1/scenes", doc, token=token)
        if status == 201:
            break
        time.sleep(0.5)
    if status != 201:
        sys.exit(f"store_check: FAIL: 30 s after the database returned a new scene still gets {status}")
    print("store_check: database back: new scenes store again")
    check(base, manifest_path)


def main(argv):
    command, args = argv[1], argv[2:]
    if command == "reference":
        reference(args[0], args[1], int(args[2]), int(args[3]))
    elif command == "store":
        store(*args)
    elif command == "check":
        check(*args)
    elif command == "race":
        race(args[0], args[1], int(args[2]))
    elif command == "release":
        release(*args)
    elif command == "outage":
        outage(*args)
    elif command == "recovered":
        recovered(*args)
    else:
        sys.exit(f"unknown command {command}")


if __name__ == "__main__":
    main(sys.argv)
