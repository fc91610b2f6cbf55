// Wavefront OBJ text -> a request with one mesh solid per (o/g name, usemtl material) group, in order
// of first appearance, coloured by the .mtl diffuse colour (Kd) and textured by its map_Kd image (a
// data: URI of the file's bytes) with the group's vt as the mesh's uvs. Object space is the file's (Y up,
// counter-clockwise fronts); the scale goes into each mesh's "scale". Faces are repaired so the
// validator accepts them: repeated corners dropped, faces that are not planar within 1e-7 of their
// group's size (the validator allows 1e-6) fan-triangulated, faces of zero area dropped; each repair
// is counted in a warning. Bad numbers and indices are errors naming the line. The camera looks
// from inside when the model has a floor and a ceiling (docs/import.md), else frames it from outside.
#include "render/import/import_obj.hpp"

#include "render/core/texture.hpp"
#include "render/import/import.hpp"
#include "render/scene_io/scene_json.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <unordered_map>

namespace rr {

using nlohmann::json;
namespace import_detail {

namespace {

// Parses one `f` token's index (1-based, or negative from the end) against `count` defined so far.
std::string plural(const std::string& noun, size_t count) {
  if (count == 1) return noun;
  return noun == "vertex" ? "vertices" : noun + "s";
}

uint32_t resolve_index(std::string_view field, size_t count, const char* what, size_t line) {
  std::optional<long long> raw = parse_long(field);
  if (!raw)
    throw_at_line(Kind::malformed, line, std::string(what) + " index '" + quote_input(field) + "' is not an integer");
  const long long signed_count = static_cast<long long>(count);
  long long index = *raw > 0 ? *raw - 1 : signed_count + *raw;
  if (*raw == 0 || index < 0 || index >= signed_count) {
    throw_at_line(Kind::invalid, line,
                  std::string(what) + " index " + std::to_string(*raw) + " is out of range (" + std::to_string(count) +
                      " " + plural(what, count) +
                      " defined before this line; OBJ indices start at 1, negative ones count back)");
  }
  return uint32_t(index);
}

Vec3 parse_vector(const std::vector<std::string_view>& fields, size_t line, const char* what) {
  if (fields.size() < 4) throw_at_line(Kind::malformed, line, std::string(what) + " needs 3 numbers");
  Vec3 v{0.0};
  for (int k = 0; k < 3; ++k) {
    std::optional<double> value = parse_double(fields[size_t(k) + 1]);
    if (!value) {
      throw_at_line(
          Kind::invalid, line,
          std::string(what) + " coordinate '" + quote_input(fields[size_t(k) + 1]) + "' is not a finite number");
    }
    // The mesh keeps file units; the request refuses coordinates beyond 1e7.
    if (std::abs(*value) > 1e7) throw_at_line(Kind::invalid, line, std::string(what) + " coordinate exceeds 1e7");
    v[k] = *value;
  }
  return v;
}

void parse_face(const std::vector<std::string_view>& fields, size_t line, ObjData& obj, Group& group) {
  if (fields.size() < 4) throw_at_line(Kind::invalid, line, "a face needs at least 3 vertices");
  Face face{uint32_t(obj.corners.size()), uint32_t(fields.size() - 1)};
  for (size_t k = 1; k < fields.size(); ++k) {
    std::string_view token = fields[k];
    size_t slash1 = token.find('/');
    Corner c;
    c.v = resolve_index(token.substr(0, slash1), obj.positions.size(), "vertex", line);
    if (slash1 != std::string_view::npos) {
      size_t slash2 = token.find('/', slash1 + 1);
      std::string_view vt = token.substr(slash1 + 1, slash2 == std::string_view::npos ? slash2 : slash2 - slash1 - 1);
      if (!vt.empty()) c.vt = resolve_index(vt, obj.texcoords.size(), "texture coordinate", line);
      if (slash2 != std::string_view::npos)
        c.vn = resolve_index(token.substr(slash2 + 1), obj.normals.size(), "normal", line);
    }
    obj.corners.push_back(c);
  }
  group.faces.push_back(face);
}

// "vt u [v [w]]": v is 0 when absent, w is ignored.
Vec2 parse_texcoord(const std::vector<std::string_view>& fields, size_t line) {
  if (fields.size() < 2) throw_at_line(Kind::malformed, line, "texture coordinate needs at least 1 number");
  Vec2 uv{0.0};
  for (size_t k = 1; k < std::min<size_t>(fields.size(), 3); ++k) {
    std::optional<double> value = parse_double(fields[k]);
    if (!value || std::abs(*value) > 1e7) {
      throw_at_line(Kind::invalid, line,
                    "texture coordinate '" + quote_input(fields[k]) + "' is not a finite number within 1e7");
    }
    uv[int(k) - 1] = *value;
  }
  return uv;
}

// Everything after the keyword, trimmed (names may contain spaces).
std::string rest_of_line(std::string_view line, std::string_view keyword) {
  std::string_view rest = line.substr(std::min(line.size(), line.find(keyword) + keyword.size()));
  while (!rest.empty() && (rest.front() == ' ' || rest.front() == '\t')) rest.remove_prefix(1);
  while (!rest.empty() && (rest.back() == ' ' || rest.back() == '\t')) rest.remove_suffix(1);
  return std::string(rest);
}

}  // namespace

ObjData parse_obj(std::string_view text) {
  ObjData obj;
  std::map<std::pair<std::string, std::string>, size_t> group_index;
  std::string name, material;
  size_t current = SIZE_MAX;  // the group faces go to; chosen lazily so empty groups vanish
  size_t face_count = 0;
  LineReader lines(text);
  while (auto line = lines.next()) {
    const size_t n = lines.line_number();
    if (line->empty() || line->front() == '#') continue;
    std::vector<std::string_view> fields = split_fields(*line);
    if (fields.empty()) continue;
    std::string_view key = fields[0];
    if (key == "v") {
      obj.positions.push_back(parse_vector(fields, n, "vertex"));
    } else if (key == "vn") {
      obj.normals.push_back(parse_vector(fields, n, "normal"));
    } else if (key == "vt") {
      obj.texcoords.push_back(parse_texcoord(fields, n));
    } else if (key == "f") {
      if (++face_count > max_faces) {
        throw_at_line(Kind::too_large, n, "more than " + std::to_string(max_faces) + " faces");
      }
      if (current == SIZE_MAX) {
        auto [it, inserted] = group_index.try_emplace({name, material}, obj.groups.size());
        if (inserted) obj.groups.push_back({name, material, {}});
        current = it->second;
      }
      parse_face(fields, n, obj, obj.groups[current]);
    } else if (key == "o" || key == "g") {
      name = rest_of_line(*line, key);
      current = SIZE_MAX;
    } else if (key == "usemtl") {
      material = rest_of_line(*line, key);
      current = SIZE_MAX;
    } else if (key == "mtllib") {
      for (size_t k = 1; k < fields.size(); ++k) obj.libraries.emplace_back(fields[k]);
    }
    // s, l, p, curves and anything else carry nothing we draw.
  }
  return obj;
}

namespace {

// How many fields after a texture map option (from fields[at]) are its arguments: -o, -s and -t take
// up to three numbers, -mm up to two, the other options of the format one word; an unknown option
// takes the numbers and on/off words that follow it. The last field is never taken: it is the file.
size_t option_arguments(std::string_view option, const std::vector<std::string_view>& fields, size_t at) {
  for (std::string_view one :
       {"-blendu", "-blendv", "-bm", "-boost", "-cc", "-clamp", "-imfchan", "-texres", "-type"}) {
    if (option == one) return at + 1 < fields.size() ? 1 : 0;
  }
  const size_t most = option == "-o" || option == "-s" || option == "-t" ? 3 : option == "-mm" ? 2 : SIZE_MAX;
  auto is_argument = [](std::string_view f) { return parse_double(f) || f == "on" || f == "off"; };
  size_t taken = 0;
  while (taken < most && at + taken + 1 < fields.size() && is_argument(fields[at + taken])) ++taken;
  return taken;
}

// The file a texture map line names, after its options (the rest of the line: names may hold spaces).
std::string map_path(std::string_view line, const std::vector<std::string_view>& fields, bool& options_changing_uvs) {
  size_t k = 1;
  while (k + 1 < fields.size() && fields[k].front() == '-') {
    const std::string_view option = fields[k];
    if (option == "-o" || option == "-s" || option == "-t") options_changing_uvs = true;
    k += 1 + option_arguments(option, fields, k + 1);
  }
  if (k >= fields.size()) return "";
  std::string_view rest = line.substr(size_t(fields[k].data() - line.data()));
  while (!rest.empty() && (rest.back() == ' ' || rest.back() == '\t' || rest.back() == '\r')) rest.remove_suffix(1);
  return std::string(rest);
}

}  // namespace

void parse_mtl(std::string_view text, std::map<std::string, MtlMaterial>& materials, const std::string& library_dir) {
  std::string current;
  LineReader lines(text);
  // The first three numbers after the keyword, each clamped to 0..1; nullopt when one is missing.
  auto rgb = [](const std::vector<std::string_view>& fields) -> std::optional<Color> {
    if (fields.size() < 4) return std::nullopt;
    Color c{0.7f};
    for (int k = 0; k < 3; ++k) {
      if (auto v = parse_double(fields[size_t(k) + 1])) c[k] = float(std::clamp(*v, 0.0, 1.0));
    }
    return c;
  };
  while (auto line = lines.next()) {
    std::vector<std::string_view> fields = split_fields(*line);
    if (fields.empty() || fields[0].front() == '#') continue;
    if (fields[0] == "newmtl") {
      current = rest_of_line(*line, "newmtl");
      materials.try_emplace(current).first->second.library_dir = library_dir;
      continue;
    }
    if (current.empty()) continue;
    MtlMaterial& m = materials[current];
    if (fields[0] == "Kd") {
      if (auto c = rgb(fields)) m.diffuse = *c, m.has_diffuse = true;
    } else if (fields[0] == "map_Kd") {
      m.diffuse_map = map_path(*line, fields, m.map_options);
    } else if (fields[0] == "map_d") {
      m.alpha_map = true;
    } else if (fields[0] == "Ks") {
      if (auto c = rgb(fields)) {
        const float strength = std::max({c->r, c->g, c->b});
        m.params.specular = strength;
        m.params.specular_color = strength > 0.0f ? *c / strength : Color{1.0f};
        m.specular = true;
      }
    } else if (fields[0] == "Ns" && fields.size() >= 2) {
      if (auto v = parse_double(fields[1])) {
        m.params.shininess = float(std::clamp(*v, 1.0, 128.0));
        m.specular = true;
      }
    }
  }
}

nlohmann::json material_json(const MtlMaterial& m) {
  if (!m.specular) return nullptr;
  auto round3 = [](double v) { return std::round(v * 1000.0) / 1000.0; };
  return {{"specular", round3(m.params.specular)},
          {"specular_color", json_color(m.params.specular_color)},
          {"shininess", round3(m.params.shininess)}};
}

const std::map<std::string, MtlMaterial>& default_materials() {
  static const std::map<std::string, MtlMaterial> library = [] {
    std::map<std::string, MtlMaterial> out;
    parse_mtl(default_materials_mtl(), out);
    return out;
  }();
  return library;
}

namespace {

// Twice the area, and the largest distance of a corner from the plane through the centroid, as
// scene_checks computes them for validation.
std::pair<double, double> area_and_flatness(const std::vector<Vec3>& p) {
  Vec3 centroid{0.0};
  for (const Vec3& q : p) centroid += q;
  centroid /= double(p.size());
  Vec3 normal{0.0};
  for (size_t k = 0; k < p.size(); ++k) normal += glm::cross(p[k] - centroid, p[(k + 1) % p.size()] - centroid);
  double twice_area = glm::length(normal);
  double off_plane = 0.0;
  if (twice_area > 0.0) {
    for (const Vec3& q : p) off_plane = std::max(off_plane, std::abs(glm::dot(normal / twice_area, q - centroid)));
  }
  return {twice_area, off_plane};
}

}  // namespace

json group_mesh(const Group& g, const ObjData& obj, const std::vector<Vec3>& positions,
                const std::vector<Vec3>& normals_in, bool mirrored, Color color, RepairCounts& repairs, Box3& box,
                bool want_uvs) {
  bool with_normals = !obj.normals.empty();
  bool with_uvs = want_uvs;
  Box3 group_box;
  for (const Face& f : g.faces) {
    for (uint32_t k = 0; k < f.corner_count; ++k) {
      const Corner& c = obj.corners[f.first_corner + k];
      group_box.add(positions[c.v]);
      if (c.vn == no_normal || !(glm::length(obj.normals[c.vn]) > 0.0)) with_normals = false;
      if (c.vt == no_texcoord) with_uvs = false;
    }
  }
  if (!obj.normals.empty() && !with_normals) ++repairs.dropped_normals;
  if (want_uvs && !with_uvs) ++repairs.dropped_uvs;
  box.add(group_box.lo), box.add(group_box.hi);
  const double size = glm::length(group_box.hi - group_box.lo);
  // 4x the validator's zero-area threshold, so rounding in either computation cannot disagree.
  const double min_twice_area = 8.0 * (1e-8 * size) * (1e-8 * size);

  // Without uvs the key is (position, normal), as before texture coordinates were read; with them
  // each vt of a (position, normal) gets its own vertex, numbered in the same order of first use.
  std::unordered_map<uint64_t, uint32_t> local;
  std::map<std::pair<uint64_t, uint32_t>, uint32_t> local_uv;
  json vertices = json::array(), normals = json::array(), faces = json::array(), uvs = json::array();
  auto local_index = [&](const Corner& c) {
    uint64_t key = (uint64_t(c.v) << 32) | (with_normals ? c.vn : 0u);
    uint32_t index = 0;
    bool inserted = false;
    if (with_uvs) {
      auto [it, added] = local_uv.try_emplace({key, c.vt}, uint32_t(local_uv.size()));
      index = it->second, inserted = added;
    } else {
      auto [it, added] = local.try_emplace(key, uint32_t(local.size()));
      index = it->second, inserted = added;
    }
    if (inserted) {
      if (with_uvs) uvs.push_back({obj.texcoords[c.vt].x, obj.texcoords[c.vt].y});
      const Vec3& p = positions[c.v];
      vertices.push_back({p.x, p.y, p.z});
      if (with_normals) {
        const Vec3 n = glm::normalize(normals_in[c.vn]);
        normals.push_back(json_vec3(n));
      }
    }
    return index;
  };
  std::vector<Corner> ring;
  std::vector<Vec3> points;
  auto emit = [&](const std::vector<Corner>& corners) {
    points.clear();
    for (const Corner& c : corners) points.push_back(positions[c.v]);
    if (!(area_and_flatness(points).first > min_twice_area)) return ++repairs.degenerate, void();
    json& face = faces.emplace_back(json::array());
    for (const Corner& c : corners) face.push_back(local_index(c));
  };
  for (const Face& f : g.faces) {
    ring.clear();
    for (uint32_t k = 0; k < f.corner_count; ++k) {
      const Corner& c = obj.corners[f.first_corner + k];
      if (ring.empty() || ring.back().v != c.v) ring.push_back(c);
    }
    while (ring.size() > 1 && ring.front().v == ring.back().v) ring.pop_back();
    if (mirrored) std::reverse(ring.begin(), ring.end());  // a mirror turns fronts into backs
    if (ring.size() < 3) {
      ++repairs.degenerate;
      continue;
    }
    points.clear();
    for (const Corner& c : ring) points.push_back(positions[c.v]);
    std::set<uint32_t> distinct;
    for (const Corner& c : ring) distinct.insert(c.v);
    bool flat = ring.size() == 3 || area_and_flatness(points).second <= 1e-7 * size;
    if (flat && distinct.size() == ring.size()) {
      emit(ring);
      continue;
    }
    ++repairs.triangulated;  // a fan from the first corner; a repeated corner leaves zero-area pieces
    for (size_t k = 1; k + 1 < ring.size(); ++k) {
      if (ring[0].v == ring[k].v || ring[k].v == ring[k + 1].v || ring[0].v == ring[k + 1].v) {
        ++repairs.degenerate;
        continue;
      }
      emit({ring[0], ring[k], ring[k + 1]});
    }
  }
  json mesh = {{"type", "mesh"}, {"vertices", std::move(vertices)}, {"faces", std::move(faces)}};
  std::string id = g.name.empty() ? g.material : (g.material.empty() ? g.name : g.name + " / " + g.material);
  if (!id.empty()) mesh["id"] = id;
  mesh["color"] = json_color(color);
  if (with_normals) mesh["normals"] = std::move(normals);
  if (with_uvs) mesh["uvs"] = std::move(uvs);
  return mesh;
}

std::optional<std::string> image_data_uri(std::string_view bytes) {
  const char* media_type = nullptr;
  if (bytes.starts_with("\x89PNG\r\n\x1a\n")) media_type = "image/png";
  if (bytes.starts_with("\xff\xd8\xff")) media_type = "image/jpeg";
  if (!media_type) return std::nullopt;
  static constexpr char alphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out = std::string("data:") + media_type + ";base64,";
  out.reserve(out.size() + (bytes.size() + 2) / 3 * 4);
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const size_t n = std::min<size_t>(3, bytes.size() - i);
    uint32_t chunk = 0;
    for (size_t k = 0; k < 3; ++k) chunk = (chunk << 8) | (k < n ? uint8_t(bytes[i + k]) : 0u);
    for (size_t k = 0; k < 4; ++k) out += k <= n ? alphabet[(chunk >> (18 - 6 * k)) & 63u] : '=';
  }
  return out;
}

std::optional<std::string> usable_image_data_uri(std::string_view bytes, std::string* problem) {
  if (bytes.size() > texture_image_bytes_cap) {
    *problem = "has " + std::to_string(bytes.size()) + " bytes, more than the " +
               std::to_string(texture_image_bytes_cap) + " a request takes per image";
    return std::nullopt;
  }
  std::optional<std::string> uri = image_data_uri(bytes);
  if (!uri) {
    *problem = "is neither a PNG nor a JPEG";
    return std::nullopt;
  }
  TextureError error;
  if (!read_texture_header({reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()}, TextureLimits{}, nullptr,
                           nullptr, &error)) {
    *problem = "is refused: " + error.message;
    return std::nullopt;
  }
  return uri;
}

void add_repair_warnings(const RepairCounts& repairs, std::vector<std::string>& warnings) {
  if (repairs.triangulated) {
    warnings.push_back(std::to_string(repairs.triangulated) + " non-planar faces were split into triangles");
  }
  if (repairs.degenerate) warnings.push_back(std::to_string(repairs.degenerate) + " faces of zero area were dropped");
  if (repairs.dropped_normals) {
    warnings.push_back(std::to_string(repairs.dropped_normals) +
                       " groups had faces without (or with zero) normals: their normals were dropped");
  }
  if (repairs.dropped_uvs) {
    warnings.push_back(std::to_string(repairs.dropped_uvs) +
                       " textured groups had faces without texture coordinates (vt): drawn untextured");
  }
}

}  // namespace import_detail

using namespace import_detail;

namespace {

std::string directory_of(const std::string& path) {
  const size_t slash = path.rfind('/');
  return slash == std::string::npos ? "" : path.substr(0, slash + 1);
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// The data: URI of the image file at `path` (as read_companion takes it), or nullopt with a warning
// when it is missing or a request could not use it (usable_image_data_uri).
std::optional<std::string> load_texture(const std::string& path, const ImportOptions& options,
                                        std::vector<std::string>& warnings) {
  std::optional<std::string> bytes = options.read_companion ? options.read_companion(path) : std::nullopt;
  const std::string what = "texture '" + path + "' ";
  if (!bytes) {
    warnings.push_back(what + "is not available: its materials are drawn untextured");
    return std::nullopt;
  }
  std::string problem;
  std::optional<std::string> uri = usable_image_data_uri(*bytes, &problem);
  if (!uri) warnings.push_back(what + problem + ": its materials are drawn untextured");
  return uri;
}

// Material name -> the data: URI of its map_Kd, for the materials `groups` use; each file read once.
// Warns once about the alpha maps (map_d) and texture options that are not applied.
std::map<std::string, std::string> material_textures(const std::vector<Group>& groups,
                                                     const std::map<std::string, MtlMaterial>& materials,
                                                     const ImportOptions& options, std::vector<std::string>& warnings) {
  std::set<std::string> used;
  for (const Group& g : groups) used.insert(g.material);
  std::map<std::string, std::optional<std::string>> by_path;
  std::map<std::string, std::string> out;
  std::vector<std::string> alpha, options_skipped;
  for (const std::string& name : used) {
    auto m = materials.find(name);
    if (m == materials.end()) continue;
    if (m->second.alpha_map) alpha.push_back(name);
    if (m->second.diffuse_map.empty()) continue;
    const std::string path = m->second.library_dir + m->second.diffuse_map;
    auto [file, first] = by_path.try_emplace(path);
    if (first) file->second = load_texture(path, options, warnings);
    if (!file->second) continue;
    out.emplace(name, *file->second);
    if (m->second.map_options) options_skipped.push_back(name);
  }
  if (!alpha.empty()) {
    warnings.push_back("alpha cut-outs (map_d) are not supported, these materials are drawn opaque: " + joined(alpha));
  }
  if (!options_skipped.empty()) {
    warnings.push_back("texture options -o, -s and -t are not applied (the image is used as it is): " +
                       joined(options_skipped));
  }
  return out;
}

constexpr double eye_height_m = 1.6;
constexpr double level_step_m = 0.01;       // horizontal faces within 1 cm make one level
constexpr double large_level_share = 0.25;  // of the box's footprint: a floor, not a table top
constexpr double low_room_eye_share = 0.6;  // of floor-to-ceiling, for rooms lower than 1.6 / 0.6 m

// Whether the plan point (x, z) lies inside the face's plan projection (crossing count; the edge
// case of a point on an edge can go either way, which a floor's neighbouring faces absorb).
bool covers_plan_point(const ObjData& obj, const Face& f, double x, double z) {
  bool inside = false;
  for (uint32_t i = 0, j = f.corner_count - 1; i < f.corner_count; j = i++) {
    const Vec3 a = obj.positions[obj.corners[f.first_corner + i].v];
    const Vec3 b = obj.positions[obj.corners[f.first_corner + j].v];
    if ((a.z > z) != (b.z > z) && x < a.x + (z - a.z) * (b.x - a.x) / (b.z - a.z)) inside = !inside;
  }
  return inside;
}

// The first view of an interior, in metres. A large level is one of horizontal faces (within 1 cm)
// that together cover a quarter of the box's footprint, one of them over the box's plan centre; the
// lowest is the floor, the highest the ceiling. The eye is 1.6 m above the floor (0.6 of the room's
// height in a room lower than that) at the plan centre, looking along the box's longer horizontal
// side (+x, or +z when deeper), near plane 5 cm. Nothing without a floor and a ceiling above it: a
// model, not a room, which the caller frames from outside. `box` is in file units, as the positions.
std::optional<json> camera_inside(const ObjData& obj, const Box3& box, double scale) {
  const double cx = 0.5 * (box.lo.x + box.hi.x), cz = 0.5 * (box.lo.z + box.hi.z);
  const double footprint = (box.hi.x - box.lo.x) * (box.hi.z - box.lo.z) * scale * scale;
  struct Level {
    double area_m2 = 0.0;
    bool under_centre = false;
  };
  std::map<int64_t, Level> levels;  // by height in centimetres, lowest first
  for (const Group& g : obj.groups) {
    for (const Face& f : g.faces) {
      if (f.corner_count < 3) continue;
      Vec3 normal{0.0};  // Newell: twice the area vector
      double y = 0.0;
      for (uint32_t i = 0; i < f.corner_count; ++i) {
        const Vec3 a = obj.positions[obj.corners[f.first_corner + i].v];
        const Vec3 b = obj.positions[obj.corners[f.first_corner + (i + 1) % f.corner_count].v];
        normal += glm::cross(a, b);
        y += a.y;
      }
      const double twice_area = glm::length(normal);
      if (twice_area <= 0.0 || std::abs(normal.y) < 0.999 * twice_area) continue;
      Level& level = levels[std::llround(y / f.corner_count * scale / level_step_m)];
      level.area_m2 += 0.5 * twice_area * scale * scale;
      if (!level.under_centre) level.under_centre = covers_plan_point(obj, f, cx, cz);
    }
  }
  auto is_large = [&](const Level& level) {
    return level.under_centre && level.area_m2 >= large_level_share * footprint;
  };
  auto floor = std::find_if(levels.begin(), levels.end(), [&](const auto& l) { return is_large(l.second); });
  auto ceiling = std::find_if(levels.rbegin(), levels.rend(), [&](const auto& l) { return is_large(l.second); });
  if (floor == levels.end() || ceiling->first <= floor->first) return std::nullopt;
  const double floor_y = double(floor->first) * level_step_m;
  const double eye_y =
      floor_y + std::min(eye_height_m, low_room_eye_share * double(ceiling->first - floor->first) * level_step_m);
  const Vec3 eye{cx * scale, eye_y, cz * scale};
  const bool along_x = box.hi.x - box.lo.x >= box.hi.z - box.lo.z;
  const Vec3 target = along_x ? Vec3{box.hi.x * scale, eye_y, eye.z} : Vec3{eye.x, eye_y, box.hi.z * scale};
  const double diagonal = glm::length(box.hi - box.lo) * scale;
  return json{{"position", json_vec3(eye)},
              {"target", json_vec3(target)},
              {"fov_y", 60.0},
              {"near", 0.05},
              {"far", round_m(std::max(2.0 * diagonal, 1.0))}};
}

}  // namespace

ImportResult import_obj(std::string_view text, const ImportOptions& options) {
  const double scale = resolve_scale(options, ImportFormat::obj);
  ObjData obj = parse_obj(text);
  ImportResult result;
  std::map<std::string, MtlMaterial> colors;
  for (const std::string& library : obj.libraries) {
    std::optional<std::string> mtl = options.read_companion ? options.read_companion(library) : std::nullopt;
    if (mtl) {
      parse_mtl(*mtl, colors, directory_of(library));
    } else {
      result.warnings.push_back("material library '" + library + "' is not available: its groups are grey");
    }
  }
  std::set<std::string> unknown;
  for (const Group& g : obj.groups) {
    if (!g.material.empty() && !colors.contains(g.material)) unknown.insert(g.material);
  }
  if (!unknown.empty()) {
    std::string names;
    for (const std::string& n : unknown) names += (names.empty() ? "" : ", ") + n;
    result.warnings.push_back("materials without a Kd colour, drawn grey: " + names);
  }
  const std::map<std::string, std::string> textures = material_textures(obj.groups, colors, options, result.warnings);
  RepairCounts repairs;
  Box3 box;  // in file units; the meshes keep them and carry the scale
  json solids = json::array();
  for (const Group& g : obj.groups) {
    auto material = colors.find(g.material);
    auto texture = textures.find(g.material);
    const bool textured = texture != textures.end();
    Color color{0.7f};
    if (material != colors.end()) color = material->second.diffuse;
    // Kd multiplies map_Kd; a textured material without Kd shows its image as it is.
    if (textured && (material == colors.end() || !material->second.has_diffuse)) color = Color{1.0f};
    json mesh = group_mesh(g, obj, obj.positions, obj.normals, false, color, repairs, box, textured);
    if (textured && mesh.contains("uvs")) mesh["texture"] = {{"image", texture->second}};
    if (scale != 1.0) mesh["scale"] = scale;
    if (!mesh["faces"].empty()) solids.push_back(std::move(mesh));
  }
  if (solids.empty()) throw InputError(Kind::invalid, "", "the OBJ file has no faces to draw");
  add_repair_warnings(repairs, result.warnings);
  std::optional<json> inside = camera_inside(obj, box, scale);
  box.lo *= scale, box.hi *= scale;
  const double aspect = double(options.width) / double(options.height);
  result.request = {{"scene",
                     {{"background", "#20242a"},
                      {"ambient", {{"intensity", 0.35}}},
                      {"solids", std::move(solids)},
                      {"lights", json::array({default_sun_light()})}}},
                    {"camera", inside ? std::move(*inside) : camera_showing_box(box, aspect)},
                    {"options", request_options(options)}};
  return result;
}

}  // namespace rr
