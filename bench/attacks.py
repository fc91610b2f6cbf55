#!/usr/bin/env python3
"""Attack benchmark: does the server stay reachable, bounded and exact under hostile clients?

Runs each attack below against the real server, one after another, for --seconds each (default 8),
with a fresh `roomrender serve` per attack (started on a free loopback port by bench_server.py), or,
with --port, against a server that is already running (a container's, say; attacks then share it).
While an attack runs, a victim thread sends, every 0.5 s on a NEW connection, a normal render
(examples/studio.json at 320x240, flat), and a sampler reads process_resident_memory_bytes from
/metrics every 0.25 s on a connection of its own.

  slow_headers       64 connections sending header bytes at one byte per 0.5 s, never finishing
  idle_keepalive     200 keep-alive connections: one GET /livez each, then idle
  slow_body          16 renders whose body (studio's Content-Length) arrives at 1 byte/s
  flood              64 keep-alive clients posting the studio render back to back
                     (legitimate heavy renders: the victim may get a fast 503 here)
  long_request_line  a 50 MB request line with no newline, as fast as the server takes it
  many_headers       a render with 10,000 header lines; GET /livez with 100,000 (expect 431)
  nul_after_json     {studio}\\0{"options":{"width":100000}}  (expect 400)
  huge_unknown_key   the studio request plus a 4 MB unknown key (expect a 4xx smaller than 2 KB)
  pipelined          two requests in one write (expect two answers, in order, no idle wait)
  connection_flood   up to 5000 connections opened as fast as possible, never sending

The malformed-input attacks (the long request line included) repeat back to back, one at a time,
on new connections, for the whole window. Per attack
it reports the victim's latency (median, max) and statuses, the attack's own answers, the latency
of every 503 from the request's last byte written to the answer's first byte (p50, p99), RSS
before (after two warm-up renders) / peak during / after (1 s after the attack stops), and
"unanswered": requests written completely that got neither an answer nor a close by the end of
the window + 10 s. Goals (pass/fail columns): victim answered 200 within 1 s (flood: 200 or 503
within 1 s), 503 p99 <= 50 ms, nothing unanswered, peak RSS growth < 64 MiB, plus each attack's
own expectation. Results are merged under --label into bench/results/attacks.json and the
Markdown table bench/results/attacks.md is rewritten from every label in that JSON.

Standard library only; loopback only; every socket has a timeout, every loop a deadline, and a
watchdog ends the script if anything still hangs. Exits 0 even when goals fail (they are results).

usage: bench/attacks.py [--binary build/roomrender] [--port P] [--seconds 8] [--label main]
                        [--attacks slow_headers,flood,...] [--server-flag=--threads=4 ...]
"""
import argparse
import collections
import errno
import json
import os
import resource
import selectors
import socket
import statistics
import subprocess
import sys
import threading
import time

from bench_server import start_server

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
HOST = "127.0.0.1"
GRACE_S = 10.0          # complete requests get the window + this long to be answered or closed
VICTIM_EVERY_S = 0.5
SAMPLE_EVERY_S = 0.25
GOAL_VICTIM_S = 1.0
GOAL_503_P99_MS = 50.0
GOAL_RSS_MIB = 64.0
ATTACKS = ["slow_headers", "idle_keepalive", "slow_body", "flood", "long_request_line", "many_headers",
           "nul_after_json", "huge_unknown_key", "pipelined", "connection_flood"]


def now():
    return time.monotonic()


# ---------------------------------------------------------------------------------------------
# A small HTTP/1.1 client on raw sockets: we need to know exactly when the last request byte was
# written and when the first answer byte arrived, and to read pipelined answers in order.

class Closed(Exception):
    """The server closed (or reset) the connection before a whole answer arrived."""


class Reader:
    def __init__(self, sock):
        self.sock = sock
        self.buf = b""
        self.first_byte_at = None

    def _fill(self, deadline):
        remaining = deadline - now()
        if remaining <= 0:
            raise socket.timeout("deadline")
        self.sock.settimeout(min(remaining, 1.0))
        try:
            data = self.sock.recv(65536)
        except socket.timeout:
            return
        except (ConnectionResetError, BrokenPipeError, ConnectionAbortedError) as e:
            raise Closed(str(e))
        if not data:
            raise Closed("eof")
        if self.first_byte_at is None:
            self.first_byte_at = now()
        self.buf += data

    def response(self, deadline, max_body=64 << 20):
        """Reads one answer: (status, headers dict, body bytes, answer size in bytes, first-byte time)."""
        self.first_byte_at = None if not self.buf else now()
        while b"\r\n\r\n" not in self.buf:
            if len(self.buf) > 1 << 20:
                raise Closed("head too large")
            self._fill(deadline)
        first = self.first_byte_at
        head, self.buf = self.buf.split(b"\r\n\r\n", 1)
        lines = head.decode("latin-1").split("\r\n")
        try:
            status = int(lines[0].split()[1])
        except (IndexError, ValueError):
            raise Closed(f"bad status line {lines[0][:60]!r}")
        headers = {}
        for line in lines[1:]:
            name, _, value = line.partition(":")
            headers[name.strip().lower()] = value.strip()
        size = len(head) + 4
        if "content-length" in headers:
            length = int(headers["content-length"])
            while len(self.buf) < min(length, max_body):
                self._fill(deadline)
            body, self.buf = self.buf[:length], self.buf[length:]
        elif headers.get("transfer-encoding", "").lower() == "chunked":
            body = b""
            while True:
                while b"\r\n" not in self.buf:
                    self._fill(deadline)
                line, self.buf = self.buf.split(b"\r\n", 1)
                n = int(line.split(b";")[0], 16)
                while len(self.buf) < n + 2:
                    self._fill(deadline)
                body += self.buf[:n]
                self.buf = self.buf[n + 2:]
                if n == 0:
                    break
        else:  # until close
            try:
                while len(self.buf) < max_body:
                    self._fill(deadline)
            except Closed:
                pass
            body, self.buf = self.buf, b""
        return status, headers, body, size + len(body), first


def request_bytes(method, path, body=b"", extra_headers=(), keep_alive=True):
    lines = [f"{method} {path} HTTP/1.1", f"Host: {HOST}"]
    if body or method == "POST":
        lines += ["Content-Type: application/json", f"Content-Length: {len(body)}"]
    if not keep_alive:
        lines.append("Connection: close")
    head = ("\r\n".join(lines) + "\r\n").encode()
    head += b"".join(extra_headers)
    return head + b"\r\n" + body


def connect(port, timeout=5.0):
    sock = socket.create_connection((HOST, port), timeout=timeout)
    sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    return sock


def send_all(sock, data, deadline):
    """Writes data before deadline; returns True when the last byte was written."""
    view = memoryview(data)
    while view:
        remaining = deadline - now()
        if remaining <= 0:
            return False
        sock.settimeout(min(remaining, 1.0))
        try:
            n = sock.send(view[:1 << 20])
        except socket.timeout:
            continue
        except (BrokenPipeError, ConnectionResetError, ConnectionAbortedError):
            raise Closed("closed while writing")
        view = view[n:]
    return True


def exchange(port, data, deadline, connect_timeout=5.0):
    """One request on a new connection. Returns a dict: outcome (status or word), times, sizes."""
    started = now()
    try:
        sock = connect(port, timeout=max(0.1, min(connect_timeout, deadline - now())))
    except OSError as e:
        return {"outcome": "connect " + (errno.errorcode.get(e.errno, "timeout") if e.errno else "timeout"),
                "started": started, "complete": False}
    reader = Reader(sock)
    result = {"started": started, "complete": False}
    try:
        try:
            result["complete"] = send_all(sock, data, deadline)
        except Closed:
            # The server may answer and close before it has read everything (414, 431...).
            pass
        written = now()
        result["written"] = written
        if not result["complete"] and deadline - now() <= 0:
            result["outcome"] = "write stalled"
            return result
        try:
            status, headers, body, size, first = reader.response(deadline)
            result.update(outcome=status, size=size, body=body[:200], headers=headers,
                          first_ms=(first - written) * 1000.0, total_ms=(now() - started) * 1000.0)
        except Closed as e:
            result["outcome"] = "closed" if not reader.buf else "closed mid-answer"
            result["total_ms"] = (now() - started) * 1000.0
        except socket.timeout:
            result["outcome"] = "unanswered" if result["complete"] else "no answer (incomplete)"
    except OSError as e:
        result["outcome"] = "error " + errno.errorcode.get(e.errno, str(e.errno))
    finally:
        sock.close()
        result["ended"] = now()
    return result


# ---------------------------------------------------------------------------------------------
# What runs beside every attack: the victim and the RSS sampler.

class Victim(threading.Thread):
    """Starts a normal render on a new connection every VICTIM_EVERY_S until stop_at, each in its own
    thread (so one stuck render does not hide the ones after it; at most seconds / 0.5 + 1 threads)."""

    def __init__(self, port, body, stop_at):
        super().__init__(daemon=True)
        self.port, self.body, self.stop_at = port, body, stop_at
        self.results = []
        self.threads = []
        self.lock = threading.Lock()

    def one(self, data):
        r = exchange(self.port, data, self.stop_at + GRACE_S)
        with self.lock:
            self.results.append(r)

    def run(self):
        data = request_bytes("POST", "/v1/render", self.body, keep_alive=False)
        next_at = now()
        while now() < self.stop_at:
            t = threading.Thread(target=self.one, args=(data,), daemon=True)
            t.start()
            self.threads.append(t)
            next_at += VICTIM_EVERY_S
            time.sleep(max(0.0, min(next_at, self.stop_at) - now()))
        for t in self.threads:
            t.join(timeout=max(0.0, self.stop_at + GRACE_S + 2 - now()))


class Sampler(threading.Thread):
    def __init__(self, port):
        super().__init__(daemon=True)
        self.port = port
        self.samples, self.failures = [], 0
        self.stop = threading.Event()

    def run(self):
        sock = reader = None
        while not self.stop.is_set():
            t = now()
            try:
                if sock is None:
                    sock = connect(self.port, timeout=1.0)
                    reader = Reader(sock)
                send_all(sock, request_bytes("GET", "/metrics"), t + 1.0)
                status, headers, body, _, _ = reader.response(t + 2.0)
                mib = metrics_rss(body)
                if mib is None:
                    self.failures += 1
                else:
                    self.samples.append(mib)
                if headers.get("connection", "").lower() == "close":
                    sock.close()
                    sock = None
            except (OSError, Closed, ValueError):
                self.failures += 1
                if sock is not None:
                    sock.close()
                sock = None
            self.stop.wait(max(0.0, SAMPLE_EVERY_S - (now() - t)))
        if sock is not None:
            sock.close()


def metrics_rss(body):
    for line in body.decode("latin-1").splitlines():
        if line.startswith("process_resident_memory_bytes"):
            return float(line.split()[-1]) / 2**20
    return None


def rss_once(port, timeout=3.0):
    """One /metrics read on a new connection; None when unreachable."""
    try:
        sock = connect(port, timeout=timeout)
        try:
            send_all(sock, request_bytes("GET", "/metrics", keep_alive=False), now() + timeout)
            _, _, body, _, _ = Reader(sock).response(now() + timeout)
            return metrics_rss(body)
        finally:
            sock.close()
    except (OSError, Closed, ValueError):
        return None


# ---------------------------------------------------------------------------------------------
# The attacks. Each gets (port, stop_at, ctx) and returns a dict with at least
#   answers: Counter of what the attack itself saw, unanswered: int, lat503: [ms],
#   expect: (passed: bool or None, text) -- the attack's own expectation.

def slow_sockets(port, count, head, trickle, every_s, stop_at, read_first=False):
    """One thread, selectors: `count` connections send `head` at once, then one byte of `trickle`
    every `every_s`, until stop_at. Records how each connection ended (answer status, close)."""
    sel = selectors.DefaultSelector()
    conns = {}
    answers = collections.Counter()
    lat503 = []
    unanswered = 0
    for k in range(count):
        if now() >= stop_at:
            break
        try:
            s = connect(port, timeout=2.0)
        except OSError:
            answers["connect failed"] += 1
            continue
        s.setblocking(False)
        try:
            s.send(head)
        except OSError:
            answers["closed at once"] += 1
            s.close()
            continue
        conns[s] = {"sent": 0, "next": now() + every_s, "buf": b"", "written_at": now(), "opened": now(),
                    "answered": not read_first}
        sel.register(s, selectors.EVENT_READ)
    ended = collections.Counter()
    close_after = []

    def finish(s, how):
        ended[how] += 1
        close_after.append(now() - conns[s]["opened"])
        sel.unregister(s)
        s.close()
        del conns[s]

    # After stop_at, connections whose complete request is still unanswered keep waiting (grace).
    while conns:
        t = now()
        if t >= stop_at:
            waiting = [s for s, c in conns.items() if not c["answered"]]
            for s in [s for s, c in conns.items() if c["answered"]]:
                ended["open at end"] += 1
                sel.unregister(s)
                s.close()
                del conns[s]
            if not waiting or t >= stop_at + GRACE_S:
                for s in waiting:
                    unanswered += 1
                    ended["unanswered"] += 1
                    sel.unregister(s)
                    s.close()
                    del conns[s]
                break
        for key, _ in sel.select(timeout=0.05):
            s = key.fileobj
            c = conns[s]
            try:
                data = s.recv(65536)
            except BlockingIOError:
                continue
            except OSError:
                data = b""
            if not data:
                if c.get("idle"):
                    finish(s, "closed while idle")
                else:
                    finish(s, "closed by server" if not c["buf"] else f"answered {status_of(c['buf'])}, closed")
                continue
            if c.get("idle"):
                continue  # the rest of the keep-alive answer's body
            if not c["buf"] and not c["answered"]:
                first_ms = (now() - c["written_at"]) * 1000.0
            else:
                first_ms = None
            c["buf"] += data
            if b"\r\n\r\n" in c["buf"]:
                st = status_of(c["buf"])
                if not c["answered"]:
                    c["answered"] = True
                    answers[f"{st}"] += 1
                    if st == 503 and first_ms is not None:
                        lat503.append(first_ms)
                    c["buf"] = b""  # the keep-alive answer: now go idle
                    c["idle"] = True
                else:
                    answers[f"{st} (while trickling)"] += 1
                    finish(s, f"answered {st}")
        if trickle:
            for s, c in list(conns.items()):
                if c["answered"] and now() >= c["next"] and c["sent"] < len(trickle):
                    try:
                        s.send(trickle[c["sent"]:c["sent"] + 1])
                        c["sent"] += 1
                        c["next"] += every_s
                    except BlockingIOError:
                        pass
                    except OSError:
                        finish(s, "closed by server (write failed)")
    sel.close()
    for s in list(conns):
        s.close()
    for how, n in ended.items():
        answers[how] += n
    note = f"{count} connections"
    if close_after:
        note += f"; server closes after {statistics.median(close_after):.1f} s median"
    return {"answers": answers, "unanswered": unanswered, "lat503": lat503, "note": note}


def status_of(buf):
    try:
        return int(buf.split(b"\r\n", 1)[0].split()[1])
    except (IndexError, ValueError):
        return "garbled"


def attack_slow_headers(port, stop_at, ctx):
    head = f"POST /v1/render HTTP/1.1\r\nHost: {HOST}\r\nX-Slow: ".encode()
    r = slow_sockets(port, ctx.slow_headers, head, b"a" * 10000, 0.5, stop_at)
    r["expect"] = (None, "victim served")
    return r


def attack_idle_keepalive(port, stop_at, ctx):
    r = slow_sockets(port, ctx.idle, request_bytes("GET", "/livez"), b"", 1.0, stop_at, read_first=True)
    # 503 is a legitimate answer to 200 requests arriving at once (load shedding); silence is not.
    answered = r["answers"].get("200", 0) + r["answers"].get("503", 0)
    r["expect"] = (answered == ctx.idle, f"all {ctx.idle} /livez answered 200 or 503")
    return r


def attack_slow_body(port, stop_at, ctx):
    head = request_bytes("POST", "/v1/render", ctx.studio)[:-len(ctx.studio)]
    r = slow_sockets(port, ctx.slow_body, head, ctx.studio, 1.0, stop_at)
    r["expect"] = (None, "victim served")
    return r


def attack_flood(port, stop_at, ctx):
    data = request_bytes("POST", "/v1/render", ctx.studio)
    lock = threading.Lock()
    answers, lat503, lat200 = collections.Counter(), [], []
    unanswered = [0]

    def client():
        sock = reader = None
        while now() < stop_at:
            try:
                if sock is None:
                    try:
                        sock = connect(port, timeout=2.0)
                    except OSError:
                        with lock:
                            answers["connect failed"] += 1
                        time.sleep(0.05)
                        continue
                    reader = Reader(sock)
                if not send_all(sock, data, stop_at + GRACE_S):
                    with lock:
                        answers["write stalled"] += 1
                    break
                written = now()
                status, headers, _, _, first = reader.response(stop_at + GRACE_S)
                with lock:
                    answers[str(status)] += 1
                    (lat503 if status == 503 else lat200 if status == 200 else []).append((first - written) * 1000.0)
                if headers.get("connection", "").lower() == "close":
                    sock.close()
                    sock = None
            except socket.timeout:
                with lock:
                    unanswered[0] += 1
                    answers["unanswered"] += 1
                break
            except Closed:
                with lock:
                    answers["closed"] += 1
                sock.close()
                sock = None
            except OSError as e:
                with lock:
                    answers["error " + errno.errorcode.get(e.errno, str(e.errno))] += 1
                if sock is not None:
                    sock.close()
                sock = None
                time.sleep(0.05)
        if sock is not None:
            sock.close()

    threads = [threading.Thread(target=client, daemon=True) for _ in range(ctx.flood)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(timeout=max(0.0, stop_at + GRACE_S + 5 - now()))
    note = f"{ctx.flood} clients; legitimate heavy renders"
    if lat200:
        note += f"; 200 first byte p50 {percentile(lat200, 50):.0f} ms"
    total = sum(answers.values())
    return {"answers": answers, "unanswered": unanswered[0], "lat503": lat503, "note": note,
            "expect": (unanswered[0] == 0 and total > 0, "every render answered")}


def one_long_request_line(port, stop_at, ctx):
    """One connection sending the line; returns (outcome, bytes sent, seconds)."""
    total = ctx.long_line_mib << 20
    chunk = b"a" * (1 << 16)
    sent = 0
    started = now()
    try:
        sock = connect(port, timeout=2.0)
    except OSError:
        return "connect failed", 0, now() - started
    sock.setblocking(False)
    sel = selectors.DefaultSelector()
    sel.register(sock, selectors.EVENT_READ | selectors.EVENT_WRITE)
    buf, outcome = b"", None
    try:
        sock.send(b"GET /")
        while now() < stop_at and outcome is None:
            for key, events in sel.select(timeout=0.1):
                if events & selectors.EVENT_READ:
                    try:
                        data = sock.recv(65536)
                    except BlockingIOError:
                        data = None
                    except OSError:
                        data = b""
                    if data == b"":
                        outcome = f"answered {status_of(buf)}, closed" if buf else "closed by server"
                        break
                    if data:
                        buf += data
                        if b"\r\n\r\n" in buf:
                            outcome = f"answered {status_of(buf)}"
                            break
                if events & selectors.EVENT_WRITE and sent < total:
                    try:
                        sent += sock.send(chunk[:min(len(chunk), total - sent)])
                    except BlockingIOError:
                        pass
                    except OSError:
                        outcome = "closed by server (write failed)"
                        # An answer may still be readable.
                        try:
                            sock.settimeout(0.5)
                            data = sock.recv(65536)
                            if data:
                                outcome = f"answered {status_of(data)}, closed"
                        except OSError:
                            pass
                        break
                    if sent >= total:
                        sel.modify(sock, selectors.EVENT_READ)
        if outcome is None:
            outcome = "all sent, no answer" if sent >= total else "still sending at window end"
    finally:
        sel.close()
        sock.close()
    return outcome, sent, now() - started


def attack_long_request_line(port, stop_at, ctx):
    """Repeats the line on new connections until the window ends (main takes ~5 s for one)."""
    total = ctx.long_line_mib << 20
    answers, sents, times, oks = collections.Counter(), [], [], []
    while now() < stop_at:
        outcome, sent, seconds = one_long_request_line(port, stop_at, ctx)
        answers[outcome] += 1
        sents.append(sent)
        times.append(seconds)
        # "sent" counts what loopback's socket buffers swallowed too (a few MiB), not only what
        # the server read, so the expectation is the 414 before the whole line, not a byte count.
        # (A line cut short by the window's end is no verdict, unless it is the only one.)
        if outcome != "still sending at window end" or not oks:
            oks.append(outcome.startswith("answered 414") and sent < total)
        if outcome == "connect failed":
            time.sleep(0.05)
    note = f"{len(sents)} lines"
    if sents:
        note += (f"; max {max(sents) / 2**20:.1f} MiB of {ctx.long_line_mib} MiB sent (incl. socket buffers), "
                 f"max {max(times):.1f} s each")
    return {"answers": answers, "unanswered": 0, "lat503": [], "note": note,
            "expect": (bool(oks) and all(oks), "414 before the whole line")}


def repeat(stop_at, make, describe):
    """Runs make() (one exchange per call, returning a list of (label, result)) back to back until
    stop_at; collects answers, 503 latencies and unanswered requests."""
    answers, lat503, unanswered, runs = collections.Counter(), [], 0, 0
    extra = []
    while now() < stop_at:
        runs += 1
        for label, r in make():
            out = r["outcome"]
            answers[f"{label}: {out}"] += 1
            if out == 503 and "first_ms" in r:
                lat503.append(r["first_ms"])
            if out == "unanswered":
                unanswered += 1
            extra.append((label, r))
    return answers, lat503, unanswered, runs, extra


def attack_many_headers(port, stop_at, ctx):
    render = request_bytes("POST", "/v1/render", ctx.studio,
                           [f"X-Many-{k}: v\r\n".encode() for k in range(10000)])
    livez = request_bytes("GET", "/livez", b"", [f"X-Many-{k}: v\r\n".encode() for k in range(100000)])

    def make():
        return [("render+10k headers", exchange(port, render, max(stop_at, now()) + GRACE_S)),
                ("livez+100k headers", exchange(port, livez, max(stop_at, now()) + GRACE_S))]
    answers, lat503, unanswered, runs, extra = repeat(stop_at, make, "")
    ok = all(r["outcome"] == 431 or r["outcome"] in ("closed",) for _, r in extra)
    return {"answers": answers, "unanswered": unanswered, "lat503": lat503, "note": f"{runs} rounds",
            "expect": (ok and bool(extra), "431 (or close) for both")}


def attack_nul_after_json(port, stop_at, ctx):
    body = ctx.studio + b"\0" + b'{"options":{"width":100000}}'
    data = request_bytes("POST", "/v1/render", body)

    def make():
        return [("nul", exchange(port, data, max(stop_at, now()) + GRACE_S))]
    answers, lat503, unanswered, runs, extra = repeat(stop_at, make, "")
    ok = bool(extra) and all(r["outcome"] == 400 for _, r in extra)
    return {"answers": answers, "unanswered": unanswered, "lat503": lat503, "note": f"{runs} requests",
            "expect": (ok, "400")}


def attack_huge_unknown_key(port, stop_at, ctx):
    request = json.loads(ctx.studio)
    request = {"k" * (ctx.huge_key_mib << 20): 1, **request}
    data = request_bytes("POST", "/v1/render", json.dumps(request).encode())

    def make():
        return [("4 MB key", exchange(port, data, max(stop_at, now()) + GRACE_S))]
    answers, lat503, unanswered, runs, extra = repeat(stop_at, make, "")
    sizes = [r.get("size", 0) for _, r in extra if isinstance(r["outcome"], int)]
    ok = bool(extra) and all(isinstance(r["outcome"], int) and 400 <= r["outcome"] < 500 and r["size"] < 2048
                             for _, r in extra)
    note = f"{runs} requests; answer size max {max(sizes) if sizes else 0} B"
    return {"answers": answers, "unanswered": unanswered, "lat503": lat503, "note": note,
            "expect": (ok, "4xx, answer < 2 KB")}


def attack_pipelined(port, stop_at, ctx):
    data = request_bytes("GET", "/v1/pipelines") + request_bytes("GET", "/livez")
    answers, lat503, unanswered, runs, times, close_times = collections.Counter(), [], 0, 0, [], []
    while now() < stop_at:
        runs += 1
        deadline = max(stop_at, now()) + GRACE_S
        try:
            sock = connect(port, timeout=2.0)
        except OSError:
            answers["connect failed"] += 1
            time.sleep(0.05)
            continue
        reader, got = Reader(sock), []
        written = now()
        try:
            if not send_all(sock, data, deadline):
                answers["write stalled"] += 1
                continue
            written = now()
            for _ in range(2):
                status, _, body, _, first = reader.response(deadline)
                got.append((status, body))
                if status == 503:
                    lat503.append((first - written) * 1000.0)
            in_order = b"pipelines" in got[0][1] and b"status" in got[1][1]
            answers[f"2 answers {'in order' if in_order else 'OUT OF ORDER'}"] += 1
            times.append(now() - written)
        except Closed:
            answers[f"{len(got)} answer(s), then closed" if len(got) < 2 else "closed"] += 1
            close_times.append(now() - written)
        except socket.timeout:
            answers[f"{len(got)} answer(s), then nothing"] += 1
            unanswered += 2 - len(got)
        except OSError as e:
            answers["error " + errno.errorcode.get(e.errno, str(e.errno))] += 1
        finally:
            sock.close()
    merged = answers
    ok = runs > 0 and merged.get("2 answers in order", 0) == sum(merged.values()) and \
        (max(times) if times else 0) < GOAL_VICTIM_S
    note = f"{runs} pairs"
    if times:
        note += f"; both answered in max {max(times) * 1000:.0f} ms"
    if close_times:
        note += f"; closed {statistics.median(close_times):.1f} s after the write (median)"
    return {"answers": merged, "unanswered": unanswered, "lat503": lat503, "note": note,
            "expect": (ok, "2 answers in order, < 1 s")}


def attack_connection_flood(port, stop_at, ctx):
    sel = selectors.DefaultSelector()
    pending, opened = {}, {}
    answers = collections.Counter()
    lat503 = []
    attempts = 0
    while now() < stop_at:
        # Open as fast as possible, up to the target, while watching what comes back.
        while attempts < ctx.connections and now() < stop_at:
            try:
                s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
            except OSError:
                answers["out of fds"] += 1
                attempts = ctx.connections
                break
            s.setblocking(False)
            attempts += 1
            rc = s.connect_ex((HOST, port))
            if rc in (0, errno.EINPROGRESS):
                pending[s] = now()
                sel.register(s, selectors.EVENT_WRITE)
            else:
                answers[f"connect {errno.errorcode.get(rc, rc)}"] += 1
                s.close()
            if attempts % 200 == 0:
                break  # let the selector run now and then
        for key, events in sel.select(timeout=0.02):
            s = key.fileobj
            if s in pending:
                err = s.getsockopt(socket.SOL_SOCKET, socket.SO_ERROR)
                sel.unregister(s)
                t0 = pending.pop(s)
                if err:
                    answers[f"connect {errno.errorcode.get(err, err)}"] += 1
                    s.close()
                    continue
                opened[s] = {"at": now(), "buf": b""}
                sel.register(s, selectors.EVENT_READ)
                continue
            c = opened[s]
            try:
                data = s.recv(4096)
            except BlockingIOError:
                continue
            except OSError:
                data = b""
            if data:
                c["buf"] += data
                if b"\r\n\r\n" not in c["buf"]:
                    continue
                st = status_of(c["buf"])
                answers[f"answered {st}"] += 1
                if st == 503:
                    # No request was sent: measured from the connection's establishment.
                    lat503.append((now() - c["at"]) * 1000.0)
            else:
                answers["closed by server" if not c["buf"] else f"answered {status_of(c['buf'])}, closed"] += 1
            sel.unregister(s)
            s.close()
            del opened[s]
    answers["open at end"] += len(opened)
    if pending:
        answers["connect still pending at end"] += len(pending)
    for s in list(opened) + list(pending):
        s.close()
    sel.close()
    return {"answers": answers, "unanswered": 0, "lat503": lat503,
            "note": f"{attempts} connection attempts (503s timed from connect)",
            "expect": (None, "victim served")}


ATTACK_FUNCS = {name: globals()["attack_" + name] for name in ATTACKS}


# ---------------------------------------------------------------------------------------------

def percentile(values, p):
    if not values:
        return None
    values = sorted(values)
    k = (len(values) - 1) * p / 100.0
    lo = int(k)
    hi = min(lo + 1, len(values) - 1)
    return values[lo] + (values[hi] - values[lo]) * (k - lo)


def run_attack(name, port, ctx):
    for _ in range(2):  # warm-up renders, so "before" includes a render's working memory
        exchange(port, request_bytes("POST", "/v1/render", ctx.studio, keep_alive=False), now() + 30)
    before = rss_once(port)
    sampler = Sampler(port)
    sampler.start()
    started = now()
    stop_at = started + ctx.seconds
    victim = Victim(port, ctx.studio, stop_at)
    victim.start()
    try:
        result = ATTACK_FUNCS[name](port, stop_at, ctx)
    except Exception as e:  # report, never crash: the other attacks still run
        result = {"answers": collections.Counter({f"attack crashed: {type(e).__name__}: {e}": 1}),
                  "unanswered": 0, "lat503": [], "note": "", "expect": (False, "attack ran")}
    attack_done = now()
    victim.join(timeout=max(0.0, stop_at + GRACE_S + 5 - now()))
    time.sleep(max(0.0, 1.0 - (now() - attack_done)))
    sampler.stop.set()
    sampler.join(timeout=5)
    after = rss_once(port)

    with victim.lock:
        vr = list(victim.results)
    v_lat = [r["total_ms"] for r in vr if isinstance(r["outcome"], int)]
    # A victim answered only once the attackers let go was not served during the attack: say so.
    v_status = collections.Counter(str(r["outcome"]) + (" after the attack stopped" if r.get("ended", 0) > attack_done
                                                        and r.get("total_ms", 0) > GOAL_VICTIM_S * 1000
                                                        and isinstance(r["outcome"], int) else "")
                                   for r in vr)
    v_unanswered = sum(1 for r in vr if r["outcome"] == "unanswered")
    lat503 = list(result["lat503"]) + [r["first_ms"] for r in vr if r["outcome"] == 503]
    ok_status = {200, 503} if name == "flood" else {200}
    victim_ok = bool(vr) and all(r["outcome"] in ok_status and r["total_ms"] <= GOAL_VICTIM_S * 1000 for r in vr)
    peak = max(sampler.samples) if sampler.samples else None
    growth = (peak - before) if (peak is not None and before is not None) else None
    unanswered = result["unanswered"] + v_unanswered
    p99 = percentile(lat503, 99)
    expect_ok, expect_text = result["expect"]
    return {
        "attack": name,
        "seconds": ctx.seconds,
        "victim": {"count": len(vr), "median_ms": statistics.median(v_lat) if v_lat else None,
                   "max_ms": max(v_lat) if v_lat else None, "statuses": dict(v_status),
                   "unanswered": v_unanswered},
        "attack_answers": dict(result["answers"]),
        "note": result.get("note", ""),
        "503": {"count": len(lat503), "p50_ms": percentile(lat503, 50), "p99_ms": p99},
        "rss_mib": {"before": before, "peak": peak, "after": after, "peak_growth": growth,
                    "samples": len(sampler.samples), "metrics_failures": sampler.failures},
        "unanswered": unanswered,
        "goals": {"victim": victim_ok,
                  "503_p99": None if p99 is None else p99 <= GOAL_503_P99_MS,
                  "unanswered": unanswered == 0,
                  "rss": None if growth is None else growth < GOAL_RSS_MIB,
                  "expect": expect_ok},
        "expect": expect_text,
    }


# ---------------------------------------------------------------------------------------------
# Reports

def fmt(v, spec=".0f", none="–"):
    return none if v is None else format(v, spec)


def mark(ok):
    return "n/a" if ok is None else ("pass" if ok else "FAIL")


def counter_text(d, limit=6):
    items = sorted(d.items(), key=lambda kv: -kv[1])
    text = ", ".join(f"{k} ×{n}" for k, n in items[:limit])
    if len(items) > limit:
        text += f", … ({len(items) - limit} more)"
    return text


def markdown(all_results):
    out = ["# Attack benchmark: hostile clients against the real server", "",
           "Written by `bench/attacks.py`; loopback; RSS in MiB from /metrics; latencies in ms. "
           f"Goals: victim 200 within {GOAL_VICTIM_S:.0f} s (flood: 200 or 503), 503 p99 ≤ {GOAL_503_P99_MS:.0f} ms "
           f"(from the request's last byte), nothing unanswered (window + {GRACE_S:.0f} s), "
           f"peak RSS growth < {GOAL_RSS_MIB:.0f} MiB. n/a: nothing to judge (no 503 seen, or /metrics unreachable).", ""]
    for label, run in all_results.items():
        out += [f"## {label}", "", f"binary `{run.get('binary')}` (its tree at {run.get('commit', '?')}), {run.get('when')}, "
                f"{run.get('seconds')} s per attack, load {run.get('load')}", "",
                "| attack | victim median / max | victim statuses | attack's answers | 503 p50 / p99 | "
                "RSS before / peak / after | unanswered | victim | 503 p99 | none unanswered | RSS | expectation |",
                "|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for r in run["attacks"]:
            v, rss, g = r["victim"], r["rss_mib"], r["goals"]
            name = r["attack"] + (" (legitimate heavy renders)" if r["attack"] == "flood" else "")
            peak = fmt(rss["peak"]) + ("" if not rss["metrics_failures"] else f" ({rss['metrics_failures']} /metrics failed)")
            out.append(
                f"| {name} | {fmt(v['median_ms'])} / {fmt(v['max_ms'])} (n={v['count']}) | {counter_text(v['statuses'])} | "
                f"{counter_text(r['attack_answers'])}{'; ' + r['note'] if r['note'] else ''} | "
                f"{fmt(r['503']['p50_ms'], '.1f')} / {fmt(r['503']['p99_ms'], '.1f')} ({r['503']['count']}) | "
                f"{fmt(rss['before'])} / {peak} / {fmt(rss['after'])} | {r['unanswered']} | "
                f"{mark(g['victim'])} | {mark(g['503_p99'])} | {mark(g['unanswered'])} | {mark(g['rss'])} | "
                f"{mark(g['expect'])}: {r['expect']} |")
        out.append("")
    return "\n".join(out)


def write_results(path_json, path_md, label, run):
    results = {}
    if os.path.exists(path_json):
        try:
            with open(path_json) as f:
                results = json.load(f)
        except ValueError:
            results = {}
    results[label] = run
    os.makedirs(os.path.dirname(os.path.abspath(path_json)), exist_ok=True)
    with open(path_json, "w") as f:
        json.dump(results, f, indent=1)
    with open(path_md, "w") as f:
        f.write(markdown(results) + "\n")


def print_row(r):
    v, rss, g = r["victim"], r["rss_mib"], r["goals"]
    print(f"{r['attack']:18s} victim {fmt(v['median_ms']):>6s}/{fmt(v['max_ms']):>6s} ms {mark(g['victim']):4s}  "
          f"503 p99 {fmt(r['503']['p99_ms'], '.1f'):>7s} {mark(g['503_p99']):4s}  unanswered {r['unanswered']:3d} "
          f"{mark(g['unanswered']):4s}  RSS {fmt(rss['before'])}/{fmt(rss['peak'])}/{fmt(rss['after'])} "
          f"{mark(g['rss']):4s}  expect {mark(g['expect'])}", flush=True)
    print(f"{'':18s} victim statuses: {counter_text(v['statuses'])}; attack: {counter_text(r['attack_answers'])}"
          f"{'; ' + r['note'] if r['note'] else ''}", flush=True)


def stop_server(server):
    if server is None or server.poll() is not None:
        return
    server.terminate()
    try:
        server.wait(timeout=15)
    except subprocess.TimeoutExpired:
        server.kill()
        server.wait(timeout=10)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--binary", default=os.path.join(ROOT, "build", "roomrender"))
    parser.add_argument("--port", type=int, help="attack this already-running server (loopback) instead")
    parser.add_argument("--seconds", type=float, default=8.0, help="length of each attack")
    parser.add_argument("--attacks", default=",".join(ATTACKS), help="comma-separated subset of " + ",".join(ATTACKS))
    parser.add_argument("--label", default="run", help="key of this run in the JSON (e.g. main, front, container)")
    parser.add_argument("--server-flag", action="append", default=[], help="passed on to serve (repeat)")
    parser.add_argument("--slow-headers", type=int, default=64)
    parser.add_argument("--idle", type=int, default=200, help="idle keep-alive connections")
    parser.add_argument("--slow-body", type=int, default=16)
    parser.add_argument("--flood", type=int, default=64, help="render clients in the flood")
    parser.add_argument("--long-line-mib", type=int, default=50)
    parser.add_argument("--huge-key-mib", type=int, default=4)
    parser.add_argument("--connections", type=int, default=5000, help="connection flood target")
    parser.add_argument("--out", default=os.path.join(ROOT, "bench", "results", "attacks.json"))
    parser.add_argument("--md", default=os.path.join(ROOT, "bench", "results", "attacks.md"))
    ctx = parser.parse_args()
    names = [n for n in ctx.attacks.split(",") if n]
    unknown = [n for n in names if n not in ATTACK_FUNCS]
    if unknown:
        sys.exit(f"unknown attacks: {unknown}")

    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    want = ctx.connections + 1000
    if soft < want:
        try:
            resource.setrlimit(resource.RLIMIT_NOFILE, (min(want, hard), hard))
        except (ValueError, OSError):
            pass
    nofile = resource.getrlimit(resource.RLIMIT_NOFILE)[0]
    if nofile < want:
        print(f"note: RLIMIT_NOFILE is {nofile}; the connection flood stops at about {nofile - 300}")
        ctx.connections = min(ctx.connections, max(0, nofile - 300))

    with open(os.path.join(ROOT, "examples", "studio.json"), "rb") as f:
        studio = json.load(f)
    studio.setdefault("options", {}).update({"width": 320, "height": 240, "shading": "flat"})
    ctx.studio = json.dumps(studio).encode()

    current = {"server": None}
    budget = len(names) * (ctx.seconds + GRACE_S + 120) + 60

    def watchdog():
        print(f"watchdog: {budget:.0f} s passed; stopping", file=sys.stderr, flush=True)
        server = current["server"]
        if server is not None and server.poll() is None:
            server.kill()
        os._exit(3)
    timer = threading.Timer(budget, watchdog)
    timer.daemon = True
    timer.start()

    run = {"binary": None if ctx.port else ctx.binary, "port": ctx.port,
           "when": time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime()), "seconds": ctx.seconds,
           "load": " ".join(f"{x:.1f}" for x in os.getloadavg()), "server_flags": ctx.server_flag,
           "attacks": []}
    if ctx.port:
        run["binary"] = f"already running on port {ctx.port}"
    if not ctx.port:
        try:
            run["version"] = subprocess.run([ctx.binary, "--version"], capture_output=True, text=True,
                                            timeout=10).stdout.strip()
        except (OSError, subprocess.TimeoutExpired):
            pass
        try:  # the commit of the tree the binary was built in (build/ sits in it), best effort
            tree = os.path.dirname(os.path.dirname(os.path.abspath(ctx.binary)))
            run["commit"] = subprocess.run(["git", "-C", tree, "log", "-1", "--format=%h %s"], capture_output=True,
                                           text=True, timeout=10).stdout.strip()
        except (OSError, subprocess.TimeoutExpired):
            pass
    print(f"{run['binary']}: {len(names)} attacks of {ctx.seconds:.0f} s; victim = studio 320x240 flat "
          f"every {VICTIM_EVERY_S} s", flush=True)
    for name in names:
        server = None
        try:
            if ctx.port:
                port = ctx.port
            else:
                server, port = start_server(ctx.binary, ctx.server_flag)
                current["server"] = server
            result = run_attack(name, port, ctx)
        finally:
            stop_server(server)
            current["server"] = None
        if server is not None:
            result["server_exit"] = server.returncode
        run["attacks"].append(result)
        print_row(result)
        write_results(ctx.out, ctx.md, ctx.label, run)
        if ctx.port:
            time.sleep(3)  # let the shared server settle before the next attack
    timer.cancel()
    print(f"wrote {os.path.relpath(ctx.out)} and {os.path.relpath(ctx.md)} (label {ctx.label!r})")


if __name__ == "__main__":
    main()
