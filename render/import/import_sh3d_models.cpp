// Sweet Home 3D furniture drawn with its OBJ model (ImportOptions::furniture_models), as Sweet Home 3D
// places it: modelRotation (a row-major 3x3 matrix) first, then the model's bounding box centred and
// scaled onto the piece's width x height x depth, mirrored across its width axis when modelMirrored,
// turned by the piece's angle and set on its bottom centre. Each distinct (model, modelRotation,
// mirroring, group) is one mesh in the unit box, placed by a mesh solid's scale, rotation_y and
// position, so a model placed N times is stored once. Faces are repaired as for any OBJ.
#include "render/import/import_obj.hpp"
#include "render/import/import_sh3d.hpp"

#include <algorithm>
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

// The model's OBJ and .mtl colours; null (with the reason kept for a warning) when the OBJ is broken:
// one bad model should not lose the whole home. Errors reading an archive are not the model's and
// pass through.
std::shared_ptr<Sh3dModel> read_model(const std::string& name, const std::string& path, const std::string& text,
                                      const ImportOptions& options, Sh3dModelCache& cache) {
  auto model = std::make_shared<Sh3dModel>();
  try {
    model->obj = parse_obj(text);
  } catch (const InputError& e) {
    cache.unreadable_reasons.push_back("furniture model '" + quote_input(name) + "' (" + quote_input(path) +
                                       ") cannot be read: " + e.errors().front().detail + "; its pieces are boxes");
    return nullptr;
  }
  for (const std::string& library : model->obj.libraries) {
    if (auto mtl = options.read_companion(directory_of(path) + library)) parse_mtl(*mtl, model->mtl_colors);
  }
  return model;
}

// The model by its name as written, else furniture/<file name> (the layout of the example homes).
std::shared_ptr<const Sh3dModel> load_model(const std::string& name, const ImportOptions& options,
                                            Sh3dModelCache& cache) {
  if (auto it = cache.by_name.find(name); it != cache.by_name.end()) return it->second;
  std::shared_ptr<Sh3dModel> model;
  bool found = false;
  const std::string base = name.substr(name.rfind('/') + 1);
  for (const std::string& path : {name, "furniture/" + base}) {
    std::optional<std::string> text = options.read_companion ? options.read_companion(path) : std::nullopt;
    if (!text) continue;
    found = true;
    model = read_model(name, path, *text, options, cache);
    break;
  }
  if (!found) cache.missing_names.push_back(name);
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

// The model as pieces with this modelRotation and mirroring use it, built once: positions turned by
// modelRotation, centred on their box and divided by its extent (so any piece places it by scaling
// with its own size), mirrored across x (faces reversed by group_mesh); normals by the inverse
// transpose of the same map.
const Sh3dModelVariant& model_variant(const std::string& name, const Sh3dModel& model, const pugi::xml_node& node,
                                      Sh3dModelCache& cache) {
  const glm::dmat3 rotation = model_rotation(node);
  const bool mirrored = node.attribute("modelMirrored").as_bool(false);
  std::string key = name + (mirrored ? " mirrored" : "");
  for (int col = 0; col < 3; ++col) {
    for (int row = 0; row < 3; ++row) key.append(1, ' ').append(std::to_string(rotation[col][row]));
  }
  auto [it, inserted] = cache.variants.try_emplace(key);
  Sh3dModelVariant& variant = it->second;
  if (!inserted) return variant;
  Box3 box;
  std::vector<Vec3> positions(model.obj.positions.size());
  for (size_t i = 0; i < positions.size(); ++i) box.add(positions[i] = rotation * model.obj.positions[i]);
  const Vec3 middle = 0.5 * (box.lo + box.hi);
  variant.extent = box.hi - box.lo;
  Vec3 stretch{1.0};  // the extent where there is one to normalise
  for (int k = 0; k < 3; ++k) stretch[k] = variant.extent[k] > 1e-9 ? variant.extent[k] : 1.0;
  const Vec3 flip{mirrored ? -1.0 : 1.0, 1.0, 1.0};
  for (Vec3& p : positions) p = flip * (p - middle) / stretch;
  std::vector<Vec3> normals(model.obj.normals.size());
  for (size_t i = 0; i < normals.size(); ++i) normals[i] = flip * (rotation * model.obj.normals[i]) * stretch;
  std::string prefix = std::to_string(cache.variants.size());
  prefix.append(":").append(name, name.rfind('/') + 1).append("#");
  RepairCounts repairs;
  Box3 unused;
  for (size_t g = 0; g < model.obj.groups.size(); ++g) {
    json mesh = group_mesh(model.obj.groups[g], model.obj, positions, normals, mirrored, Color{0.7f}, repairs, unused);
    if (mesh["faces"].empty()) {
      variant.mesh_keys.emplace_back();
      continue;
    }
    json form = {{"vertices", std::move(mesh["vertices"])}, {"faces", std::move(mesh["faces"])}};
    if (mesh.contains("normals")) form["normals"] = std::move(mesh["normals"]);
    variant.mesh_keys.push_back(prefix + std::to_string(g));
    cache.meshes[variant.mesh_keys.back()] = std::move(form);
  }
  cache.polygons_repaired += repairs.triangulated + repairs.degenerate;
  return variant;
}

}  // namespace

bool add_piece_model(const Sh3dElement& e, const PiecePlacement& place, const ImportOptions& options,
                     Sh3dModelCache& cache, json& solids) {
  const std::string name = e.node.attribute("model").as_string("");
  if (name.empty()) return false;
  std::shared_ptr<const Sh3dModel> model = load_model(name, options, cache);
  if (!model || model->obj.positions.empty()) return false;
  const Sh3dModelVariant& variant = model_variant(name, *model, e.node, cache);
  // Scale, then rotation_y, then position (the mesh solid's order) puts the unit model on the piece's box.
  Vec3 scale{1.0};
  for (int k = 0; k < 3; ++k) scale[k] = variant.extent[k] > 1e-9 ? place.size[k] : 1.0;
  const json position = json_vec3({place.centre.x, place.base + 0.5 * place.size.y, place.centre.y});
  std::map<std::string, Color> piece_materials;
  for (pugi::xml_node m : e.node.children("material")) {
    if (auto color = color_attribute(m, "color")) piece_materials[m.attribute("name").as_string("")] = *color;
  }
  const std::optional<Color> piece_color = color_attribute(e.node, "color");
  const std::string id = std::string(e.node.attribute("name").as_string("")) + " (" + e.pointer + ")";
  for (size_t g = 0; g < model->obj.groups.size(); ++g) {
    if (variant.mesh_keys[g].empty()) continue;
    const std::string& material = model->obj.groups[g].material;
    Color color{0.7f};
    if (auto it = model->mtl_colors.find(material); it != model->mtl_colors.end()) color = it->second;
    if (auto it = piece_materials.find(material); it != piece_materials.end()) color = it->second;
    if (piece_color) color = *piece_color;
    solids.push_back({{"type", "mesh"},
                      {"id", id + " " + material},
                      {"ref", variant.mesh_keys[g]},
                      {"position", position},
                      {"rotation_y", -place.angle * 180.0 / pi},
                      {"scale", json_vec3(scale)},
                      {"color", json_color(color)}});
  }
  return true;
}

void add_model_warnings(const Sh3dModelCache& cache, std::vector<std::string>& warnings) {
  const size_t missing = cache.missing_names.size(), unreadable = cache.unreadable_reasons.size();
  if (missing || unreadable) {
    std::string names;
    for (size_t i = 0; i < std::min<size_t>(missing, 5); ++i)
      names += (i ? ", " : "") + quote_input(cache.missing_names[i]);
    if (missing > 5) names += ", ...";
    warnings.push_back(std::to_string(missing) + " furniture models were not found and " + std::to_string(unreadable) +
                       " could not be read: those pieces are boxes" + (missing ? " (not found: " + names + ")" : ""));
  }
  for (const std::string& reason : cache.unreadable_reasons) warnings.push_back(reason);
  if (cache.polygons_repaired) {
    warnings.push_back("furniture models: " + std::to_string(cache.polygons_repaired) +
                       " faces were triangulated or dropped (non-planar or of zero area)");
  }
}

namespace {

void inline_refs(std::map<std::string, json>& meshes, json& solids) {
  for (json& solid : solids) {
    auto ref = solid.find("ref");
    if (ref == solid.end() || !ref->is_string()) continue;
    auto mesh = meshes.find(ref->get<std::string>());
    if (mesh == meshes.end()) continue;
    solid.erase(ref);
    for (auto& [field, value] : mesh->second.items()) solid[field] = value;
  }
  meshes.clear();
}

}  // namespace

}  // namespace rr::import_detail

namespace rr {

void inline_mesh_refs(ImportResult& result) {
  auto solids = result.request.find("scene");
  if (solids != result.request.end() && solids->contains("solids")) {
    import_detail::inline_refs(result.meshes, (*solids)["solids"]);
  }
  result.meshes.clear();
}

}  // namespace rr
