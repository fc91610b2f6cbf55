"""The Python client and the curl examples against the real server on a free loopback port.

Each TestCase class is one CTest test (tests/clients/CMakeLists.txt). A class whose endpoints the
server lacks skips as a whole, naming them; CTest reports it as skipped. Run by hand:
    ROOMRENDER_BINARY=build/roomrender python3 -m unittest -v test_python_client   (in tests/clients)
"""
import io
import json
import math
import os
import subprocess
import sys
import tempfile
import unittest

from server_fixture import REPO, RoomrenderServer

sys.path.insert(0, os.path.join(REPO, "clients", "python"))
import roomrender_client as rc  # noqa: E402

CLIENT = os.path.join(REPO, "clients", "python", "roomrender_client.py")
CURL = os.path.join(REPO, "clients", "curl")
HOME_XML = os.path.join(REPO, "tests", "clients", "fixtures", "two_rooms.xml")


def load_example(name):
    with open(os.path.join(REPO, "examples", name + ".json"), encoding="utf-8") as f:
        return json.load(f)


def small(request, width=160, height=120):
    """The request at a small size: the tests check behaviour, not pixels."""
    return {**request, "options": {**request.get("options", {}), "width": width, "height": height}}


class ServerTest(unittest.TestCase):
    needs = []  # (method, OpenAPI path) the class's tests need

    @classmethod
    def setUpClass(cls):
        cls.server = RoomrenderServer.start()
        cls.addClassCleanup(cls.server.stop)
        cls.client = rc.Client(cls.server.url)
        missing = [f"{m.upper()} {p}" for m, p in cls.needs if not cls.client.has(p, m)]
        if missing:
            raise unittest.SkipTest(f"needs {', '.join(missing)} (not on this server yet)")

    def tmpdir(self):
        d = tempfile.TemporaryDirectory(prefix="rr-clients-")
        self.addCleanup(d.cleanup)
        return d.name

    def write_json(self, value, name="request.json"):
        path = os.path.join(self.tmpdir(), name)
        with open(path, "w", encoding="utf-8") as f:
            json.dump(value, f)
        return path

    def read_png(self, path, size):
        """The PNG file's bytes, after checking it is a PNG of `size` (width, height)."""
        with open(path, "rb") as f:
            png = f.read()
        self.assertEqual(rc.png_size(png), size, path)
        return png


class InlineRender(ServerTest):
    def test_render_returns_the_png_and_its_timings(self):
        result = self.client.render(load_example("studio"))
        self.assertEqual(rc.png_size(result.png), (640, 480))
        self.assertRegex(result.scene_id, r"^[0-9a-f]{16}$")
        for stage in ("parse", "tessellate", "raster", "encode", "total"):
            self.assertIn(stage, result.timings_ms)
        self.assertGreater(result.timings_ms["total"], 0)
        self.assertGreaterEqual(result.timings_ms["total"], result.timings_ms["raster"])

    def test_same_request_same_image_and_camera_changes_it(self):
        request = small(load_example("studio"))
        first = self.client.render(request).png
        self.assertEqual(self.client.render(json.dumps(request)).png, first)  # text or object alike
        moved = {**request, "camera": {**request["camera"], "position": [1, 2, 3]}}
        self.assertNotEqual(self.client.render(moved).png, first)

    def test_server_errors_carry_the_pointer(self):
        request = small(load_example("studio"))
        request["camera"]["fov_y"] = 500
        with self.assertRaises(rc.RoomrenderError) as caught:
            self.client.render(request)
        self.assertEqual(caught.exception.status, 422)
        self.assertEqual(caught.exception.errors[0]["pointer"], "/camera/fov_y")
        self.assertTrue(caught.exception.lines()[0].startswith("/camera/fov_y: "))
        with self.assertRaises(rc.RoomrenderError) as caught:
            self.client.render("{not json")
        self.assertEqual(caught.exception.status, 400)

    def test_pipelines_lists_the_table(self):
        self.assertIn("zbuffer", self.client.pipelines())


class JsonAnswers(ServerTest):
    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        if not cls.client.render("{}", json_answer=True).counts:
            raise unittest.SkipTest("needs JSON answers from POST /v1/render (Accept: application/json)")

    def test_json_answer_has_counts_and_the_same_image(self):
        request = small(load_example("studio"))
        answer = self.client.render(request, json_answer=True)
        png = self.client.render(request, json_answer=False)
        self.assertEqual(answer.png, png.png)
        self.assertGreater(answer.counts["polygons"], 0)
        self.assertIsInstance(answer.warnings, list)


class StoredScenes(ServerTest):
    needs = [("post", "/v1/scenes"), ("post", "/v1/scenes/{id}/render"), ("get", "/v1/scenes/{id}/render.png"),
             ("delete", "/v1/scenes/{id}")]

    def test_views_of_a_stored_scene_equal_inline_renders(self):
        request = small(load_example("studio"))
        receipt = self.client.store_scene(request["scene"])
        self.assertRegex(receipt["id"], r"^[0-9a-f]{16}$")
        self.assertEqual(self.client.store_scene(request["scene"])["id"], receipt["id"])  # content-addressed
        inline = self.client.render(request, json_answer=False).png
        stored = self.client.render_stored(receipt["id"], request["camera"], request["options"], json_answer=False)
        self.assertEqual(stored.png, inline)
        by_get = self.client.get_png(self.client.render_png_path(receipt["id"], request["camera"], request["options"]))
        self.assertEqual(by_get, inline)
        other = {**request["camera"], "position": [3, 12, 2.3], "target": [3, 0, 2.25]}
        self.assertNotEqual(self.client.render_stored(receipt["id"], other, request["options"]).png, inline)

    def test_query_parameters_name_nested_options(self):
        query = rc.view_query({"position": [1, 2.5, -3], "fov_y": 50}, {"width": 64, "shadows": True,
                                                                         "painter": {"key": "newell"}})
        self.assertEqual(query, "position=1,2.5,-3&fov_y=50&width=64&shadows=true&painter_key=newell")
        receipt = self.client.store_scene(load_example("tetrahedron")["scene"])
        png = self.client.get_png(self.client.render_png_path(receipt["id"], {"fov_y": 50}, {"width": 64, "height": 48}))
        self.assertEqual(rc.png_size(png), (64, 48))

    def test_antialias_reaches_both_render_paths(self):
        # The reference casts S rays per pixel for antialias = S, so its bytes change with S whatever
        # the other pipelines do; the stored scene's render.png gets the option as its query parameter.
        request = small(load_example("tetrahedron"), 96, 72)
        request["options"]["pipeline"] = "reference"
        self.assertEqual(rc.view_query(None, {"antialias": 8}), "antialias=8")
        aliased = self.client.render(request, json_answer=False).png
        smooth = self.client.render(rc.with_antialias(request, 8), json_answer=False).png
        self.assertNotEqual(smooth, aliased)
        receipt = self.client.store_scene(request["scene"])
        options = rc.with_antialias(request, 8)["options"]
        self.assertEqual(self.client.get_png(self.client.render_png_path(receipt["id"], request["camera"], options)), smooth)
        with self.assertRaises(ValueError):
            rc.with_antialias(request, 3)
        with self.assertRaises(rc.RoomrenderError) as caught:
            self.client.render({**request, "options": {**request["options"], "antialias": 3}})
        self.assertIn("/options/antialias", "\n".join(caught.exception.lines()))

    def test_delete_forgets_the_scene(self):
        receipt = self.client.store_scene(load_example("tri_parallel")["scene"])
        self.client.delete_scene(receipt["id"])
        with self.assertRaises(rc.RoomrenderError) as caught:
            self.client.get_scene(receipt["id"])
        self.assertEqual(caught.exception.status, 404)


class StoredTextures(ServerTest):
    needs = [("post", "/v1/textures"), ("get", "/v1/textures/{id}"), ("delete", "/v1/textures/{id}"),
             ("post", "/v1/scenes")]

    def test_a_texture_naming_the_stored_image_draws_as_its_data_uri(self):
        import base64
        request = small(load_example("studio_textured"))
        texture = request["scene"]["walls"][0]["right_texture"]
        png = base64.b64decode(texture["image"].split(",", 1)[1])
        receipt = self.client.store_texture(png)
        self.assertRegex(receipt["id"], r"^[0-9a-f]{16}$")
        self.assertEqual(receipt["media_type"], "image/png")
        self.assertEqual(self.client.store_texture(png)["id"], receipt["id"])  # content-addressed
        self.assertEqual(self.client.get_texture(receipt["id"]), png)
        inline = self.client.render(request, json_answer=False).png
        by_id = json.loads(json.dumps(request))
        by_id["scene"]["walls"][0]["right_texture"]["image"] = receipt["id"]
        self.assertEqual(self.client.render(by_id, json_answer=False).png, inline)

        scene = self.client.store_scene(by_id["scene"])
        with self.assertRaises(rc.RoomrenderError) as caught:
            self.client.delete_texture(receipt["id"])
        self.assertEqual(caught.exception.status, 409)
        self.client.delete_scene(scene["id"])
        self.client.delete_texture(receipt["id"])
        with self.assertRaises(rc.RoomrenderError) as caught:
            self.client.get_texture(receipt["id"])
        self.assertEqual(caught.exception.status, 404)


class CameraPath(ServerTest):
    def test_orbit_cameras_keep_distance_height_and_target(self):
        camera = load_example("studio")["camera"]
        cameras = rc.orbit_cameras(camera, 8)
        self.assertEqual(len(cameras), 8)
        self.assertEqual(cameras[0]["position"], [round(x, 6) for x in camera["position"]])
        tx, _, tz = camera["target"]
        radius = math.hypot(camera["position"][0] - tx, camera["position"][2] - tz)
        angles = []
        for c in cameras:
            x, y, z = c["position"]
            self.assertAlmostEqual(math.hypot(x - tx, z - tz), radius, places=5)
            self.assertEqual(y, camera["position"][1])
            self.assertEqual(c["target"], camera["target"])
            angles.append(math.atan2(x - tx, z - tz))
        steps = [(b - a) % (2 * math.pi) for a, b in zip(angles, angles[1:])]
        for s in steps:
            self.assertAlmostEqual(s, 2 * math.pi / 8, places=5)
        with self.assertRaises(ValueError):
            rc.orbit_cameras(camera, 0)

    def test_render_path_writes_numbered_frames_with_a_progress_bar(self):
        request = small(load_example("studio"), 96, 72)
        out = self.tmpdir()
        progress = io.StringIO()
        paths = self.client.render_path(request, rc.orbit_cameras(request["camera"], 4), out,
                                        progress=rc.ProgressBar(progress))
        self.assertEqual([os.path.basename(p) for p in paths],
                         ["frame_0001.png", "frame_0002.png", "frame_0003.png", "frame_0004.png"])
        frames = [self.read_png(p, (96, 72)) for p in paths]
        self.assertEqual(len(set(frames)), 4, "every frame shows a different view")
        self.assertEqual(frames[0], self.client.render(request, json_answer=False).png)  # frame 1 is the start
        self.assertIn("4/4 frame_0004.png", progress.getvalue())
        inline = self.client.render_path(request, rc.orbit_cameras(request["camera"], 4), self.tmpdir(), use_store=False)
        for p, frame in zip(inline, frames):
            self.assertEqual(self.read_png(p, (96, 72)), frame, "stored and inline paths draw the same frames")


class Import(ServerTest):
    needs = [("post", "/v1/import/{format}")]

    def test_sweet_home_3d_home_becomes_a_request_that_renders(self):
        with open(HOME_XML, "rb") as f:
            request = self.client.import_file(f.read(), "sh3d", width=160, height=120)
        walls = request["scene"]["walls"]
        self.assertEqual(len(walls), 5)
        self.assertEqual(sorted(o["type"] for w in walls for o in w.get("openings", [])), ["door", "window"])
        self.assertEqual(rc.png_size(self.client.render(request).png), (160, 120))

    def test_store_option_stores_the_home(self):
        with open(HOME_XML, "rb") as f:
            receipt = self.client.import_file(f.read(), "sh3d", store=True)
        view = self.client.render_stored(receipt["id"], receipt["camera"], {"width": 80, "height": 60})
        self.assertEqual(rc.png_size(view.png), (80, 60))


class Catalogue(ServerTest):
    needs = [("get", "/v1/catalogue"), ("post", "/v1/pick")]

    def test_a_catalogue_chair_is_a_piece_that_renders_and_picks_whole(self):
        catalogue = self.client.catalogue()
        self.assertIn("CC BY 3.0", catalogue["attribution"])
        chair = next(item for item in catalogue["items"] if item["id"] == "chair")
        self.assertEqual(chair["size_cm"], {"width": 40, "depth": 42, "height": 90})
        self.assertEqual(rc.png_size(self.client.catalogue_icon("chair"))[0] > 0, True)
        piece = rc.place_piece(chair, center=[0, 0], rotation_y=30, id="chair-1")
        self.assertEqual((piece["type"], piece["size"], piece["id"]), ("piece", [0.4, 0.9, 0.42], "chair-1"))
        request = {"scene": {"solids": [piece]}, "camera": {"position": [0, 1.2, 2], "target": [0, 0.45, 0]},
                   "options": {"width": 96, "height": 72}}
        result = self.client.render(request)
        self.assertEqual(rc.png_size(result.png), (96, 72))
        self.assertGreater(result.counts["polygons"], 12, "the model, not a box")
        hit = self.client.pick(request, 48, 36)
        self.assertEqual(hit["pointer"], "/scene/solids/0")
        self.assertTrue(hit["part"]["pointer"].startswith("/scene/solids/0/parts/"), hit["part"])
        # Its parts are read-only stored meshes: served, not deletable.
        ref = piece["parts"][0]["ref"]
        with self.assertRaises(rc.RoomrenderError) as refused:
            self.client._send("DELETE", f"/v1/meshes/{ref}")
        self.assertEqual(refused.exception.status, 403)

    def test_command_lists_the_catalogue(self):
        done = subprocess.run([sys.executable, CLIENT, "--url", self.server.url, "catalogue", "--category", "Bedroom"],
                              capture_output=True, text=True, timeout=120)
        self.assertEqual(done.returncode, 0, done.stderr)
        lines = done.stdout.splitlines()
        self.assertTrue(lines and all("\tBedroom\t" in line for line in lines), lines)
        self.assertIn("bed140x190\tBedroom\tBed 140x190\t158 x 208 x 70 cm", lines)


class CommandLine(ServerTest):
    def run_cli(self, *args, check=True):
        done = subprocess.run([sys.executable, CLIENT, "--url", self.server.url, *args],
                              capture_output=True, text=True, timeout=120)
        if check:
            self.assertEqual(done.returncode, 0, done.stderr)
        return done

    def test_render_writes_the_png_and_reports_timings(self):
        out = os.path.join(self.tmpdir(), "t.png")
        done = self.run_cli("render", os.path.join(REPO, "examples", "tetrahedron.json"), "-o", out,
                            "--width", "120", "--height", "90")
        report = json.loads(done.stdout)
        self.assertEqual((report["width"], report["height"]), (120, 90))
        self.assertGreater(report["timings_ms"]["total"], 0)
        self.read_png(out, (120, 90))

    def test_render_antialias_flag_sets_the_option(self):
        request = small(load_example("tetrahedron"), 96, 72)
        request["options"]["pipeline"] = "reference"
        out = os.path.join(self.tmpdir(), "aa.png")
        self.run_cli("render", self.write_json(request), "-o", out, "--antialias", "4")
        self.assertEqual(self.read_png(out, (96, 72)), self.client.render(rc.with_antialias(request, 4), json_answer=False).png)
        self.assertNotEqual(self.read_png(out, (96, 72)), self.client.render(request, json_answer=False).png)
        self.assertEqual(self.run_cli("render", self.write_json(request), "-o", out, "--antialias", "3", check=False).returncode, 2)

    def test_errors_print_pointer_and_detail_and_exit_1(self):
        bad = self.write_json({"options": {"width": 0}})
        done = self.run_cli("render", bad, "-o", os.path.join(self.tmpdir(), "x.png"), check=False)
        self.assertEqual(done.returncode, 1)
        self.assertTrue(done.stderr.startswith("/options/width: "), done.stderr)
        unreachable = subprocess.run([sys.executable, CLIENT, "--url", "http://127.0.0.1:9", "pipelines"],
                                     capture_output=True, text=True, timeout=60)
        self.assertEqual(unreachable.returncode, 1)
        self.assertIn("error:", unreachable.stderr)

    def test_orbit_writes_frames(self):
        out = self.tmpdir()
        done = self.run_cli("orbit", os.path.join(REPO, "examples", "tetrahedron.json"), "--frames", "3",
                            "--width", "64", "--height", "48", "--out-dir", out)
        self.assertEqual(json.loads(done.stdout)["frames"], 3)
        self.assertEqual(sorted(os.listdir(out)), ["frame_0001.png", "frame_0002.png", "frame_0003.png"])
        self.assertIn("3/3", done.stderr)

    def test_pipelines(self):
        self.assertIn("zbuffer", self.run_cli("pipelines").stdout.split())


class CurlScripts:
    def run_script(self, name, *args, expect_status=0):
        env = {**os.environ, "ROOMRENDER_URL": self.server.url}
        done = subprocess.run([os.path.join(CURL, name), *args], capture_output=True, text=True, env=env, timeout=120)
        self.assertEqual(done.returncode, expect_status, f"{name}: {done.stdout}\n{done.stderr}")
        return done


class CurlExamples(CurlScripts, ServerTest):
    def test_render(self):
        out = os.path.join(self.tmpdir(), "studio.png")
        done = self.run_script("render.sh", os.path.join(REPO, "examples", "studio.json"), out)
        self.assertIn("server-timing:", done.stdout.lower())
        self.read_png(out, (640, 480))

    def test_render_error_stops_with_the_problem(self):
        out = os.path.join(self.tmpdir(), "x.png")
        done = self.run_script("render.sh", self.write_json({"camera": {"fov_y": 500}}), out, expect_status=22)
        problem = next(json.loads(line) for line in done.stderr.splitlines() if line.startswith("{"))
        self.assertEqual(problem["errors"][0]["pointer"], "/camera/fov_y")
        self.assertFalse(os.path.exists(out), "no PNG file is left behind")


class CurlStoredScenes(CurlScripts, ServerTest):
    needs = StoredScenes.needs

    def test_render_json(self):
        out = os.path.join(self.tmpdir(), "a.png")
        done = self.run_script("render-json.sh", os.path.join(REPO, "examples", "tetrahedron.json"), out)
        self.assertGreater(json.loads(done.stdout)["counts"]["polygons"], 0)
        self.read_png(out, (640, 480))

    def test_store_and_render(self):
        out = self.tmpdir()
        self.run_script("store-and-render.sh", os.path.join(REPO, "examples", "studio.json"), out)
        views = {name: self.read_png(os.path.join(out, name + ".png"), (320, 240))
                 for name in ("view_post", "view_get", "view_top")}
        self.assertEqual(views["view_post"], views["view_get"], "POST and GET of the same view agree")
        self.assertNotEqual(views["view_top"], views["view_get"])

    def test_orbit(self):
        out = self.tmpdir()
        done = self.run_script("orbit.sh", os.path.join(REPO, "examples", "studio.json"), "4", out, "80", "60")
        names = sorted(n for n in os.listdir(out) if n.endswith(".png"))
        self.assertEqual(names, ["frame_0001.png", "frame_0002.png", "frame_0003.png", "frame_0004.png"])
        self.assertIn("4/4", done.stderr)
        frames = [self.read_png(os.path.join(out, n), (80, 60)) for n in names]
        self.assertEqual(len(set(frames)), 4)
        # The shell's path agrees with the Python client's: frame 3 of 4 is half a turn.
        request = small(load_example("studio"), 80, 60)
        half_turn = rc.orbit_cameras(request["camera"], 4)[2]
        self.assertEqual(self.client.render({**request, "camera": half_turn}, json_answer=False).png, frames[2])


class CurlImport(CurlScripts, ServerTest):
    needs = [("post", "/v1/import/{format}")]

    def test_import_sh3d(self):
        out = self.tmpdir()
        request, png = os.path.join(out, "home.json"), os.path.join(out, "home.png")
        self.run_script("import-sh3d.sh", HOME_XML, request, png)
        with open(request, encoding="utf-8") as f:
            self.assertEqual(len(json.load(f)["scene"]["walls"]), 5)
        self.read_png(png, (640, 480))


if __name__ == "__main__":
    unittest.main()
