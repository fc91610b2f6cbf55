#!/usr/bin/env python3
"""roomrender client: render rooms on a roomrender server from Python or the command line.

Standard library only (urllib, json, argparse). As a module:

    from roomrender_client import Client, orbit_cameras
    rr = Client("http://127.0.0.1:8080")
    result = rr.render(json.load(open("examples/studio.json")))   # RenderResult: png, timings_ms, ...
    receipt = rr.store_scene(request["scene"])                     # stored scene -> id
    view = rr.render_stored(receipt["id"], camera={...}, options={"width": 320, "height": 240})
    smooth = rr.render(with_antialias(request, 8))                 # 8 coverage sub-samples per pixel
    rr.render_path(request, orbit_cameras(request["camera"], 36), "frames/")  # frame_0001.png ...
    catalogue = rr.catalogue()                                      # the server's furniture models
    chair = place_piece(catalogue["items"][0], center=[2, 1.5], rotation_y=90, id="chair-1")
    request["scene"]["solids"].append(chair)                        # a piece of its real size
    rr.pick(request, 320, 240)["pointer"]                           # "/scene/solids/3": the piece whole

As a command (python3 roomrender_client.py --help): render, store, render-stored, import, orbit,
pipelines, catalogue. Server errors are RFC 9457 problem+json with JSON Pointers; they surface as RoomrenderError
(and on the command line as "pointer: detail" lines and exit status 1). Endpoints newer than the
first server (stored scenes, JSON answers, importers) are detected from GET /openapi.json; using one
the server lacks raises EndpointMissing naming it.
"""
from __future__ import annotations

import argparse
import base64
import json
import math
import os
import sys
import time
import urllib.error
import urllib.parse
import urllib.request
from dataclasses import dataclass, field
from typing import Any, Callable, Iterable, Optional

DEFAULT_URL = os.environ.get("ROOMRENDER_URL", "http://127.0.0.1:8080")
CAMERA_DEFAULTS = {"position": [0, 1.6, 5], "target": [0, 1, 0]}  # docs/scene-format.md


class RoomrenderError(Exception):
    """The server refused a request. `errors` is the problem's [{pointer, detail}] list."""

    def __init__(self, status: int, problem: dict):
        self.status = status
        self.problem = problem
        self.errors = problem.get("errors") or []
        super().__init__(f"HTTP {status}: {problem.get('detail') or problem.get('title') or 'error'}")

    def lines(self) -> list[str]:
        """One line per field error ("/camera/fov_y: must be in (1, 170)"), or the detail."""
        if not self.errors:
            return [str(self)]
        return [f"{e.get('pointer') or '(request)'}: {e.get('detail', '')}" for e in self.errors]


class EndpointMissing(RoomrenderError):
    """The server does not have an endpoint this call needs (an older server)."""

    def __init__(self, endpoint: str):
        super().__init__(404, {"title": "Not Found", "detail": f"this server has no {endpoint}"})
        self.endpoint = endpoint


@dataclass
class RenderResult:
    png: bytes
    timings_ms: dict = field(default_factory=dict)
    scene_id: str = ""
    cache: Optional[str] = None  # BSP cache: "hit", "miss", or None when no tree was built
    counts: dict = field(default_factory=dict)  # only in JSON answers
    warnings: list = field(default_factory=list)  # only in JSON answers
    warning_count: int = 0
    etag: str = ""


def parse_server_timing(header: str) -> dict:
    """'parse;dur=0.12, total;dur=3.4' -> {'parse': 0.12, 'total': 3.4}."""
    out = {}
    for entry in (header or "").split(","):
        name, *params = [p.strip() for p in entry.split(";")]
        if not name:
            continue
        dur = next((p[4:] for p in params if p.startswith("dur=")), None)
        out[name] = float(dur) if dur is not None else float("nan")
    return out


def png_size(png: bytes) -> tuple[int, int]:
    """(width, height) from a PNG's IHDR chunk."""
    if png[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("not a PNG")
    return int.from_bytes(png[16:20], "big"), int.from_bytes(png[20:24], "big")


def _query_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (list, tuple)):
        return ",".join(_query_value(v) for v in value)
    return json.dumps(value) if isinstance(value, float) else str(value)


def view_query(camera: Optional[dict] = None, options: Optional[dict] = None) -> str:
    """Camera and options as the query of GET /v1/scenes/{id}/render.png (docs/api.md)."""
    params = []
    for key, value in (camera or {}).items():
        params.append((key, _query_value(value)))
    for key, value in (options or {}).items():
        if isinstance(value, dict):  # painter.key -> painter_key, shadow.size -> shadow_size, ...
            params.extend((f"{key}_{k}", _query_value(v)) for k, v in value.items())
        else:
            params.append((key, _query_value(value)))
    return urllib.parse.urlencode(params, safe=",")


ANTIALIAS_SAMPLES = (1, 4, 8, 16)  # options.antialias: coverage sub-samples per pixel (docs/antialiasing.md)


def with_antialias(request: dict, samples: int) -> dict:
    """A copy of the request with options.antialias = samples (1: aliased, the default; 4, 8 or 16).
    The same key in the options of render_stored / render_png_path becomes render.png's `antialias`."""
    if samples not in ANTIALIAS_SAMPLES:
        raise ValueError(f"antialias must be one of {ANTIALIAS_SAMPLES}, not {samples}")
    return {**request, "options": {**request.get("options", {}), "antialias": samples}}


def _exposure(text: str):
    """options.exposure from the command line: "auto" or a number (the server checks its range)."""
    return text if text == "auto" else float(text)


class Client:
    def __init__(self, base_url: str = DEFAULT_URL, timeout: float = 120.0):
        self.base_url = base_url.rstrip("/")
        self.timeout = timeout
        self._paths: Optional[dict] = None

    # -- plumbing ----------------------------------------------------------------------------
    def _send(self, method: str, path: str, body: Optional[bytes] = None,
              content_type: Optional[str] = None, accept: Optional[str] = None):
        headers = {}
        if content_type:
            headers["Content-Type"] = content_type
        if accept:
            headers["Accept"] = accept
        req = urllib.request.Request(self.base_url + path, data=body, method=method, headers=headers)
        try:
            with urllib.request.urlopen(req, timeout=self.timeout) as res:
                return res.status, res.headers, res.read()
        except urllib.error.HTTPError as e:
            raw = e.read()
            try:
                problem = json.loads(raw)
            except ValueError:
                problem = {"detail": raw.decode("utf-8", "replace")[:500] or e.reason}
            raise RoomrenderError(e.code, problem) from None

    def _json(self, method: str, path: str, payload: Any = None, accept: str = "application/json"):
        body = None if payload is None else _encode(payload)
        _, headers, raw = self._send(method, path, body, "application/json" if body is not None else None, accept)
        return headers, json.loads(raw) if raw else None

    def paths(self) -> dict:
        """The server's OpenAPI paths; {} for a server without /openapi.json (the first one)."""
        if self._paths is None:
            try:
                self._paths = self._json("GET", "/openapi.json")[1].get("paths", {})
            except RoomrenderError:
                self._paths = {}
        return self._paths

    def has(self, path: str, method: str = "post") -> bool:
        return method in self.paths().get(path, {})

    def _require(self, path: str, method: str = "post") -> None:
        if not self.has(path, method):
            raise EndpointMissing(f"{method.upper()} {path}")

    # -- endpoints ---------------------------------------------------------------------------
    def health(self) -> dict:
        return self._json("GET", "/healthz")[1]

    def pipelines(self) -> list[str]:
        return [p["name"] for p in self._json("GET", "/v1/pipelines")[1]["pipelines"]]

    def render(self, request: Any, json_answer: bool = True) -> RenderResult:
        """POST /v1/render. With json_answer the server's JSON answer (counts, warnings) is asked
        for; a server that only answers PNG is fine too."""
        return self._render("/v1/render", request, json_answer)

    def store_scene(self, scene: dict) -> dict:
        """POST /v1/scenes: stores a scene document (the request's "scene"); returns the receipt
        {id, location, scene_id, created, warnings}."""
        self._require("/v1/scenes")
        return self._json("POST", "/v1/scenes", scene)[1]

    def get_scene(self, scene_id: str) -> dict:
        self._require("/v1/scenes/{id}", "get")
        return self._json("GET", f"/v1/scenes/{_segment(scene_id)}")[1]

    def delete_scene(self, scene_id: str) -> None:
        self._require("/v1/scenes/{id}", "delete")
        self._send("DELETE", f"/v1/scenes/{_segment(scene_id)}")

    def store_texture(self, image: bytes) -> dict:
        """POST /v1/textures: stores a PNG or JPEG file's bytes (the server tells them apart by
        their first bytes); returns the receipt {id, location, created, media_type, width, height,
        bytes}. A texture then names the image by id: {"image": receipt["id"], ...}."""
        self._require("/v1/textures")
        _, _, raw = self._send("POST", "/v1/textures", image, "application/octet-stream", "application/json")
        return json.loads(raw)

    def get_texture(self, texture_id: str) -> bytes:
        """GET /v1/textures/{id}: the stored image's bytes, as they were sent."""
        self._require("/v1/textures/{id}", "get")
        return self._send("GET", f"/v1/textures/{_segment(texture_id)}")[2]

    def delete_texture(self, texture_id: str) -> None:
        """DELETE /v1/textures/{id}; the server answers 409 while a stored scene uses the image."""
        self._require("/v1/textures/{id}", "delete")
        self._send("DELETE", f"/v1/textures/{_segment(texture_id)}")

    def render_stored(self, scene_id: str, camera: Optional[dict] = None, options: Optional[dict] = None,
                      json_answer: bool = True) -> RenderResult:
        """POST /v1/scenes/{id}/render with only the view: no scene upload, parse or tessellation."""
        self._require("/v1/scenes/{id}/render")
        view = {k: v for k, v in (("camera", camera), ("options", options)) if v is not None}
        return self._render(f"/v1/scenes/{_segment(scene_id)}/render", view, json_answer)

    def render_png_path(self, scene_id: str, camera: Optional[dict] = None, options: Optional[dict] = None) -> str:
        """The cacheable GET URL path of a stored scene's view (immutable: cache it forever)."""
        query = view_query(camera, options)
        return f"/v1/scenes/{_segment(scene_id)}/render.png" + (f"?{query}" if query else "")

    def get_png(self, path: str) -> bytes:
        return self._send("GET", path, accept="image/png")[2]

    def pick(self, request: dict, x: int, y: int) -> dict:
        """POST /v1/pick: the element visible at pixel (x, y) of the request's image: {pointer, part,
        polygon, point, depth, camera, ...}. A piece of furniture is named whole; `part` is the part
        under the pixel ({index, pointer, name}), None for other elements and the background."""
        self._require("/v1/pick")
        return self._json("POST", "/v1/pick", {**request, "x": x, "y": y})[1]

    def catalogue(self) -> dict:
        """GET /v1/catalogue: {items: [{id, name, category, size_cm, elevation_cm, icon, piece}],
        licence, attribution}. Place an item with place_piece()."""
        self._require("/v1/catalogue", "get")
        return self._json("GET", "/v1/catalogue")[1]

    def catalogue_icon(self, item_id: str) -> bytes:
        """The PNG icon of a catalogue entry."""
        return self._send("GET", f"/v1/catalogue/{_segment(item_id)}/icon.png", accept="image/png")[2]

    def import_file(self, data: bytes, fmt: str = "sh3d", store: bool = False, **params: Any) -> dict:
        """POST /v1/import/{fmt} (sh3d: Sweet Home 3D Home.xml or .sh3d; r2v; obj): the complete render
        request the file describes, or with store=True the stored scene's receipt with its camera."""
        self._require("/v1/import/{format}")
        query = {k: _query_value(v) for k, v in params.items() if v is not None}
        if store:
            query["store"] = "1"
        path = f"/v1/import/{_segment(fmt)}" + (f"?{urllib.parse.urlencode(query)}" if query else "")
        _, headers, raw = self._send("POST", path, data, "application/octet-stream", "application/json")
        return json.loads(raw)

    def render_path(self, request: dict, cameras: Iterable[dict], out_dir: str,
                    pattern: str = "frame_{:04d}.png", progress: Optional[Callable[[int, int, str, float], None]] = None,
                    use_store: Optional[bool] = None) -> list[str]:
        """Renders the request from each camera into out_dir/frame_0001.png, ... and returns the
        paths. The scene is stored once and each view rendered by id when the server can (use_store
        None: when it can), else every frame is an inline render."""
        cameras = list(cameras)
        os.makedirs(out_dir, exist_ok=True)
        if use_store is None:
            use_store = self.has("/v1/scenes") and self.has("/v1/scenes/{id}/render")
        scene_id = self.store_scene(request.get("scene", {}))["id"] if use_store else None
        options = request.get("options")
        written = []
        for i, camera in enumerate(cameras, start=1):
            started = time.monotonic()
            if scene_id:
                result = self.render_stored(scene_id, camera, options, json_answer=False)
            else:
                result = self.render({**request, "camera": camera}, json_answer=False)
            path = os.path.join(out_dir, pattern.format(i))
            with open(path, "wb") as f:
                f.write(result.png)
            written.append(path)
            if progress:
                progress(i, len(cameras), path, (time.monotonic() - started) * 1000)
        return written

    def _render(self, path: str, payload: Any, json_answer: bool) -> RenderResult:
        accept = "application/json, image/png;q=0.5" if json_answer else "image/png"
        _, headers, raw = self._send("POST", path, _encode(payload), "application/json", accept)
        common = dict(scene_id=headers.get("X-Scene-Id", ""), cache=headers.get("X-Cache"),
                      warning_count=int(headers.get("X-Warning-Count") or 0), etag=headers.get("ETag", ""))
        if (headers.get("Content-Type") or "").startswith("application/json"):
            answer = json.loads(raw)
            common.update(scene_id=answer.get("scene_id", common["scene_id"]),
                          cache=None if answer.get("cache") in (None, "none") else answer["cache"])
            # The listed warnings are the deepest; warning_count is every problem the server found.
            common["warning_count"] = answer.get("warning_count", common["warning_count"])
            return RenderResult(png=base64.b64decode(answer["png_base64"]), timings_ms=answer.get("timings_ms", {}),
                                counts=answer.get("counts", {}), warnings=answer.get("warnings", []), **common)
        return RenderResult(png=raw, timings_ms=parse_server_timing(headers.get("Server-Timing", "")), **common)


def place_piece(item: dict, center: list, rotation_y: float = 0, id: Optional[str] = None,
                mirrored: bool = False) -> dict:
    """A catalogue entry (an item of Client.catalogue()) placed as a piece solid at `center` [x, z]:
    its real size, elevation and parts (read-only stored meshes), turned and optionally mirrored."""
    piece = {**item["piece"], "center": list(center), "rotation_y": rotation_y}
    if id is not None:
        piece["id"] = id
    if mirrored:
        piece["mirrored"] = True
    return piece


def _encode(payload: Any) -> bytes:
    if isinstance(payload, bytes):
        return payload
    if isinstance(payload, str):
        return payload.encode("utf-8")
    return json.dumps(payload).encode("utf-8")


def _segment(text: str) -> str:
    return urllib.parse.quote(text, safe="")


def orbit_cameras(camera: Optional[dict], frames: int, turns: float = 1.0) -> list[dict]:
    """`frames` cameras turning `turns` times about the target (about +Y), keeping the start's
    distance and height; frame 1 is the start camera. Other camera members are kept."""
    if frames < 1:
        raise ValueError("frames must be at least 1")
    start = {**CAMERA_DEFAULTS, **(camera or {})}
    px, py, pz = start["position"]
    tx, _, tz = start["target"]
    radius = math.hypot(px - tx, pz - tz)
    azimuth0 = math.atan2(px - tx, pz - tz)
    out = []
    for i in range(frames):
        a = azimuth0 + 2 * math.pi * turns * i / frames
        position = [round(tx + radius * math.sin(a), 6), py, round(tz + radius * math.cos(a), 6)]
        out.append({**start, "position": position})
    return out


class ProgressBar:
    """A progress bar on a terminal (rewritten in place), or a line per 10 % elsewhere (logs)."""

    def __init__(self, stream=None, width: int = 30):
        self.stream = stream or sys.stderr
        self.width = width
        self.tty = hasattr(self.stream, "isatty") and self.stream.isatty()
        self.last_decile = -1

    def __call__(self, done: int, total: int, path: str, ms: float) -> None:
        filled = int(self.width * done / total)
        line = f"[{'#' * filled}{'.' * (self.width - filled)}] {done}/{total} {os.path.basename(path)} {ms:.0f} ms"
        if self.tty:
            self.stream.write("\r" + line + ("\n" if done == total else ""))
        elif done * 10 // total != self.last_decile or done == total:
            self.last_decile = done * 10 // total
            self.stream.write(line + "\n")
        self.stream.flush()


# -- command line ------------------------------------------------------------------------------

def _load_json(path: str) -> Any:
    if path == "-":
        return json.load(sys.stdin)
    with open(path, encoding="utf-8") as f:
        return json.load(f)


def _write(path: str, data: bytes) -> None:
    if path == "-":
        sys.stdout.buffer.write(data)
    else:
        with open(path, "wb") as f:
            f.write(data)


def _report(result: RenderResult, out: str) -> None:
    width, height = png_size(result.png)
    print(json.dumps({"out": out, "width": width, "height": height, "bytes": len(result.png),
                      "scene_id": result.scene_id, "cache": result.cache, "timings_ms": result.timings_ms,
                      "counts": result.counts, "warnings": result.warnings or result.warning_count}),
          file=sys.stderr if out == "-" else sys.stdout)


def _cmd_render(rr: Client, args) -> None:
    request = _load_json(args.request)
    options = request.setdefault("options", {})
    for key in ("pipeline", "shading", "width", "height", "antialias", "exposure"):
        if getattr(args, key) is not None:
            options[key] = getattr(args, key)
    result = rr.render(request)
    _write(args.output, result.png)
    _report(result, args.output)


def _cmd_store(rr: Client, args) -> None:
    document = _load_json(args.file)
    scene = document["scene"] if isinstance(document, dict) and "scene" in document else document  # a request's scene
    print(json.dumps(rr.store_scene(scene)))


def _cmd_render_stored(rr: Client, args) -> None:
    view = _load_json(args.view) if args.view else {}
    result = rr.render_stored(args.id, view.get("camera"), view.get("options"))
    _write(args.output, result.png)
    _report(result, args.output)


def _cmd_import(rr: Client, args) -> None:
    with open(args.file, "rb") as f:
        data = f.read()
    fmt = args.format or {".obj": "obj", ".txt": "r2v"}.get(os.path.splitext(args.file)[1].lower(), "sh3d")
    answer = rr.import_file(data, fmt, store=args.store, scale=args.scale, width=args.width, height=args.height)
    _write(args.output, (json.dumps(answer, indent=2) + "\n").encode())


def _cmd_orbit(rr: Client, args) -> None:
    request = _load_json(args.request)
    options = request.setdefault("options", {})
    if args.width:
        options["width"] = args.width
    if args.height:
        options["height"] = args.height
    if args.antialias:
        options["antialias"] = args.antialias
    cameras = orbit_cameras(request.get("camera"), args.frames, args.turns)
    started = time.monotonic()
    paths = rr.render_path(request, cameras, args.out_dir, progress=ProgressBar(),
                           use_store=False if args.inline else None)
    print(json.dumps({"frames": len(paths), "first": paths[0], "last": paths[-1],
                      "seconds": round(time.monotonic() - started, 3)}))


def _cmd_pipelines(rr: Client, args) -> None:
    print("\n".join(rr.pipelines()))


def _cmd_catalogue(rr: Client, args) -> None:
    answer = rr.catalogue()
    for item in answer["items"]:
        if args.category and item["category"] != args.category:
            continue
        size = item["size_cm"]
        print(f"{item['id']}\t{item['category']}\t{item['name']}\t{size['width']:g} x {size['depth']:g} x {size['height']:g} cm")
    print(answer["attribution"], file=sys.stderr)


def make_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="roomrender_client.py", description=__doc__.split("\n\n")[0])
    p.add_argument("--url", default=DEFAULT_URL, help="server base URL (env ROOMRENDER_URL; default %(default)s)")
    p.add_argument("--timeout", type=float, default=120.0, help="seconds per request")
    sub = p.add_subparsers(dest="command", required=True)

    r = sub.add_parser("render", help="render a request (JSON file, or - for stdin) to a PNG")
    r.add_argument("request")
    r.add_argument("-o", "--output", default="out.png", help="PNG file, or - for stdout")
    r.add_argument("--pipeline")
    r.add_argument("--shading")
    r.add_argument("--width", type=int)
    r.add_argument("--height", type=int)
    r.add_argument("--antialias", type=int, choices=ANTIALIAS_SAMPLES, help="coverage sub-samples per pixel")
    r.add_argument("--exposure", type=_exposure, help="multiplier of the lights and ambient in (0, 64], or auto")
    r.set_defaults(run=_cmd_render)

    s = sub.add_parser("store", help="store a scene (a scene document or a request's scene); prints the receipt")
    s.add_argument("file")
    s.set_defaults(run=_cmd_store)

    v = sub.add_parser("render-stored", help="render a view of a stored scene")
    v.add_argument("id")
    v.add_argument("--view", help='JSON file with {"camera": ..., "options": ...}')
    v.add_argument("-o", "--output", default="out.png")
    v.set_defaults(run=_cmd_render_stored)

    i = sub.add_parser("import", help="import a Sweet Home 3D home (or an r2v plan, an OBJ model)")
    i.add_argument("file")
    i.add_argument("--format", choices=["sh3d", "r2v", "obj"], help="default: from the file name (sh3d)")
    i.add_argument("--store", action="store_true", help="store the scene; print its receipt and default camera")
    i.add_argument("--scale", type=float, help="metres per file unit")
    i.add_argument("--width", type=int)
    i.add_argument("--height", type=int)
    i.add_argument("-o", "--output", default="-", help="where the request JSON goes (default stdout)")
    i.set_defaults(run=_cmd_import)

    o = sub.add_parser("orbit", help="render N frames turning about the camera's target into numbered PNGs")
    o.add_argument("request")
    o.add_argument("--frames", type=int, default=36)
    o.add_argument("--turns", type=float, default=1.0)
    o.add_argument("--out-dir", default="frames")
    o.add_argument("--width", type=int)
    o.add_argument("--height", type=int)
    o.add_argument("--antialias", type=int, choices=ANTIALIAS_SAMPLES, help="coverage sub-samples per pixel")
    o.add_argument("--inline", action="store_true", help="send the whole scene with every frame")
    o.set_defaults(run=_cmd_orbit)

    c = sub.add_parser("catalogue", help="list the server's furniture catalogue: id, category, name, size")
    c.add_argument("--category", help="only this category (Bedroom, Living room, Kitchen, ...)")
    c.set_defaults(run=_cmd_catalogue)

    l = sub.add_parser("pipelines", help="list the server's pipelines")
    l.set_defaults(run=_cmd_pipelines)
    return p


def main(argv: Optional[list[str]] = None) -> int:
    args = make_parser().parse_args(argv)
    try:
        args.run(Client(args.url, args.timeout), args)
    except RoomrenderError as e:
        print("\n".join(e.lines()), file=sys.stderr)
        return 1
    except (OSError, ValueError) as e:  # unreachable server, unreadable file, bad JSON
        print(f"error: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
