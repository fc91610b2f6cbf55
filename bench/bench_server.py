"""The real roomrender server for the HTTP benchmarks in bench/: started on a free loopback port
(it announces the port in its first JSON line), and its resident memory read from /metrics."""
import http.client
import json
import os
import subprocess
import sys


def start_server(binary, flags=(), env_extra=None):
    """Starts `binary serve` on a free loopback port with request logs off; returns (process, port)."""
    env = dict(os.environ, **(env_extra or {}))
    server = subprocess.Popen([binary, "serve", "--port", "0", "--log-requests", "0", *flags],
                              stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True, env=env)
    line = server.stdout.readline()
    try:
        port = json.loads(line)["port"]
    except (ValueError, KeyError):
        server.kill()
        sys.exit(f"the server did not announce its port: {line!r}")
    return server, port


def resident_mib(port):
    """The server's resident memory in MiB, from its /metrics (process_resident_memory_bytes)."""
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
    conn.request("GET", "/metrics")
    text = conn.getresponse().read().decode()
    conn.close()
    for line in text.splitlines():
        if line.startswith("process_resident_memory_bytes"):
            return float(line.split()[-1]) / 2**20
    return float("nan")
