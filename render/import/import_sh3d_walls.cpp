// Sweet Home 3D walls -> scene walls. A straight wall is one wall; an arc wall (arcExtent) becomes
// segments of at most 10 degrees whose chords follow the arc; a sloped top (heightAtEnd) becomes a
// wall as high as its lower end plus a closed wedge mesh above it. Every door or window is cut into
// each wall it intersects (as Sweet Home 3D cuts it), as the part of its width that lies along that
// wall; a piece reaching past a wall's end is clamped, one wider than the single wall it sits in is
// an error. Metres; plan (x, z) = (x_cm, y_cm) / 100.
#include "render/import/import_sh3d.hpp"

#include <algorithm>
#include <cmath>

namespace rr::import_detail {

using nlohmann::json;

namespace {

constexpr double max_arc_step_rad = pi / 18.0;  // 10 degrees: chords within 0.4% of the arc
constexpr double min_cut_m = 0.01;              // overlaps below 1 cm are touching, not cutting
// A door or window cuts a wall whose direction is within this angle of its own width axis.
const double parallel_cos = std::cos(radians(20.0));

// One straight piece of a Sweet Home 3D wall.
struct Piece {
  const Sh3dElement* element = nullptr;
  size_t source = 0;  // index of the <wall> element
  std::string id, level;
  const Sh3dLevel* scene_level = nullptr;
  Vec2 start, end;
  double thickness = 0.1, base = 0.0, height_start = 2.5, height_end = 2.5;
  Color color{0.902f, 0.882f, 0.839f};
  std::optional<json> left_texture, right_texture;
  json openings = json::array();
  std::vector<std::pair<double, double>> spans;  // taken [offset, offset + width]
};

struct WallSource {
  std::string id;
  double length = 0.0;  // along the arc for arc walls
};

Vec2 round_plan(Vec2 p) { return {round_m(p.x), round_m(p.y)}; }

Vec2 rotate(Vec2 v, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * v.x - s * v.y, s * v.x + c * v.y};
}

// Points along the arc from a to b that bulges to the left of a->b (seen in the plan, y down) when
// `extent` is positive, as Sweet Home 3D draws it. Returns the end points of the chords.
std::vector<Vec2> arc_points(Vec2 a, Vec2 b, double extent) {
  const Vec2 chord = b - a;
  const double length = glm::length(chord);
  const Vec2 normal = Vec2(chord.y, -chord.x) / length;  // the side a positive extent bulges to
  const Vec2 centre = 0.5 * (a + b) - normal * (0.5 * length / std::tan(0.5 * extent));
  // The sweep that carries a onto b: try both senses, keep the one that lands on b.
  const double sweep =
      glm::length(centre + rotate(a - centre, extent) - b) < glm::length(centre + rotate(a - centre, -extent) - b)
          ? extent
          : -extent;
  // 1e-6 absorbs the rounding of a file's "1.0471976" for 60 degrees.
  const int steps = std::max(2, int(std::ceil(std::abs(extent) / max_arc_step_rad - 1e-6)));
  std::vector<Vec2> points;
  for (int k = 0; k <= steps; ++k) points.push_back(centre + rotate(a - centre, sweep * k / steps));
  points.front() = a, points.back() = b;  // exact ends, so joined walls still share them
  return points;
}

// The pieces of one <wall>, or none (with a warning) when it is hidden or has no length.
void read_wall(const Sh3dElement& e, size_t source, const Sh3dHome& h, const ImportOptions& options,
               Sh3dTextures& textures, std::vector<Piece>& pieces, std::vector<WallSource>& sources,
               std::vector<std::string>& warnings) {
  const Sh3dLevel& level = element_level(e, h);
  std::string id = e.node.attribute("id").as_string("");
  sources.push_back({id.empty() ? e.pointer : id, 0.0});
  // Rounded once here, so the lengths computed below are the ones the request validator computes.
  const Vec2 a = round_plan(Vec2(required_number(e, "xStart"), required_number(e, "yStart")) / 100.0);
  const Vec2 b = round_plan(Vec2(required_number(e, "xEnd"), required_number(e, "yEnd")) / 100.0);
  if (glm::length(b - a) <= 1e-6) {
    warnings.push_back("line " + std::to_string(e.line) + ": wall '" + sources.back().id + "' has no length; skipped");
    return;
  }
  Piece p;
  p.element = &e;
  p.source = source;
  p.level = e.node.attribute("level").as_string("");
  p.thickness = round_m(std::max(number_attribute(e, "thickness", 10.0) / 100.0, 0.001));
  p.base = round_m(level.elevation_m);
  p.scene_level = &level;
  const double h0 = round_m(std::max(number_attribute(e, "height", h.wall_height_m * 100.0) / 100.0, 0.001));
  const double h1 = round_m(std::max(number_attribute(e, "heightAtEnd", h0 * 100.0) / 100.0, 0.001));
  if (auto c = color_attribute(e.node, "leftSideColor")) p.color = *c;
  else if (auto c2 = color_attribute(e.node, "rightSideColor")) p.color = *c2;
  // Sweet Home 3D's left side is ours: walking from start to end, the side toward -y on its plan
  // (y down), which is -z, the normal (dz, -dx).
  p.left_texture = sh3d_texture(e, "leftSideTexture", options, textures);
  p.right_texture = sh3d_texture(e, "rightSideTexture", options, textures);
  const double extent = number_attribute(e, "arcExtent", 0.0);
  std::vector<Vec2> points = std::abs(extent) > 1e-3 ? arc_points(a, b, extent) : std::vector<Vec2>{a, b};
  const size_t n = points.size() - 1;
  for (size_t k = 0; k < n; ++k) {
    p.id = sources.back().id + (n > 1 ? " #" + std::to_string(k + 1) : "");
    p.start = round_plan(points[k]), p.end = round_plan(points[k + 1]);
    p.height_start = round_m(h0 + (h1 - h0) * double(k) / double(n));
    p.height_end = round_m(h0 + (h1 - h0) * double(k + 1) / double(n));
    sources.back().length += glm::length(p.end - p.start);
    pieces.push_back(p);
  }
}

// A closed triangular prism over [start, end] from the wall's top (its lower end) to the slope.
json wedge_mesh(const Piece& p) {
  const double low = p.base + std::min(p.height_start, p.height_end);
  const Vec2 u = glm::normalize(p.end - p.start), side = Vec2(-u.y, u.x) * (0.5 * p.thickness);
  const bool high_at_start = p.height_start > p.height_end;
  const Vec2 apex_plan = high_at_start ? p.start : p.end;
  const double apex_y = p.base + std::max(p.height_start, p.height_end);
  const Vec3 profile[3] = {{p.start.x, low, p.start.y}, {p.end.x, low, p.end.y}, {apex_plan.x, apex_y, apex_plan.y}};
  std::vector<Vec3> v;
  for (double s : {-1.0, 1.0}) {
    for (const Vec3& q : profile) v.push_back(q + Vec3(side.x * s, 0.0, side.y * s));
  }
  Vec3 centroid{0.0};
  for (const Vec3& q : v) centroid += q / 6.0;
  const std::vector<std::vector<uint32_t>> faces = {{0, 1, 2}, {3, 4, 5}, {0, 1, 4, 3}, {1, 2, 5, 4}, {2, 0, 3, 5}};
  json vertices = json::array(), out_faces = json::array();
  for (const Vec3& q : v) vertices.push_back(json_vec3(q));
  for (std::vector<uint32_t> f : faces) {
    Vec3 normal{0.0}, middle{0.0};  // wind each face counter-clockwise seen from outside
    for (size_t k = 0; k < f.size(); ++k) {
      normal += glm::cross(v[f[k]], v[f[(k + 1) % f.size()]]);
      middle += v[f[k]] / double(f.size());
    }
    if (glm::dot(normal, middle - centroid) < 0.0) std::reverse(f.begin(), f.end());
    out_faces.push_back(f);
  }
  return {{"type", "mesh"},       {"id", p.id + " (sloped top)"}, {"color", json_color(p.color)},
          {"vertices", vertices}, {"faces", out_faces},           {"closed", true}};
}

std::string describe(const Sh3dOpening& o) {
  return "line " + std::to_string(o.element->line) + ": " + (o.door ? "door" : "window") + " '" + o.name + "'";
}

// The opening's part along one piece: [t0, t1] metres from the piece's start, or an empty span.
std::pair<double, double> cut_span(const Sh3dOpening& o, const Piece& p) {
  const Vec2 d = p.end - p.start;
  const double length = glm::length(d);
  const Vec2 u = d / length;
  if (o.level != p.level || std::abs(glm::dot(u, o.axis)) < parallel_cos) return {0.0, 0.0};
  const Vec2 rel = o.centre - p.start;
  // The piece's footprint and the wall's must overlap across the wall, as boxes.
  if (std::abs(u.x * rel.y - u.y * rel.x) > 0.5 * (p.thickness + o.depth) + 0.01) return {0.0, 0.0};
  const double t = glm::dot(u, rel);
  return {std::max(t - 0.5 * o.width, 0.0), std::min(t + 0.5 * o.width, length)};
}

json opening_json(const Sh3dOpening& o, double offset, double width, double sill, double height) {
  // Not rounded: offset + width must stay within the wall's length to 1e-9 m.
  json j = {{"id", o.name + " (" + o.element->pointer + ")"}, {"offset", offset}, {"width", width}, {"height", height}};
  if (o.door && sill <= 0.01) {
    j.update({{"type", "door"}, {"leaf", o.leaf}});
  } else if (o.door) {  // a door above the floor: an opaque panel in a window opening
    j.update({{"type", "window"}, {"sill", sill}, {"color", "#8b5a2b"}, {"opacity", 1}});
  } else {
    j.update({{"type", "window"}, {"sill", sill}});
  }
  return j;
}

// Cuts one door or window into every piece it intersects.
void cut_opening(const Sh3dOpening& o, std::vector<Piece>& pieces, const std::vector<WallSource>& sources,
                 std::vector<std::string>& warnings) {
  std::vector<std::pair<size_t, std::pair<double, double>>> hits;
  std::vector<size_t> hit_sources;
  double covered = 0.0;
  for (size_t i = 0; i < pieces.size(); ++i) {
    auto span = cut_span(o, pieces[i]);
    if (span.second - span.first < min_cut_m) continue;
    hits.push_back({i, span});
    covered += span.second - span.first;
    if (std::find(hit_sources.begin(), hit_sources.end(), pieces[i].source) == hit_sources.end()) {
      hit_sources.push_back(pieces[i].source);
    }
  }
  if (hits.empty()) return warnings.push_back(describe(o) + " is in no wall; skipped"), void();
  if (hit_sources.size() == 1 && o.width > sources[hit_sources[0]].length + 0.005) {
    throw InputError(Kind::invalid, o.element->pointer,
                     describe(o) + " is " + std::to_string(o.width) + " m wide, wider than the wall '" +
                         sources[hit_sources[0]].id + "' it sits in (" +
                         std::to_string(sources[hit_sources[0]].length) + " m long)");
  }
  if (covered < o.width - 0.02) warnings.push_back(describe(o) + " reaches past the end of its wall; clamped");
  for (auto& [i, span] : hits) {
    Piece& p = pieces[i];
    const double wall_height = std::min(p.height_start, p.height_end);
    double sill = std::max(o.elevation, 0.0), height = o.height - (sill - o.elevation);
    if (sill > wall_height - min_cut_m || height < min_cut_m) {
      warnings.push_back(describe(o) + " lies above the top of wall '" + p.id + "'; skipped there");
      continue;
    }
    if (sill + height > wall_height) {
      height = wall_height - sill;
      warnings.push_back(describe(o) + " reaches above wall '" + p.id + "'; its top was lowered to the wall's");
    }
    // Two pieces side by side often overlap by a few millimetres (a double door made of two doors):
    // the later one gives way. One mostly covered by another is dropped.
    const double wanted = span.second - span.first;
    for (auto [a, b] : p.spans) {
      if (span.first >= a && span.first < b) span.first = b;
      if (span.second > a && span.second <= b) span.second = a;
      if (span.first < a && span.second > b) span.second = a;  // keep the part before it
    }
    if (span.second - span.first < 0.5 * wanted) {
      warnings.push_back(describe(o) + " overlaps another opening of wall '" + p.id + "'; skipped there");
      continue;
    }
    if (span.second - span.first < wanted - 0.02) {
      warnings.push_back(describe(o) + " overlaps another opening of wall '" + p.id + "'; narrowed to the free part");
    }
    p.spans.push_back(span);
    p.openings.push_back(opening_json(o, span.first, span.second - span.first, sill, height));
  }
}

}  // namespace

void add_sh3d_walls(const std::vector<Sh3dElement>& wall_elements, const std::vector<Sh3dOpening>& openings,
                    const Sh3dHome& h, const ImportOptions& options, Sh3dTextures& textures, json& walls, json& solids,
                    std::vector<std::string>& warnings, Box3& box) {
  std::vector<Piece> pieces;
  std::vector<WallSource> sources;
  for (size_t i = 0; i < wall_elements.size(); ++i)
    read_wall(wall_elements[i], i, h, options, textures, pieces, sources, warnings);
  for (const Sh3dOpening& o : openings) cut_opening(o, pieces, sources, warnings);
  for (Piece& p : pieces) {
    // The format wants openings ordered by nothing, but sorted reads better and diffs stably.
    std::sort(p.openings.begin(), p.openings.end(),
              [](const json& a, const json& b) { return a["offset"].get<double>() < b["offset"].get<double>(); });
    const double height = std::min(p.height_start, p.height_end);
    walls.push_back({{"id", p.id},
                     {"start", json_vec2(p.start)},
                     {"end", json_vec2(p.end)},
                     {"thickness", round_m(p.thickness)},
                     {"height", round_m(height)},
                     {"base", round_m(p.base)},
                     {"color", json_color(p.color)},
                     {"openings", std::move(p.openings)}});
    if (p.left_texture) walls.back()["left_texture"] = *p.left_texture;
    if (p.right_texture) walls.back()["right_texture"] = *p.right_texture;
    tag_level(walls.back(), *p.scene_level);
    if (std::abs(p.height_start - p.height_end) > 1e-3) {
      solids.push_back(wedge_mesh(p));
      tag_level(solids.back(), *p.scene_level);
    }
    for (const Vec2& q : {p.start, p.end}) {
      box.add({q.x, p.base, q.y});
      box.add({q.x, p.base + std::max(p.height_start, p.height_end), q.y});
    }
  }
}

}  // namespace rr::import_detail
