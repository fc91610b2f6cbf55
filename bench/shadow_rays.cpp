// Shadow-ray throughput of the pipelines' tree (render/core/shadow_rays.hpp), and of Embree 3's
// rtcOccluded1 on the same rays when the build found Embree (the measurement behind choosing a tree
// of our own). Scene: one Sweet Home 3D home imported with its furniture models, as the service
// does. Rays: from a random point of the polygon seen in each of W x H pixels of the home's own
// camera (z-buffer ids) to each of the home's lights, one thread. Embree gets every opaque polygon
// fan-triangulated, in floats, with no caster rule and a fixed 1e-4 m start offset (the peers'
// setup: less work than the exact rule), so its time is a lower bound for the same job.
// Also the same rays with a memo per light (the last blocker first), and the work per ray of both.
//   bench_shadow_rays [--home 3BedroomApartment] [--size 640x360] [--out FILE]
#include "render/core/shadow_rays.hpp"
#include "render/core/timer.hpp"
#include "render/pipelines/pipeline_table.hpp"
#include "render/pipelines/render.hpp"
#include "tests/support/culling_cases.hpp"

#if defined(ROOMRENDER_HAVE_EMBREE)
#include <embree3/rtcore.h>
#endif

#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <random>

using namespace rr;

namespace {

struct Ray {
  uint32_t self;
  Vec3 p;
  uint32_t light;
};

}  // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::string> a{{"--home", "3BedroomApartment"}, {"--size", "640x360"}, {"--out", ""}};
  for (int i = 1; i + 1 < argc; i += 2) a[argv[i]] = argv[i + 1];
  const auto data = std::filesystem::path(ROOMRENDER_SOURCE_DIR).parent_path() / "shared" / "data";
  const auto scenes = testing::culling_scenes("homes", ROOMRENDER_SOURCE_DIR, data, {a["--home"]});
  if (scenes.empty()) {
    std::cerr << "no home " << a["--home"] << " under " << data << "\n";
    return 1;
  }
  RenderRequest request = scenes[0].request;
  std::sscanf(a["--size"].c_str(), "%dx%d", &request.options.width, &request.options.height);
  request.options.pipeline = pipeline_id("zbuffer");
  request.options.shadows = false;
  const PreparedScene prepared = prepare_scene(request.scene);
  const PolygonSoup& soup = prepared.soup;
  Stopwatch build_clock;
  const ShadowBvh bvh = build_shadow_bvh(soup, *prepared.hierarchy);
  const double build_ms = build_clock.elapsed_ms();
  const RenderOutcome frame = render(request, prepared);
  std::mt19937 rng(31);
  std::vector<Ray> rays;
  for (uint32_t id : frame.frame.ids.ids) {
    if (id == background_id) continue;
    // Ids are soup indices for a scene drawn whole.
    const Polygon& poly = soup.polygons[id];
    const auto points = soup.points(poly);
    const size_t k = rng() % (points.size() - 2);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    double s = u(rng), t = u(rng);
    if (s + t > 1.0) s = 1.0 - s, t = 1.0 - t;
    const Vec3 p = points[0] + s * (points[k + 1] - points[0]) + t * (points[k + 2] - points[0]);
    for (uint32_t l = 0; l < prepared.scene.lights.size(); ++l) rays.push_back({id, p, l});
  }
  Stopwatch clock;
  size_t blocked = 0;
  std::vector<uint8_t> ours(rays.size());
  for (size_t i = 0; i < rays.size(); ++i) {
    ours[i] = shadow_ray_blocked(bvh, rays[i].self, rays[i].p, prepared.scene.lights[rays[i].light]);
    blocked += ours[i];
  }
  const double ours_ms = clock.elapsed_ms();
  // The same rays with a memo per light (the last blocker tried first, as SurfaceShader does), timed,
  // then once more counting the work (the counters cost time of their own).
  std::vector<ShadowRayMemo> memos(prepared.scene.lights.size());
  Stopwatch memo_clock;
  size_t memo_disagree = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    const Light& light = prepared.scene.lights[rays[i].light];
    memo_disagree += shadow_ray_blocked(bvh, rays[i].self, rays[i].p, light, &memos[rays[i].light]) != bool(ours[i]);
  }
  const double memo_ms = memo_clock.elapsed_ms();
  ShadowRayStats plain, memo;
  std::fill(memos.begin(), memos.end(), ShadowRayMemo{});
  for (const Ray& ray : rays) {
    const Light& light = prepared.scene.lights[ray.light];
    shadow_ray_blocked(bvh, ray.self, ray.p, light, nullptr, &plain);
    shadow_ray_blocked(bvh, ray.self, ray.p, light, &memos[ray.light], &memo);
  }
  auto per_ray = [](const ShadowRayStats& st) {
    const double n = double(std::max<uint64_t>(st.rays, 1));
    return nlohmann::json{{"nodes_per_ray", double(st.nodes) / n},
                          {"polygons_per_ray", double(st.polygons) / n},
                          {"memo_hits", st.memo_hits}};
  };
  nlohmann::json out = {{"home", a["--home"]},
                        {"polygons", soup.polygons.size()},
                        {"lights", prepared.scene.lights.size()},
                        {"rays", rays.size()},
                        {"blocked", blocked},
                        {"tree_nodes", bvh.nodes.size()},
                        {"tree_depth", bvh.depth},
                        {"tree_leaves", bvh.leaf_begin.size() - 1},
                        {"tree_bytes", bvh.bytes()},
                        {"tree_build_ms", build_ms},
                        {"ours_ms", ours_ms},
                        {"ours_ns_per_ray", 1e6 * ours_ms / double(rays.size())},
                        {"ours_work", per_ray(plain)},
                        {"memo_ms", memo_ms},
                        {"memo_ns_per_ray", 1e6 * memo_ms / double(rays.size())},
                        {"memo_work", per_ray(memo)},
                        {"memo_disagreeing_rays", memo_disagree}};
#if defined(ROOMRENDER_HAVE_EMBREE)
  RTCDevice device = rtcNewDevice(nullptr);
  RTCScene scene = rtcNewScene(device);
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  std::vector<std::array<float, 3>> vertices;
  std::vector<std::array<unsigned, 3>> triangles;
  for (const Polygon& poly : soup.polygons) {
    if (poly.flags & polygon_translucent) continue;
    const auto points = soup.points(poly);
    const unsigned first = unsigned(vertices.size());
    for (const Vec3& p : points) vertices.push_back({float(p.x), float(p.y), float(p.z)});
    for (unsigned k = 1; k + 1 < points.size(); ++k) triangles.push_back({first, first + k, first + k + 1});
  }
  std::copy(vertices.begin(), vertices.end(),
            static_cast<std::array<float, 3>*>(rtcSetNewGeometryBuffer(
                geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), vertices.size())));
  std::copy(triangles.begin(), triangles.end(),
            static_cast<std::array<unsigned, 3>*>(rtcSetNewGeometryBuffer(
                geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), triangles.size())));
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(scene, geometry);
  rtcReleaseGeometry(geometry);
  Stopwatch embree_build;
  rtcCommitScene(scene);
  out["embree_build_ms"] = embree_build.elapsed_ms();
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  size_t embree_blocked = 0, disagree = 0;
  Stopwatch embree_clock;
  for (size_t i = 0; i < rays.size(); ++i) {
    const Light& light = prepared.scene.lights[rays[i].light];
    const bool directional = light.type == LightType::directional;
    const Vec3 d = directional ? -light.direction : light.position - rays[i].p;
    RTCRay ray{};
    ray.org_x = float(rays[i].p.x), ray.org_y = float(rays[i].p.y), ray.org_z = float(rays[i].p.z);
    ray.dir_x = float(d.x), ray.dir_y = float(d.y), ray.dir_z = float(d.z);
    const double length = glm::length(d);
    ray.tnear = float(1e-4 / length);
    ray.tfar = directional ? std::numeric_limits<float>::infinity() : float(1.0 - 1e-4 / length);
    ray.mask = 0xFFFFFFFFu;
    rtcOccluded1(scene, &context, &ray);
    const bool b = ray.tfar < 0.0f;
    embree_blocked += b;
    disagree += b != bool(ours[i]);
  }
  out["embree_ms"] = embree_clock.elapsed_ms();
  out["embree_ns_per_ray"] = 1e6 * out["embree_ms"].get<double>() / double(rays.size());
  out["embree_blocked"] = embree_blocked;
  out["embree_disagreeing_rays"] = disagree;
  rtcReleaseScene(scene);
  rtcReleaseDevice(device);
#endif
  std::cout << out.dump() << "\n";
  if (!a["--out"].empty()) std::ofstream(a["--out"]) << out.dump(2) << "\n";
  return 0;
}
