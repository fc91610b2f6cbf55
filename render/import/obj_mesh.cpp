// OBJ -> one JSON mesh (obj_mesh.hpp): every group's faces as one group of the importer's. Normals
// are kept only when every face has them (a mesh has one normal per vertex or none).
#include "render/import/obj_mesh.hpp"

#include "render/import/import_obj.hpp"

namespace rr {

using nlohmann::json;
using namespace import_detail;

json obj_mesh_document(std::string_view text, std::vector<std::string>& warnings) {
  const ObjData obj = parse_obj(text);
  // One group of every face, so a vertex that several groups use stays one vertex.
  Group all;
  for (const Group& g : obj.groups) all.faces.insert(all.faces.end(), g.faces.begin(), g.faces.end());
  RepairCounts repairs;
  Box3 box;
  json mesh = group_mesh(all, obj, obj.positions, obj.normals, false, Color{0.7f}, repairs, box);
  if (mesh["faces"].empty()) throw InputError(Kind::invalid, "", "the OBJ file has no faces to draw");
  add_repair_warnings(repairs, warnings);
  json out = {{"vertices", std::move(mesh["vertices"])}, {"faces", std::move(mesh["faces"])}};
  if (mesh.contains("normals")) out["normals"] = std::move(mesh["normals"]);
  return out;
}

}  // namespace rr
