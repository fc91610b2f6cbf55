// Sweet Home 3D furniture models (ImportOptions::furniture_models) as the parts of pieces, placed as
// Sweet Home 3D places them: modelRotation (a row-major 3x3 matrix) first, then the model's bounding
// box centred and scaled onto the piece's width x height x depth, mirrored across its width axis when
// modelMirrored, turned by the piece's angle and set on its bottom centre. Each distinct (model,
// modelRotation, mirroring, group) is one mesh in the unit box, which a piece stretches to its size,
// so a model placed N times is stored once. Faces are repaired as for any OBJ.
#include "render/import/import_obj.hpp"
#include "render/import/import_sh3d.hpp"

#include <algorithm>
#include <cmath>

namespace rr::import_detail {

using nlohmann::json;

struct Sh3dModel {
  ObjData obj;
  std::map<std::string, MtlMaterial> mtl_materials;
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
    if (auto mtl = options.read_companion(directory_of(path) + library)) parse_mtl(*mtl, model->mtl_materials);
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
  return model_rotation_matrix(node.attribute("modelRotation").as_string(""));
}

// The model as pieces with this modelRotation and mirroring use it, built once: positions turned by
// modelRotation, centred on their box and divided by its extent (so any piece places it by scaling
// with its own size), mirrored across x (faces reversed by group_mesh); normals by the inverse
// transpose of the same map.
const Sh3dModelVariant& model_variant(const std::string& name, const Sh3dModel& model, const glm::dmat3& rotation,
                                      bool mirrored, Sh3dModelCache& cache) {
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

// What a piece lays over its model, in Sweet Home 3D's order: its colour, else its texture (on every
// part), else its <material>s by name, each a colour or a texture.
struct PieceLook {
  std::optional<Color> color;
  std::optional<json> texture;
  std::map<std::string, Color> material_colors;
  std::map<std::string, json> material_textures;
};

PieceLook piece_look(const Sh3dElement& e, const ImportOptions& options, Sh3dTextures& textures) {
  PieceLook look;
  look.color = color_attribute(e.node, "color");
  if (!look.color) look.texture = sh3d_texture(e, "", options, textures);
  for (pugi::xml_node m : e.node.children("material")) {
    const std::string name = m.attribute("name").as_string("");
    if (auto color = color_attribute(m, "color")) {
      look.material_colors[name] = *color;
    } else if (auto texture = sh3d_texture(Sh3dElement{m, e.pointer, e.line}, "", options, textures)) {
      look.material_textures[name] = std::move(*texture);
    }
  }
  return look;
}

// One part per group of `variant` with faces, looking as `look` says, else as the model's .mtl, else
// the default library, else grey. A textured part has no colour of its own (white under the image)
// and is mapped by its faces' planes (docs/scene-format.md), as the model meshes carry no uvs.
json variant_parts(const Sh3dModel* model, const Sh3dModelVariant& variant, const PieceLook& look) {
  json parts = json::array();
  for (size_t g = 0; g < model->obj.groups.size(); ++g) {
    if (variant.mesh_keys[g].empty()) continue;
    const std::string& material_name = model->obj.groups[g].material;
    json part = {{"name", material_name}, {"ref", variant.mesh_keys[g]}};
    const json* texture = look.texture ? &*look.texture : nullptr;
    if (auto it = look.material_textures.find(material_name); !texture && it != look.material_textures.end())
      texture = &it->second;
    if (!look.color && texture) {
      part["texture"] = *texture;
      parts.push_back(std::move(part));
      continue;
    }
    MtlMaterial material;  // grey
    const std::map<std::string, MtlMaterial>& library = default_materials();
    if (auto it = library.find(material_name); it != library.end()) material = it->second;
    if (auto it = model->mtl_materials.find(material_name); it != model->mtl_materials.end()) material = it->second;
    // A colour of the piece's own replaces the model's material: no specular term, no texture.
    if (auto it = look.material_colors.find(material_name); it != look.material_colors.end())
      material = plain_material(it->second);
    if (look.color) material = plain_material(*look.color);
    part["color"] = json_color(material.diffuse);
    if (json m = material_json(material); !m.is_null()) part["material"] = std::move(m);
    parts.push_back(std::move(part));
  }
  return parts;
}

}  // namespace

glm::dmat3 model_rotation_matrix(std::string_view text) {
  glm::dmat3 m(1.0);
  std::vector<std::string_view> fields = split_fields(text);
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

std::optional<json> model_parts(const Sh3dElement& e, const ImportOptions& options, Sh3dModelCache& cache,
                                Sh3dTextures& textures, Vec3& extent) {
  const std::string name = e.node.attribute("model").as_string("");
  if (name.empty()) return std::nullopt;
  std::shared_ptr<const Sh3dModel> model = load_model(name, options, cache);
  if (!model || model->obj.positions.empty()) return std::nullopt;
  const bool mirrored = e.node.attribute("modelMirrored").as_bool(false);
  const Sh3dModelVariant& variant = model_variant(name, *model, model_rotation(e.node), mirrored, cache);
  extent = variant.extent;
  json parts = variant_parts(model.get(), variant, piece_look(e, options, textures));
  if (parts.empty()) return std::nullopt;
  return parts;
}

std::string unit_box_mesh(Sh3dModelCache& cache) {
  const std::string key = "unit box";
  if (!cache.meshes.contains(key)) {
    json vertices = json::array();
    for (double z : {-0.5, 0.5}) {
      for (double y : {-0.5, 0.5}) {
        for (double x : {-0.5, 0.5}) vertices.push_back({x, y, z});
      }
    }
    // Corner index = x + 2y + 4z (each 0 or 1); every quad counter-clockwise seen from outside.
    const json faces = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    cache.meshes[key] = {{"vertices", std::move(vertices)}, {"faces", faces}};
  }
  return key;
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
  for_each_mesh_holder(solids, [&](json& holder) {
    auto ref = holder.find("ref");
    if (ref == holder.end() || !ref->is_string()) return;
    auto mesh = meshes.find(ref->get<std::string>());
    if (mesh == meshes.end()) return;
    holder.erase(ref);
    for (auto& [field, value] : mesh->second.items()) holder[field] = value;
  });
  meshes.clear();
}

}  // namespace

}  // namespace rr::import_detail

namespace rr {

void for_each_mesh_holder(nlohmann::json& solids, const std::function<void(nlohmann::json&)>& visit) {
  for (nlohmann::json& solid : solids) {
    if (!solid.is_object()) continue;
    auto parts = solid.find("parts");
    if (parts == solid.end()) {
      visit(solid);
    } else if (parts->is_array()) {
      for (nlohmann::json& part : *parts) {
        if (part.is_object()) visit(part);
      }
    }
  }
}

FurnitureModel import_furniture_model(std::string_view obj_text, const std::string& name, const ImportOptions& options,
                                      std::string_view model_rotation_text) {
  using namespace import_detail;
  Sh3dModel model;
  model.obj = parse_obj(obj_text);
  for (const std::string& library : model.obj.libraries) {
    if (auto mtl = options.read_companion ? options.read_companion(library) : std::nullopt) {
      parse_mtl(*mtl, model.mtl_materials);
    }
  }
  if (model.obj.positions.empty()) throw InputError(Kind::invalid, "", "the model has no vertices");
  Sh3dModelCache cache;
  const Sh3dModelVariant& variant =
      model_variant(name, model, model_rotation_matrix(model_rotation_text), false, cache);
  FurnitureModel out;
  out.parts = variant_parts(&model, variant, PieceLook{});
  if (out.parts.empty()) throw InputError(Kind::invalid, "", "the model has no faces to draw");
  out.meshes = std::move(cache.meshes);
  out.extent = variant.extent;
  if (cache.polygons_repaired) {
    out.warnings.push_back(std::to_string(cache.polygons_repaired) +
                           " faces were triangulated or dropped (non-planar or of zero area)");
  }
  return out;
}

void inline_mesh_refs(ImportResult& result) {
  auto solids = result.request.find("scene");
  if (solids != result.request.end() && solids->contains("solids")) {
    import_detail::inline_refs(result.meshes, (*solids)["solids"]);
  }
  result.meshes.clear();
}

}  // namespace rr
