// Occlusion culling, two measures (docs/culling.md; bench/culling.py drives them with the peers).
//
//   bench_culling frames --request R.json [--seed S] [--inside N] [--threads T] [--frames F] [--size WxH]
//                        [--light-dir x,y,z] [--out FILE]
// The request's own camera and N seeded inside cameras at eye height (tests/support/culling_cases.hpp),
// zbuffer flat, each drawn with culling off, on without the cells' portal walk (occlusion) and on,
// frame after frame interleaved so machine drift cancels: per camera the median frame times, the
// polygons projected and the other counters, and the camera itself (so a peer can be given the same
// view). --light-dir replaces the lights by one sun.
//
//   bench_culling picture --request R.json --out-frame F.png --out-above A.png [--size WxH]
// The picture of docs/culling.md (run_picture below).
//
//   bench_culling plan --request R.json --out-plan P.png [--eye x,y,z --target x,y,z] [--scale PX_PER_M]
// The plan picture of docs/culling.md's cells: the scene's cells and portals per level, the camera,
// and the cells its portal walk reached (run_plan below).
//
//   bench_culling identity [--root DIR] [--data DIR] [--cameras N] [--seed S] [--size WxH] [--threads T]
//                          [--out FILE]
// The full identity matrix: every example, every home with its models, five R2V plans and the fireplace
// room, from N seeded cameras each (and its own), zbuffer and bsp at 1 and 4 samples, flat and Phong
// with shadows, culling on and off: counts the pairs and lists any that differ (there must be none).
#include "render/core/cells.hpp"
#include "render/core/draw.hpp"
#include "render/core/frustum.hpp"
#include "render/core/occlusion.hpp"
#include "render/core/png.hpp"
#include "render/core/timer.hpp"
#include "render/pipelines/pipeline.hpp"
#include "render/pipelines/pipeline_table.hpp"
#include "render/pipelines/render.hpp"
#include "render/pipelines/shadow_cache.hpp"
#include "render/scene_io/scene_json.hpp"
#include "tests/support/culling_cases.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <vector>

using namespace rr;
using nlohmann::json;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

json camera_json(const Camera& c) {
  return {{"position", {c.position.x, c.position.y, c.position.z}},
          {"target", {c.target.x, c.target.y, c.target.z}},
          {"up", {c.up.x, c.up.y, c.up.z}},
          {"fov_y", c.fov_y_deg},
          {"near", c.near},
          {"far", c.far}};
}

Vec3 parse_vec3(const std::string& text) {
  Vec3 v(0.0);
  std::sscanf(text.c_str(), "%lf,%lf,%lf", &v.x, &v.y, &v.z);
  return v;
}

json run_frames(std::map<std::string, std::string>& a) {
  json request_json = json::parse(std::ifstream(a["--request"]));
  RenderRequest request = request_from_json(request_json);
  if (a.count("--light-dir")) {
    Light sun;
    sun.type = LightType::directional;
    sun.direction = -glm::normalize(parse_vec3(a["--light-dir"]));
    request.scene.lights = {sun};
  }
  int width = 1280, height = 720;
  std::sscanf(a["--size"].c_str(), "%dx%d", &width, &height);
  request.options.width = width, request.options.height = height;
  request.options.pipeline = pipeline_id("zbuffer");
  request.options.shading = ShadingMode::flat;
  request.options.shadows = false;
  const PreparedScene scene = prepare_scene(request.scene);
  const int frames = std::stoi(a["--frames"]), inside = std::stoi(a["--inside"]);
  const unsigned threads = unsigned(std::stoi(a["--threads"]));
  std::vector<testing::SeededCamera> cameras =
      testing::seeded_cameras(request, scene.soup, std::stoull(a["--seed"]), inside, 1);
  cameras[0].kind = "observer";
  json out = json::array();
  for (const testing::SeededCamera& cam : cameras) {
    // off: culling off; occlusion: culling on without the portal walk; on: culling on with it.
    enum Mode { off, occlusion, on };
    std::map<Mode, std::vector<double>> ms;
    std::map<Mode, RenderReport> last;
    for (int f = -1; f < frames; ++f) {  // frame -1 warms the caches and the pages
      for (Mode mode : {off, occlusion, on}) {
        RenderRequest r = request;
        r.camera = cam.camera;
        r.options.culling = mode == off ? CullingMode::off : CullingMode::on;
        RenderContext context;
        context.threads = threads;
        context.encode = false;
        context.use_cells = mode == on;
        Stopwatch clock;
        RenderOutcome o = render(r, scene, context);
        if (f >= 0) ms[mode].push_back(clock.elapsed_ms());
        last[mode] = o.report;
      }
    }
    auto counts = [&](Mode m) {
      const RenderStats& s = last[m].stats;
      return json{{"frame_ms", median(ms[m])},
                  {"cull_ms", last[m].timings.cull_ms},
                  {"polygons_projected", s.polygons_projected},
                  {"objects_occluded", s.objects_occluded},
                  {"nodes_tested", s.nodes_tested},
                  {"cells", s.cells},
                  {"cells_visited", s.cells_visited},
                  {"portals_walked", s.portals_walked},
                  {"fragments", s.fragments}};
    };
    out.push_back({{"kind", cam.kind},
                   {"camera", camera_json(cam.camera)},
                   {"polygons", scene.soup.polygons.size()},
                   {"off", counts(off)},
                   {"occlusion", counts(occlusion)},
                   {"on", counts(on)}});
  }
  return out;
}

json run_identity(std::map<std::string, std::string>& a) {
  const std::filesystem::path root = a["--root"];
  std::optional<std::filesystem::path> data;
  if (std::filesystem::is_directory(a["--data"])) data = a["--data"];
  int width = 1280, height = 720;
  std::sscanf(a["--size"].c_str(), "%dx%d", &width, &height);
  const uint64_t seed = std::stoull(a["--seed"]);
  const int per_kind = std::max(1, std::stoi(a["--cameras"]) / 4);
  BspCache bsp_cache(size_t(4) << 30);
  ShadowCache shadow_cache(size_t(1) << 30);
  size_t pairs = 0, scenes = 0, cameras = 0;
  json differing = json::array();
  Stopwatch clock;
  for (const char* which : {"examples", "homes", "r2v", "fireplace"}) {
    std::vector<testing::CullingScene> list = testing::culling_scenes(which, root, data);
    if (std::string(which) == "r2v" && list.size() > 5) list.resize(5);
    for (const testing::CullingScene& s : list) {
      const PreparedScene scene = prepare_scene(s.request.scene);
      ++scenes;
      for (const testing::SeededCamera& cam : testing::seeded_cameras(s.request, scene.soup, seed, per_kind)) {
        ++cameras;
        for (const PipelineInfo& row : pipeline_table()) {
          if (!row.occlusion_culling) continue;
          for (int samples : {1, 4}) {
            for (bool phong : {false, true}) {
              RenderOutcome result[2];
              for (int k = 0; k < 2; ++k) {
                RenderRequest r = s.request;
                r.camera = cam.camera;
                r.options.width = width, r.options.height = height;
                r.options.pipeline = pipeline_id(row);
                r.options.antialias = samples;
                r.options.shading = phong ? ShadingMode::phong : ShadingMode::flat;
                r.options.shadows = phong;
                r.options.culling = k ? CullingMode::on : CullingMode::off;
                RenderContext context;
                context.threads = unsigned(std::stoi(a["--threads"]));
                context.bsp_cache = &bsp_cache;
                context.shadow_cache = &shadow_cache;
                result[k] = render(r, scene, context);  // the PNG too: its bytes are the contract
              }
              ++pairs;
              if (result[0].png != result[1].png || result[0].frame.ids.ids != result[1].frame.ids.ids) {
                differing.push_back({{"scene", s.name},
                                     {"camera", cam.kind},
                                     {"pipeline", row.name},
                                     {"antialias", samples},
                                     {"shading", phong ? "phong+shadows" : "flat"}});
                std::cerr << "DIFFERS: " << differing.back() << "\n";
              }
            }
          }
        }
      }
      std::cerr << which << " " << s.name << ": " << pairs << " pairs so far, " << differing.size() << " differ\n";
    }
  }
  return {{"seed", seed},
          {"size", a["--size"]},
          {"scenes", scenes},
          {"cameras", cameras},
          {"pairs", pairs},
          {"differing", differing},
          {"seconds", clock.elapsed_ms() / 1000.0}};
}

// The picture of docs/culling.md: the home's frame from its observer camera, and the same home from
// above with every polygon coloured by what the observer's frame did with it: drawn (green), skipped
// as hidden by the occlusion walk (red), or outside the view frustum or facing away (light grey).
json run_picture(std::map<std::string, std::string>& a) {
  RenderRequest request = request_from_json(json::parse(std::ifstream(a["--request"])));
  int width = 1280, height = 720;
  std::sscanf(a["--size"].c_str(), "%dx%d", &width, &height);
  request.options.width = width, request.options.height = height;
  const PreparedScene scene = prepare_scene(request.scene);
  RenderContext context;
  context.threads = 2;
  const RenderOutcome frame = render(request, scene, context);
  std::ofstream(a["--out-frame"], std::ios::binary) << frame.png;

  const ViewTransform view = make_view(request.camera, width, height);
  const PolygonSoup& soup = scene.soup;
  const ObjectsInView objects = objects_in_view(soup, view);
  std::vector<uint8_t> drawn(soup.polygons.size()), opaque(soup.polygons.size());
  for (size_t i = 0; i < soup.polygons.size(); ++i) {
    const Polygon& p = soup.polygons[i];
    drawn[i] = !is_back_facing(p, view.eye) && objects.visible[p.object];
    opaque[i] = !(p.flags & polygon_translucent);
  }
  OcclusionResult walk;
  walk_occlusion(*scene.hierarchy, soup, {}, {drawn, opaque}, view, 0, walk);
  PolygonSoup tinted = soup;
  const uint32_t red = uint32_t(tinted.materials.size()), grey = red + 1;
  Material m;
  m.color = Color{0.85f, 0.1f, 0.1f};
  tinted.materials.push_back(m);
  m.color = Color{0.8f, 0.8f, 0.8f};
  tinted.materials.push_back(m);
  m.color = Color{0.2f, 0.7f, 0.25f};
  tinted.materials.push_back(m);
  const uint32_t green = grey + 1;
  size_t hidden = 0, shown = 0, elsewhere = 0;
  for (size_t i = 0; i < tinted.polygons.size(); ++i) {
    Polygon& p = tinted.polygons[i];
    p.flags &= ~uint32_t(polygon_translucent);
    if (walk.shown[i]) {
      ++shown;
      p.material = green;
    } else if (drawn[i]) {
      p.material = red, ++hidden;
    } else {
      p.material = grey, ++elsewhere;
    }
  }
  // From above, ceilings left out (they are the observer's, but would hide the rooms).
  Camera above = request.camera;
  Vec3 lo(1e300), hi(-1e300);
  for (const Vec3& q : soup.positions) lo = glm::min(lo, q), hi = glm::max(hi, q);
  const Vec3 centre = 0.5 * (lo + hi);
  above.position = Vec3(centre.x, hi.y + 1.2 * std::max(hi.x - lo.x, hi.z - lo.z), centre.z + 0.01);
  above.target = centre, above.up = Vec3(0.0, 0.0, -1.0), above.fov_y_deg = 50.0, above.near = 0.5;
  above.far = 10.0 * glm::length(hi - lo);
  PolygonSoup roofless;
  roofless.materials = tinted.materials, roofless.objects = tinted.objects;
  for (const Polygon& p : tinted.polygons) {
    if (tinted.objects[p.object].ceiling) continue;
    Polygon q = p;
    q.first_vertex = uint32_t(roofless.positions.size());
    for (const Vec3& v : tinted.points(p)) roofless.positions.push_back(v);
    for (const glm::vec3& n : tinted.vertex_normals(p)) roofless.normals.push_back(n);
    roofless.polygons.push_back(q);
  }
  RenderOptions options = request.options;
  options.culling = CullingMode::off;
  options.shading = ShadingMode::flat;
  options.shadows = false;
  Scene lit = scene.scene;
  lit.lights = {Light{}};
  lit.lights[0].direction = glm::normalize(Vec3(-0.3, -1.0, -0.2));
  RenderResult top = render_frame(lit, roofless, above, options, RenderContext{});
  // The observer: a white disc where it stands.
  const Vec2 eye = project_to_screen(make_view(above, width, height), request.camera.position);
  for (int y = -6; y <= 6; ++y) {
    for (int x = -6; x <= 6; ++x) {
      const int px = int(eye.x) + x, py = int(eye.y) + y;
      if (x * x + y * y > 36 || px < 0 || py < 0 || px >= width || py >= height) continue;
      uint8_t* rgb = top.frame.image.rgb.data() + (size_t(py) * size_t(width) + size_t(px)) * 3;
      rgb[0] = rgb[1] = rgb[2] = (x * x + y * y > 20) ? 0 : 255;
    }
  }
  std::ofstream(a["--out-above"], std::ios::binary) << encode_png(top.frame.image, PngCompression::small, 2);
  return {{"polygons", soup.polygons.size()},
          {"shown", shown},
          {"hidden", hidden},
          {"elsewhere", elsewhere},
          {"nodes_tested", walk.nodes_tested},
          {"occluders", walk.occluders}};
}

// The plan picture of docs/culling.md: each band of the scene's cells seen from above (the cells the
// camera's portal walk reached in colours, the others light grey, the outside white, blocked wall
// squares dark, doorway zones orange), the openings' portals as blue strokes, the boundaries between
// cells of one walled space as magenta boxes, and the camera with its view's edges.
json run_plan(std::map<std::string, std::string>& a) {
  RenderRequest request = request_from_json(json::parse(std::ifstream(a["--request"])));
  int width = 1280, height = 720;
  std::sscanf(a["--size"].c_str(), "%dx%d", &width, &height);
  if (a.count("--eye")) request.camera.position = parse_vec3(a["--eye"]);
  if (a.count("--target")) request.camera.target = parse_vec3(a["--target"]);
  const PreparedScene scene = prepare_scene(request.scene);
  if (a.count("--camera")) {  // one of the identity checks' seeded cameras (culling_cases.hpp)
    const auto cams = testing::seeded_cameras(request, scene.soup, std::stoull(a["--seed"]), 1);
    request.camera = cams[size_t(std::stoi(a["--camera"]))].camera;
  }
  const SceneCells& cells = *scene.cells;
  const ViewTransform view = make_view(request.camera, width, height);
  CellWalk walk;
  walk_cells(cells, cell_conditions(cells, {}), cell_viewpoint(view), walk);
  RenderRequest r = request;
  r.options.width = width, r.options.height = height;
  RenderContext context;
  context.encode = false;
  const RenderOutcome frame = render(r, scene, context);
  json out = {{"camera", camera_json(request.camera)},
              {"cells", cells.cells.size()},
              {"portals", cells.undirected_portals},
              {"square_m", cells.square},
              {"bands", cells.bands.size()},
              {"reached", walk.cells_visited},
              {"portals_walked", walk.portals_walked},
              {"polygons", scene.soup.polygons.size()},
              {"polygons_projected", frame.report.stats.polygons_projected},
              {"bytes", cells.bytes()}};
  json list = json::array();
  for (size_t c = 0; c < cells.cells.size(); ++c) {
    const Cell& cell = cells.cells[c];
    list.push_back({{"band", cell.band},
                    {"room", cell.room >= 0 ? request.scene.geometry.rooms[size_t(cell.room)].id : ""},
                    {"reached", bool(walk.reached[c])}});
  }
  out["cell_list"] = list;
  if (!cells.derived() || !a.count("--out-plan")) return out;
  const double px_per_m = std::stod(a.count("--scale") ? a["--scale"] : "60");
  const int bw = int(cells.nx * cells.square * px_per_m), bh = int(cells.nz * cells.square * px_per_m);
  const int gap = 20;
  Image image(int(cells.bands.size()) * (bw + gap) - gap, bh, Color{1.0f, 1.0f, 1.0f});
  auto hue = [](size_t c, bool strong) {
    const double h = std::fmod(double(c) * 0.618033988749895, 1.0) * 6.0;
    const double f = h - std::floor(h);
    double rgb[3];
    switch (int(h)) {
      case 0:
        rgb[0] = 1, rgb[1] = f, rgb[2] = 0;
        break;
      case 1:
        rgb[0] = 1 - f, rgb[1] = 1, rgb[2] = 0;
        break;
      case 2:
        rgb[0] = 0, rgb[1] = 1, rgb[2] = f;
        break;
      case 3:
        rgb[0] = 0, rgb[1] = 1 - f, rgb[2] = 1;
        break;
      case 4:
        rgb[0] = f, rgb[1] = 0, rgb[2] = 1;
        break;
      default:
        rgb[0] = 1, rgb[1] = 0, rgb[2] = 1 - f;
        break;
    }
    const double mix = strong ? 0.35 : 0.8;
    return std::array<uint8_t, 3>{uint8_t(255 * (mix + (1 - mix) * rgb[0])), uint8_t(255 * (mix + (1 - mix) * rgb[1])),
                                  uint8_t(255 * (mix + (1 - mix) * rgb[2]))};
  };
  auto put = [&](int x, int y, std::array<uint8_t, 3> c) {
    if (x < 0 || y < 0 || x >= image.width || y >= image.height) return;
    uint8_t* p = image.pixel(x, y);
    p[0] = c[0], p[1] = c[1], p[2] = c[2];
  };
  auto to_px = [&](size_t band, Vec2 plan) {
    return Vec2(double(band) * (bw + gap) + (plan.x - cells.origin.x) * px_per_m, (plan.y - cells.origin.y) * px_per_m);
  };
  auto line = [&](size_t band, Vec2 p, Vec2 q, std::array<uint8_t, 3> c, int thick) {
    const Vec2 from = to_px(band, p), to = to_px(band, q);
    const int steps = int(std::max(1.0, glm::length(to - from)));
    for (int k = 0; k <= steps; ++k) {
      const Vec2 m = from + (to - from) * (double(k) / steps);
      for (int dy = -thick / 2; dy <= thick / 2; ++dy) {
        for (int dx = -thick / 2; dx <= thick / 2; ++dx) put(int(m.x) + dx, int(m.y) + dy, c);
      }
    }
  };
  for (size_t b = 0; b < cells.bands.size(); ++b) {
    for (int y = 0; y < bh; ++y) {
      for (int x = 0; x < bw; ++x) {
        const int i = int(x / (cells.square * px_per_m)), j = int(y / (cells.square * px_per_m));
        if (i >= cells.nx || j >= cells.nz) continue;
        const CellBand& band = cells.bands[b];
        const CellBand::Run* first = band.runs.data() + band.row_first[size_t(j)];
        const CellBand::Run* last = band.runs.data() + band.row_first[size_t(j) + 1];
        const CellBand::Run* run =
            std::upper_bound(first, last, uint32_t(i), [](uint32_t v, const CellBand::Run& q) { return v < q.x; }) - 1;
        const uint32_t v = run->value;
        std::array<uint8_t, 3> c{255, 255, 255};
        if (v == blocked_square) c = {70, 70, 70};
        else if (v & zone_bit) c = {240, 150, 40};
        else if (v != 0) c = walk.reached[v] ? hue(v, true) : std::array<uint8_t, 3>{215, 215, 215};
        put(int(b) * (bw + gap) + x, y, c);
      }
    }
  }
  for (const Portal& p : cells.portals) {
    if (p.from > p.to || (p.kind != PortalKind::opening && p.kind != PortalKind::boundary)) continue;
    const int band = std::max(cells.cells[p.from].band, cells.cells[p.to].band);
    for (uint32_t s = p.first; s < p.first + p.count; ++s) {
      const PortalShape& shape = cells.shapes[s];
      if (p.kind == PortalKind::opening) {
        line(size_t(band), Vec2(shape.corners[0].x, shape.corners[0].z), Vec2(shape.corners[1].x, shape.corners[1].z),
             {30, 60, 220}, 3);
        continue;
      }
      const Vec2 lo(shape.corners[0].x, shape.corners[0].z), hi(shape.corners[7].x, shape.corners[7].z);
      const std::array<uint8_t, 3> magenta{200, 0, 160};
      line(size_t(band), lo, Vec2(hi.x, lo.y), magenta, 1);
      line(size_t(band), Vec2(hi.x, lo.y), hi, magenta, 1);
      line(size_t(band), hi, Vec2(lo.x, hi.y), magenta, 1);
      line(size_t(band), Vec2(lo.x, hi.y), lo, magenta, 1);
    }
  }
  // The camera: a black disc and the edges of its view, 3 m long, on the band it stands in.
  size_t eye_band = 0;
  for (size_t b = 0; b < cells.bands.size(); ++b) {
    if (view.eye.y >= cells.bands[b].y0) eye_band = b;
  }
  const Vec2 eye(view.eye.x, view.eye.z);
  const Mat4 world_from_clip = glm::inverse(view.clip_from_world);
  for (double sx : {-1.0, 1.0}) {
    const Vec4 far = world_from_clip * Vec4(sx, 0.0, 1.0, 1.0);
    const Vec3 d = Vec3(far) / far.w - view.eye;
    const Vec2 dir = glm::normalize(Vec2(d.x, d.z));
    line(eye_band, eye, eye + 3.0 * dir, {0, 0, 0}, 2);
  }
  const Vec2 e = to_px(eye_band, eye);
  for (int dy = -6; dy <= 6; ++dy) {
    for (int dx = -6; dx <= 6; ++dx) {
      if (dx * dx + dy * dy <= 36) put(int(e.x) + dx, int(e.y) + dy, {0, 0, 0});
    }
  }
  std::ofstream(a["--out-plan"], std::ios::binary) << encode_png(image, PngCompression::small, 2);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: bench_culling frames|identity [flags] (see bench/culling.cpp)\n";
    return 2;
  }
  const std::string mode = argv[1];
  std::map<std::string, std::string> a = {{"--seed", "2029"},
                                          {"--inside", "10"},
                                          {"--threads", "2"},
                                          {"--frames", "9"},
                                          {"--size", "1280x720"},
                                          {"--cameras", "20"},
                                          {"--root", ROOMRENDER_SOURCE_DIR},
                                          {"--data", std::string(ROOMRENDER_SOURCE_DIR) + "/../shared/data"}};
  for (int i = 2; i + 1 < argc; i += 2) a[argv[i]] = argv[i + 1];
  const json result = mode == "frames"    ? run_frames(a)
                      : mode == "picture" ? run_picture(a)
                      : mode == "plan"    ? run_plan(a)
                                          : run_identity(a);
  if (a.count("--out")) std::ofstream(a["--out"]) << result.dump(1) << "\n";
  std::cout << result.dump() << "\n";
  return 0;
}
