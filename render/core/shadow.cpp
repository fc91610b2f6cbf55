// The shadow pass (see shadow.hpp). Per light: find the receivers the camera sees that the light
// reaches (clipped to the exact view frustum), keep the casters that can shadow one of them, and
// draw the casters' depth (shadow_raster.hpp) into a map fitted to those receivers. A light with no
// such caster gets no map, and a frame where no light has one skips the pass. The loops over
// polygons and maps run on parallel_for and keep their results in polygon order.
#include "render/core/shadow.hpp"

#include "render/core/draw.hpp"
#include "render/core/parallel.hpp"
#include "render/core/shadow_raster.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>

namespace rr {

using shadow_detail::cube_face_of;
using shadow_detail::cube_faces;
using shadow_detail::CubeFace;

TexelStore::TexelStore(int side)
    : pages_per_row_((size_t(side) + page_side - 1) / page_side), pages_(pages_per_row_ * pages_per_row_, 0) {}

void TexelStore::allocate_pages(std::span<const uint8_t> written) {
  const size_t count = size_t(std::count_if(written.begin(), written.end(), [](uint8_t w) { return w != 0; }));
  pool_.reserve(pool_.size() + count * page_texels);
  for (size_t i = 0; i < written.size() && i < pages_.size(); ++i) {
    if (!written[i] || pages_[i]) continue;
    pool_.resize(pool_.size() + page_texels);  // not zeroed (NoZeroAllocator)
    pages_[i] = uint32_t(pool_.size() / page_texels);
  }
}

namespace {

// glm matrices are column-major: m[column][row].
void set_row(Mat4& m, int row, Vec3 xyz, double w) {
  m[0][row] = xyz.x, m[1][row] = xyz.y, m[2][row] = xyz.z, m[3][row] = w;
}

using shadow_detail::clip_points;
using shadow_detail::ClipBuffers;
using shadow_detail::exact_frustum;

// Polygons per task of the loops over the soup.
constexpr size_t polygons_per_task = 1024;

bool expired(const CancelToken* cancel) { return cancel && cancel->expired(); }

// Polygons the camera may see, clipped to its frustum, with the side the shader lights.
struct Receivers {
  std::vector<Vec3> points;
  std::vector<uint32_t> begin{0};  // receiver r has points [begin[r], begin[r + 1])
  std::vector<Vec3> normal;        // lit side
  std::vector<double> offset;
  size_t size() const { return normal.size(); }
  std::span<const Vec3> polygon(size_t r) const { return {points.data() + begin[r], size_t(begin[r + 1] - begin[r])}; }
};

// Runs fn(task, worker, first, end) over the soup's polygons [first, end) in tasks of
// polygons_per_task; throws RenderCancelled afterwards when the render was cancelled meanwhile
// (a task that finds it so does nothing).
template <class Fn>
size_t for_polygon_tasks(const PolygonSoup& soup, unsigned threads, const CancelToken* cancel, Fn&& fn) {
  const size_t n = soup.polygons.size(), tasks = (n + polygons_per_task - 1) / polygons_per_task;
  parallel_for(threads, tasks, [&](size_t t, unsigned worker) {
    if (!expired(cancel)) fn(t, worker, t * polygons_per_task, std::min(n, (t + 1) * polygons_per_task));
  });
  check_cancel(cancel);
  return tasks;
}

Receivers collect_receivers(const PolygonSoup& soup, const ViewTransform& view, unsigned threads,
                            const CancelToken* cancel) {
  const Mat4 clip = exact_frustum(view.clip_from_world);
  std::vector<Receivers> parts((soup.polygons.size() + polygons_per_task - 1) / polygons_per_task);
  std::vector<ClipBuffers> buffers(std::max(1u, threads));
  for_polygon_tasks(soup, threads, cancel, [&](size_t task, unsigned worker, size_t first, size_t end) {
    Receivers& part = parts[task];
    for (size_t i = first; i < end; ++i) {
      const Polygon& p = soup.polygons[i];
      if (is_back_facing(p, view.eye) || !clip_points(clip, soup.points(p), buffers[worker])) continue;
      for (const ClipVertex& v : buffers[worker].out) part.points.push_back(v.p_world);
      part.begin.push_back(uint32_t(part.points.size()));
      const double side = lit_side(p, view.eye);
      part.normal.push_back(side * p.normal);
      part.offset.push_back(side * p.offset);
    }
  });
  Receivers out;  // the parts in polygon order
  for (const Receivers& part : parts) {
    const uint32_t base = uint32_t(out.points.size());
    out.points.insert(out.points.end(), part.points.begin(), part.points.end());
    for (size_t r = 1; r < part.begin.size(); ++r) out.begin.push_back(base + part.begin[r]);
    out.normal.insert(out.normal.end(), part.normal.begin(), part.normal.end());
    out.offset.insert(out.offset.end(), part.offset.begin(), part.offset.end());
  }
  return out;
}

// Every receiver any camera could see, for maps that serve all cameras: each polygon whole, a closed
// object's polygon on its front side, an open surface on both sides. Whatever a camera's
// collect_receivers keeps is part of one of these (a clipped piece, on one of its sides), so a map
// fitted to them covers every view, and their casters include every view's casters.
Receivers collect_scene_receivers(const PolygonSoup& soup, const CancelToken* cancel) {
  Receivers out;
  for (size_t i = 0; i < soup.polygons.size(); ++i) {
    if ((i & 4095) == 4095) check_cancel(cancel);
    const Polygon& p = soup.polygons[i];
    const bool open_surface = !(p.flags & polygon_closed);
    for (double side : {1.0, -1.0}) {
      if (side < 0.0 && !open_surface) break;
      for (const Vec3& v : soup.points(p)) out.points.push_back(v);
      out.begin.push_back(uint32_t(out.points.size()));
      out.normal.push_back(side * p.normal);
      out.offset.push_back(side * p.offset);
    }
  }
  return out;
}

struct Box {
  Vec3 lo{std::numeric_limits<double>::infinity()}, hi{-std::numeric_limits<double>::infinity()};
  void add(Vec3 p) { lo = glm::min(lo, p), hi = glm::max(hi, p); }
  bool empty() const { return !(lo.x <= hi.x); }
};

// True when some point of `box` lies strictly beyond the plane on side `sign` (+1: where
// dot(normal, p) > offset). Points on the plane cannot be shadowed by a polygon in it, hence the
// tolerance of ~1e-9 of the coordinates' magnitude (a box standing on the floor shares its plane).
bool box_reaches_beyond(const Box& box, Vec3 normal, double offset, double sign) {
  double best = -std::numeric_limits<double>::infinity(), magnitude = 1.0;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 p{corner & 1 ? box.hi.x : box.lo.x, corner & 2 ? box.hi.y : box.lo.y, corner & 4 ? box.hi.z : box.lo.z};
    best = std::max(best, sign * (glm::dot(normal, p) - offset));
    magnitude = std::max({magnitude, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  }
  return best > 1e-9 * magnitude;
}

// What the pass decided for one light before any memory is spent.
struct LightPlan {
  ShadowLight light;
  std::vector<uint32_t> casters;                      // polygon indices
  std::array<bool, 6> needed{};                       // cube faces (or [0]) that hold a receiver
  double min_u = 0, max_u = 0, min_v = 0, max_v = 0;  // directional: receivers' light-space rect
  double near_depth = 0, far_depth = 0;               // along forward (directional) or distance
  int map_count() const { return int(std::count(needed.begin(), needed.end(), true)); }
};

// The polygons keep(index, near) accepts, in polygon order. Each task keeps its own running minimum
// `near` (keep lowers it), folded in task order: the value one loop over all polygons would find.
template <class Keep>
std::vector<uint32_t> select_casters(const PolygonSoup& soup, unsigned threads, const CancelToken* cancel, double& near,
                                     Keep&& keep) {
  const size_t tasks = (soup.polygons.size() + polygons_per_task - 1) / polygons_per_task;
  std::vector<std::vector<uint32_t>> parts(tasks);
  std::vector<double> nears(tasks, std::numeric_limits<double>::infinity());
  for_polygon_tasks(soup, threads, cancel, [&](size_t task, unsigned, size_t first, size_t end) {
    for (size_t i = first; i < end; ++i) {
      if (keep(i, nears[task])) parts[task].push_back(uint32_t(i));
    }
  });
  std::vector<uint32_t> out;
  for (size_t t = 0; t < tasks; ++t) {
    out.insert(out.end(), parts[t].begin(), parts[t].end());
    near = std::min(near, nears[t]);
  }
  return out;
}

// A caster shadows points beyond its plane, seen from the light. Closed objects cast with their
// faces turned away from the light only: their silhouette is the same, and their lit faces are
// then never compared with their own depth (no acne on them). Translucent panes let light through.
// Returns the side (+1/-1 of the plane) the polygon shadows, or 0 when it casts nothing.
double caster_side(const Polygon& p, double facing /* > 0: the light is behind the plane */) {
  if (p.flags & polygon_translucent || facing == 0.0) return 0.0;
  if ((p.flags & polygon_closed) && facing < 0.0) return 0.0;
  return facing > 0.0 ? 1.0 : -1.0;
}

bool plan_directional(const Light& light, const Receivers& rec, const PolygonSoup& soup, unsigned threads,
                      const CancelToken* cancel, LightPlan& plan) {
  ShadowLight& sl = plan.light;
  sl.directional = true;
  sl.forward = light.direction;
  const Vec3 helper = std::abs(sl.forward.y) < 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
  sl.right = glm::normalize(glm::cross(sl.forward, helper));
  sl.up = glm::cross(sl.right, sl.forward);
  Box box;
  double inf = std::numeric_limits<double>::infinity();
  plan.min_u = plan.min_v = plan.near_depth = inf;
  plan.max_u = plan.max_v = plan.far_depth = -inf;
  for (size_t r = 0; r < rec.size(); ++r) {
    if (!light_reaches(light, rec.normal[r], rec.offset[r])) continue;
    for (const Vec3& p : rec.polygon(r)) {
      box.add(p);
      const double u = glm::dot(p, sl.right), v = glm::dot(p, sl.up);
      plan.min_u = std::min(plan.min_u, u), plan.max_u = std::max(plan.max_u, u);
      plan.min_v = std::min(plan.min_v, v), plan.max_v = std::max(plan.max_v, v);
      plan.far_depth = std::max(plan.far_depth, glm::dot(p, sl.forward));
    }
  }
  if (box.empty()) return false;
  plan.casters = select_casters(soup, threads, cancel, plan.near_depth, [&](size_t i, double& near) {
    const Polygon& p = soup.polygons[i];
    const double side = caster_side(p, glm::dot(p.normal, sl.forward));
    if (side == 0.0 || !box_reaches_beyond(box, p.normal, p.offset, side)) return false;
    double lo_u = inf, hi_u = -inf, lo_v = inf, hi_v = -inf, lo_d = inf;
    for (const Vec3& q : soup.points(p)) {
      const double u = glm::dot(q, sl.right), v = glm::dot(q, sl.up);
      lo_u = std::min(lo_u, u), hi_u = std::max(hi_u, u), lo_v = std::min(lo_v, v), hi_v = std::max(hi_v, v);
      lo_d = std::min(lo_d, glm::dot(q, sl.forward));
    }
    if (hi_u < plan.min_u || lo_u > plan.max_u || hi_v < plan.min_v || lo_v > plan.max_v) return false;
    if (lo_d >= plan.far_depth) return false;  // wholly beyond every receiver
    near = std::min(near, lo_d);
    return true;
  });
  plan.needed[0] = true;
  return !plan.casters.empty();
}

// The clip matrix of cube face `f` of a light at `c`: a 90-degree square frustum.
Mat4 cube_face_clip(const CubeFace& f, Vec3 c, double near, double far) {
  const double a = -(far + near) / (far - near), b = -2.0 * far * near / (far - near);
  Mat4 m(0.0);
  set_row(m, 0, f.right, -glm::dot(f.right, c));
  set_row(m, 1, f.up, -glm::dot(f.up, c));
  set_row(m, 2, -a * f.forward, a * glm::dot(f.forward, c) + b);
  set_row(m, 3, f.forward, -glm::dot(f.forward, c));
  return m;
}

bool plan_point(const Light& light, const Receivers& rec, const PolygonSoup& soup, unsigned threads,
                const CancelToken* cancel, LightPlan& plan) {
  ShadowLight& sl = plan.light;
  sl.directional = false;
  sl.position = light.position;
  Box box;
  std::vector<uint32_t> lit;
  double far = 0.0;
  for (size_t r = 0; r < rec.size(); ++r) {
    if (!light_reaches(light, rec.normal[r], rec.offset[r])) continue;
    lit.push_back(uint32_t(r));
    for (const Vec3& p : rec.polygon(r)) {
      box.add(p);
      far = std::max(far, glm::length(p - sl.position));
    }
  }
  if (lit.empty() || !(far > 0.0)) return false;
  // 1% beyond the farthest receiver, and a near plane that loses only casters within 1e-6 of that
  // distance of the light (1/w in float keeps its relative precision at any depth).
  plan.far_depth = far * 1.01;
  plan.near_depth = plan.far_depth * 1e-6;
  ClipBuffers buf;
  for (int f = 0; f < 6; ++f) {
    const Mat4 clip = exact_frustum(cube_face_clip(cube_faces[f], sl.position, plan.near_depth, plan.far_depth));
    for (uint32_t r : lit) {
      if (clip_points(clip, rec.polygon(r), buf)) {
        plan.needed[size_t(f)] = true;
        break;
      }
    }
  }
  double unused = 0.0;
  plan.casters = select_casters(soup, threads, cancel, unused, [&](size_t i, double&) {
    const Polygon& p = soup.polygons[i];
    const double side = caster_side(p, p.offset - glm::dot(p.normal, sl.position));
    return side != 0.0 && box_reaches_beyond(box, p.normal, p.offset, side);
  });
  return !plan.casters.empty() && plan.map_count() > 0;
}

// Fits the directional map to the receivers' rectangle with a margin of the PCF radius + 1 texels,
// so every tap of a visible receiver reads a texel that was drawn.
Mat4 fit_directional(LightPlan& plan, int side, int pcf) {
  ShadowLight& sl = plan.light;
  const int margin = pcf / 2 + 1;
  const double usable = double(std::max(1, side - 2 * margin));
  const double scale =
      std::max({1.0, std::abs(plan.min_u), std::abs(plan.max_u), std::abs(plan.min_v), std::abs(plan.max_v)});
  sl.texel_u = std::max(plan.max_u - plan.min_u, 1e-9 * scale) / usable;
  sl.texel_v = std::max(plan.max_v - plan.min_v, 1e-9 * scale) / usable;
  sl.left = plan.min_u - margin * sl.texel_u;
  sl.top = plan.max_v + margin * sl.texel_v;
  const double range = plan.far_depth - plan.near_depth;
  const double near = plan.near_depth - 0.01 * range, far = plan.far_depth + 0.01 * range + 1e-9 * scale;
  sl.far_depth = far;
  const double a = 2.0 / (side * sl.texel_u), b = 2.0 / (side * sl.texel_v), c = 2.0 / (far - near);
  Mat4 m(0.0);
  set_row(m, 0, a * sl.right, -a * sl.left - 1.0);
  set_row(m, 1, b * sl.up, 1.0 - b * sl.top);
  set_row(m, 2, c * sl.forward, -c * near - 1.0);
  set_row(m, 3, Vec3(0.0), 1.0);
  return m;
}

// One job per map the plans need (a directional light's one, a point light's needed faces), in
// light then face order; job_face[j] is the plan and face job j draws.
std::vector<ShadowMapJob> make_jobs(std::vector<LightPlan>& plans, const ShadowMaps& out,
                                    std::vector<std::pair<size_t, int>>& job_face) {
  std::vector<ShadowMapJob> jobs;
  for (size_t p = 0; p < plans.size(); ++p) {
    LightPlan& plan = plans[p];
    ShadowLight& sl = plan.light;
    for (int f = 0; f < (sl.directional ? 1 : 6); ++f) {
      if (!plan.needed[size_t(f)]) continue;
      ShadowMapJob job;
      job.directional = sl.directional;
      job.clip = sl.directional ? fit_directional(plan, out.side, out.pcf)
                                : cube_face_clip(cube_faces[size_t(f)], sl.position, plan.near_depth, plan.far_depth);
      job.forward = sl.forward, job.far_depth = sl.far_depth;
      job.casters = plan.casters;
      jobs.push_back(std::move(job));
      job_face.emplace_back(p, f);
    }
  }
  return jobs;
}

}  // namespace

ShadowMaps build_shadow_maps(const Scene& scene, const PolygonSoup& soup, const ViewTransform& view,
                             const RenderOptions& options, const CancelToken* cancel, unsigned threads) {
  threads = std::max(1u, threads);
  ShadowMaps out;
  out.pcf = options.shadow.pcf;
  out.bias = shadow_default_bias + options.shadow.bias;
  out.slope_bias = shadow_default_slope_bias + options.shadow.slope_bias;
  out.slot_of_light.assign(scene.lights.size(), -1);
  if (scene.lights.empty()) return out;
  const Receivers rec = options.shadow.fit == ShadowFit::scene ? collect_scene_receivers(soup, cancel)
                                                               : collect_receivers(soup, view, threads, cancel);
  std::vector<LightPlan> plans;
  size_t map_count = 0;
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    LightPlan plan;
    plan.light.light = uint32_t(i);
    const Light& light = scene.lights[i];
    // A light that adds nothing needs no map (its shadow could not be seen).
    if (!(light.intensity > 0.0f) || light.color == Color(0.0f)) continue;
    const bool casts = light.type == LightType::directional ? plan_directional(light, rec, soup, threads, cancel, plan)
                                                            : plan_point(light, rec, soup, threads, cancel, plan);
    if (!casts) continue;
    map_count += size_t(plan.map_count());
    plans.push_back(std::move(plan));
  }
  if (plans.empty()) return out;
  // Every map shrinks alike when the frame would exceed its texel budget.
  out.side = options.shadow.size;
  if (map_count * size_t(out.side) * size_t(out.side) > shadow_max_texels) {
    out.side = std::max(16, int(std::sqrt(double(shadow_max_texels) / double(map_count))));
  }
  std::vector<std::pair<size_t, int>> job_face;
  std::vector<ShadowMapJob> jobs = make_jobs(plans, out, job_face);
  draw_shadow_jobs(jobs, out.side, soup, threads, cancel);
  // Maps are numbered in job order, a job whose casters all fell outside its frustum getting none.
  for (size_t j = 0; j < jobs.size(); ++j) {
    if (!jobs[j].any_caster) continue;
    ShadowMap map;
    map.view.clip_from_world = jobs[j].clip;
    map.view.width = map.view.height = out.side;
    map.nearness = std::move(jobs[j].texels);
    map.blocks_per_row = jobs[j].blocks_per_row;
    map.block_min = std::move(jobs[j].block_min);
    map.block_max = std::move(jobs[j].block_max);
    out.maps.push_back(std::move(map));
    plans[job_face[j].first].light.map[size_t(job_face[j].second)] = int32_t(out.maps.size() - 1);
  }
  for (LightPlan& plan : plans) {
    ShadowLight& sl = plan.light;
    if (std::none_of(sl.map.begin(), sl.map.end(), [](int32_t m) { return m >= 0; })) continue;
    out.slot_of_light[sl.light] = int32_t(out.lights.size());
    out.lights.push_back(sl);
  }
  return out;
}

size_t ShadowMaps::bytes() const {
  size_t total = sizeof(ShadowMaps) + slot_of_light.capacity() * sizeof(int32_t) +
                 lights.capacity() * sizeof(ShadowLight) + maps.capacity() * sizeof(ShadowMap);
  for (const ShadowMap& m : maps) {
    total += m.nearness.bytes() + (m.block_min.capacity() + m.block_max.capacity()) * sizeof(float);
  }
  return total;
}

// --- lookups ---------------------------------------------------------------------------------------

Vec3 shadow_coords(const ShadowLight& light, Vec3 p) {
  if (!light.directional) return p - light.position;
  return {(glm::dot(p, light.right) - light.left) / light.texel_u, (light.top - glm::dot(p, light.up)) / light.texel_v,
          light.far_depth - glm::dot(p, light.forward)};
}

ShadowReceiver make_shadow_receiver(const ShadowMaps& maps, const ShadowLight& light, Vec3 n, double offset,
                                    bool closed) {
  if (closed) {  // no plane to extrapolate, the closed receivers' bias in place of the default one
    ShadowReceiver r;
    r.shift = shadow_closed_receiver_bias - shadow_default_bias;
    return r;
  }
  // Nearness on the plane as an affine function of texel coordinates (see shadow.hpp). A plane
  // edge-on to the light has an unbounded gradient; the divisor's floor keeps it finite and the
  // lookup clamps it to shadow_max_slope.
  auto safe = [](double d) { return std::abs(d) > 1e-12 ? d : std::copysign(1e-12, d); };
  ShadowReceiver r;
  if (light.directional) {
    const double c = safe(glm::dot(n, light.forward));
    r.gradient[0] = {glm::dot(n, light.right) / c * light.texel_u, -glm::dot(n, light.up) / c * light.texel_v};
    return r;
  }
  // 1/w = (dot(n, right) x_ndc + dot(n, up) y_ndc + dot(n, forward)) / (offset - dot(n, c)).
  const double k = safe(offset - glm::dot(n, light.position));
  const double per_texel = 2.0 / double(maps.side);
  for (size_t f = 0; f < 6; ++f) {
    r.gradient[f] = {glm::dot(n, cube_faces[f].right) / k * per_texel, -glm::dot(n, cube_faces[f].up) / k * per_texel};
  }
  return r;
}

float shadow_visibility_at(const ShadowMaps& maps, size_t light_index, Vec3 p_world, Vec3 normal, double offset) {
  if (light_index >= maps.slot_of_light.size() || maps.slot_of_light[light_index] < 0) return 1.0f;
  const ShadowLight& light = maps.lights[size_t(maps.slot_of_light[light_index])];
  return shadow_visibility(maps, light, make_shadow_receiver(maps, light, normal, offset),
                           shadow_coords(light, p_world));
}

}  // namespace rr
