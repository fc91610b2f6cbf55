// Sweet Home 3D furniture drawn with its OBJ model (ImportOptions::furniture_models). The model's
// vertices are placed in world metres here, as Sweet Home 3D places them: modelRotation (a row-major
// 3x3 matrix) first, then the model's bounding box centred and scaled onto the piece's width x height
// x depth, mirrored across its width axis when modelMirrored, turned by the piece's angle and set on
// its bottom centre. Normals follow by the inverse transpose. Faces are repaired as for any OBJ.
#include "render/import/import_obj.hpp"
#include "render/import/import_sh3d.hpp"

#include <cmath>

namespace rr::import_detail {

using nlohmann::json;

struct Sh3dModel {
  ObjData obj;
  std::map<std::string, Color> mtl_colors;
};

namespace {

std::string directory_of(const std::string& path) {
  size_t slash = path.rfind('/');
  return slash == std::string::npos ? "" : path.substr(0, slash + 1);
}

// The model by its name as written, else furniture/<file name> (the layout of the example homes).
std::shared_ptr<const Sh3dModel> load_model(const std::string& name, const ImportOptions& options,
                                            Sh3dModelCache& cache) {
  if (auto it = cache.by_name.find(name); it != cache.by_name.end()) return it->second;
  std::shared_ptr<Sh3dModel> model;
  const std::string base = name.substr(name.rfind('/') + 1);
  for (const std::string& path : {name, "furniture/" + base}) {
    std::optional<std::string> text = options.read_companion ? options.read_companion(path) : std::nullopt;
    if (!text) continue;
    try {
      model = std::make_shared<Sh3dModel>();
      model->obj = parse_obj(*text);
      for (const std::string& library : model->obj.libraries) {
        if (auto mtl = options.read_companion(directory_of(path) + library)) parse_mtl(*mtl, model->mtl_colors);
      }
    } catch (const InputError&) {
      ++cache.unreadable;  // a broken model should not lose the whole home: the piece stays a box
      model.reset();
    }
    break;
  }
  if (!model && cache.by_name.count(name) == 0) ++cache.missing;
  cache.by_name[name] = model;
  return model;
}

// The 3x3 row-major matrix of modelRotation, identity when absent or malformed.
glm::dmat3 model_rotation(const pugi::xml_node& node) {
  glm::dmat3 m(1.0);
  std::vector<std::string_view> fields = split_fields(node.attribute("modelRotation").as_string(""));
  if (fields.size() != 9) return m;
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) {
      auto v = parse_double(fields[size_t(row * 3 + col)]);
      if (!v) return glm::dmat3(1.0);
      m[col][row] = *v;  // glm is column-major
    }
  }
  return m;
}

}  // namespace

bool add_piece_model(const Sh3dElement& e, const PiecePlacement& place, const ImportOptions& options,
                     Sh3dModelCache& cache, json& solids) {
  const std::string name = e.node.attribute("model").as_string("");
  if (name.empty()) return false;
  std::shared_ptr<const Sh3dModel> model = load_model(name, options, cache);
  if (!model || model->obj.positions.empty()) return false;
  const glm::dmat3 rotation = model_rotation(e.node);
  Box3 model_box;
  std::vector<Vec3> positions(model->obj.positions.size());
  for (size_t i = 0; i < positions.size(); ++i) model_box.add(positions[i] = rotation * model->obj.positions[i]);
  const Vec3 extent = model_box.hi - model_box.lo, middle = 0.5 * (model_box.lo + model_box.hi);
  Vec3 scale{1.0};
  for (int k = 0; k < 3; ++k) scale[k] = extent[k] > 1e-9 ? place.size[k] / extent[k] : 1.0;
  const bool mirrored = e.node.attribute("modelMirrored").as_bool(false);
  const double c = std::cos(place.angle), s = std::sin(place.angle);
  // Local x (width) runs along (cos a, sin a) on the plan, local z (depth) along (-sin a, cos a).
  auto to_world = [&](Vec3 local, double y0, Vec2 origin) {
    if (mirrored) local.x = -local.x;
    return Vec3(origin.x + c * local.x - s * local.z, y0 + local.y, origin.y + s * local.x + c * local.z);
  };
  for (Vec3& p : positions) p = to_world((p - middle) * scale, place.base + 0.5 * place.size.y, place.centre);
  std::vector<Vec3> normals(model->obj.normals.size());
  for (size_t i = 0; i < normals.size(); ++i) {
    normals[i] = to_world(rotation * model->obj.normals[i] / scale, 0.0, Vec2(0.0));
  }
  std::map<std::string, Color> piece_materials;
  for (pugi::xml_node m : e.node.children("material")) {
    if (auto color = color_attribute(m, "color")) piece_materials[m.attribute("name").as_string("")] = *color;
  }
  const std::optional<Color> piece_color = color_attribute(e.node, "color");
  const std::string id = std::string(e.node.attribute("name").as_string("")) + " (" + e.pointer + ")";
  RepairCounts repairs;
  Box3 unused;
  for (const Group& g : model->obj.groups) {
    Color color{0.7f};
    if (auto it = model->mtl_colors.find(g.material); it != model->mtl_colors.end()) color = it->second;
    if (auto it = piece_materials.find(g.material); it != piece_materials.end()) color = it->second;
    if (piece_color) color = *piece_color;
    json mesh = group_mesh(g, model->obj, positions, normals, mirrored, color, repairs, unused);
    mesh["id"] = id + " " + g.material;
    if (!mesh["faces"].empty()) solids.push_back(std::move(mesh));
  }
  cache.polygons_repaired += repairs.triangulated + repairs.degenerate;
  return true;
}

}  // namespace rr::import_detail
