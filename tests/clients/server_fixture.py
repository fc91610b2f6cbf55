"""The real roomrender server for the client tests: `roomrender serve --port 0` on loopback, ready
once it prints its JSON "listening" line (which names the port it got); stopped with SIGTERM.
The binary is $ROOMRENDER_BINARY, else build/roomrender."""
import json
import os
import subprocess
import threading

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


class RoomrenderServer:
    def __init__(self, process, port):
        self.process = process
        self.port = port
        self.url = f"http://127.0.0.1:{port}"

    @classmethod
    def start(cls, *extra_args):
        binary = os.environ.get("ROOMRENDER_BINARY", os.path.join(REPO, "build", "roomrender"))
        process = subprocess.Popen(
            [binary, "serve", "--port", "0", "--bind", "127.0.0.1", "--log-requests", "0",
             "--web-dir", os.path.join(REPO, "clients", "web"), "--examples-dir", os.path.join(REPO, "examples"),
             *extra_args],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        # readline blocks; a timer ends a server that never reports (the test then fails clearly).
        timer = threading.Timer(20, process.kill)
        timer.start()
        try:
            for line in process.stdout:
                try:
                    event = json.loads(line)
                except ValueError:
                    continue
                if event.get("event") == "listening":
                    return cls(process, event["port"])
        finally:
            timer.cancel()
        raise RuntimeError(f"{binary} did not report listening: {process.stderr.read()}")

    def stop(self):
        if self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(timeout=15)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        self.process.stdout.close()
        self.process.stderr.close()
