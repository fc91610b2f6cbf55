// schemas/*.json against the tables and the parser: every enum the schemas list equals the name
// table it stands for (same names, same order), and every `default` a schema states is the parser's
// default. The defaults are checked without a list of fields: for each schema property with a
// default, a minimal request with the property absent and the same request with the property set
// to its default must parse to the same RenderRequest (compared by an exhaustive field dump).
#include "render/core/scene_names.hpp"
#include "render/core/solids.hpp"
#include "render/pipelines/pipeline_table.hpp"
#include "render/scene_io/errors.hpp"
#include "render/scene_io/scene_json.hpp"
#include "render/scene_io/scene_json_detail.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <iomanip>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace rr {
namespace {

using nlohmann::json;

json read_schema(const std::string& name) {
  std::ifstream in(std::string(ROOMRENDER_SOURCE_DIR) + "/schemas/" + name);
  EXPECT_TRUE(in) << "cannot open schemas/" << name;
  return json::parse(in);
}

template <class Table>
std::vector<std::string> names_of(const Table& table) {
  std::vector<std::string> out;
  for (const auto& row : table) out.push_back(row.name);
  return out;
}

std::vector<std::string> strings(const json& array) { return array.get<std::vector<std::string>>(); }

// The `type` constants of the $defs a oneOf refers to, in oneOf order: the schema's list of solid,
// light or opening types.
std::vector<std::string> discriminators(const json& scene_schema, const std::string& def) {
  std::vector<std::string> out;
  for (const json& choice : scene_schema["$defs"][def]["oneOf"]) {
    std::string ref = choice["$ref"];  // "#/$defs/box"
    out.push_back(scene_schema["$defs"][ref.substr(ref.rfind('/') + 1)]["properties"]["type"]["const"]);
  }
  return out;
}

TEST(SchemaTables, RequestEnumsEqualTheTables) {
  const json options = read_schema("request.schema.json")["$defs"]["options"]["properties"];
  EXPECT_EQ(strings(options["pipeline"]["enum"]), names_of(pipeline_table()));
  EXPECT_EQ(strings(options["shading"]["enum"]), names_of(shading_names));
  EXPECT_EQ(strings(options["painter"]["properties"]["key"]["enum"]), names_of(painter_key_names));
  EXPECT_EQ(strings(options["bsp"]["properties"]["traversal"]["enum"]), names_of(bsp_traversal_names));
  EXPECT_EQ(strings(options["shadow"]["properties"]["fit"]["enum"]), names_of(shadow_fit_names));
  EXPECT_EQ(strings(options["shadow"]["properties"]["method"]["enum"]), names_of(shadow_method_names));
  EXPECT_EQ(strings(options["png"]["properties"]["compression"]["enum"]), names_of(png_compression_names));
  EXPECT_EQ(strings(options["ceilings"]["enum"]), names_of(ceiling_mode_names));
  EXPECT_EQ(strings(options["culling"]["enum"]), names_of(culling_mode_names));
  EXPECT_EQ(strings(options["texture_filter"]["enum"]), names_of(texture_filter_names));
}

TEST(SchemaTables, SceneTypesEqualTheTables) {
  const json scene = read_schema("scene.schema.json");
  EXPECT_EQ(discriminators(scene, "solid"), names_of(solid_table()));
  EXPECT_EQ(discriminators(scene, "light"), names_of(light_type_names));
  EXPECT_EQ(discriminators(scene, "opening"), names_of(opening_type_names));
}

// The parser has a reader for every solid type the tessellator knows (a missing one would read no
// members at all and leave the type's defaults).
TEST(SchemaTables, EverySolidTypeHasAReader) {
  for (const SolidInfo& solid : solid_table()) {
    int readers = 0;
    for (const SolidReader& reader : solid_readers()) readers += reader.type == solid.value;
    EXPECT_EQ(readers, 1) << solid.name;
  }
  EXPECT_EQ(solid_readers().size(), solid_table().size());
}

// The query parameters of GET /v1/scenes/{id}/render.png that list their values.
TEST(SchemaTables, OpenApiParameterEnumsEqualTheTables) {
  const json parameters = read_schema("openapi.json")["paths"]["/v1/scenes/{id}/render.png"]["get"]["parameters"];
  const std::vector<std::pair<std::string, std::vector<std::string>>> tables = {
      {"pipeline", names_of(pipeline_table())},         {"shading", names_of(shading_names)},
      {"painter_key", names_of(painter_key_names)},     {"bsp_traversal", names_of(bsp_traversal_names)},
      {"shadow_fit", names_of(shadow_fit_names)},       {"png", names_of(png_compression_names)},
      {"shadow_method", names_of(shadow_method_names)}, {"texture_filter", names_of(texture_filter_names)}};
  for (const json& p : parameters) {
    if (!p["schema"].contains("enum")) continue;
    for (const auto& [name, table] : tables) {
      if (p["name"] == name) {
        EXPECT_EQ(strings(p["schema"]["enum"]), table) << "parameter " << name;
      }
    }
  }
}

// --- defaults ------------------------------------------------------------------------------------

// Every field of a parsed request, in a fixed order: two requests parse alike iff their dumps match.
class Dump {
 public:
  template <class T>
  Dump& operator()(const char* name, const T& v) {
    out_ << name << '=';
    put(v);
    out_ << ';';
    return *this;
  }
  std::string str() const { return out_.str(); }

 private:
  void put(double v) { out_ << std::setprecision(17) << v; }  // round-trips every double
  void put(float v) { put(double(v)); }
  void put(int v) { out_ << v; }
  void put(bool v) { out_ << v; }
  void put(unsigned v) { out_ << v; }
  void put(const std::string& v) { out_ << '"' << v << '"'; }
  void put(Vec2 v) { put(v.x), out_ << ',', put(v.y); }
  void put(Vec3 v) { put(v.x), out_ << ',', put(v.y), out_ << ',', put(v.z); }
  void put(Color v) { put(v.r), out_ << ',', put(v.g), out_ << ',', put(v.b); }
  void put(PipelineId v) { out_ << int(v.index); }
  template <class E>
  requires std::is_enum_v<E>
  void put(E v) { out_ << int(v); }
  template <class T>
  void put(const std::vector<T>& v) {
    out_ << '[';
    for (const T& item : v) put(item), out_ << ' ';
    out_ << ']';
  }
  void put(const std::optional<Color>& c) {
    if (c) put(*c);
  }
  void put(const std::shared_ptr<const SurfaceTexture>& t) {
    if (!t) return;
    (*this)("image", t->image)("width", t->width)("height", t->height)("x_offset", t->x_offset)(
        "y_offset", t->y_offset)("angle", t->angle);
  }
  void put(const MaterialParams& m) {
    (*this)("specular", m.specular)("specular_color", m.specular_color)("shininess", m.shininess);
  }
  void put(const Opening& o) {
    (*this)("type", o.type)("id", o.id)("offset", o.offset)("width", o.width)("height", o.height)("sill", o.sill)(
        "color", o.color)("opacity", o.opacity)("leaf", o.leaf);
  }
  void put(const Wall& w) {
    (*this)("id", w.id)("start", w.start)("end", w.end)("thickness", w.thickness)("height", w.height)("base", w.base)(
        "color", w.color)("material", w.material)("left_color", w.left_color)("right_color", w.right_color)(
        "left_texture", w.left_texture)("right_texture", w.right_texture)("openings", w.openings);
  }
  void put(const Solid& s) {
    (*this)("type", s.type)("id", s.id)("color", s.color)("material", s.material)("texture", s.texture)(
        "center", s.center)("base", s.base)("rotation_y", s.rotation_y_deg)("size", s.size)("radius", s.radius)(
        "height", s.height)("segments", s.segments)("smooth", s.smooth)("caps", s.caps)("points", s.points)(
        "mesh", s.mesh)("mesh_ref", s.mesh_ref)("position", s.position)("scale", s.scale)("closed", s.closed)(
        "parts", s.parts)("mirrored", s.mirrored);
  }
  void put(const PiecePart& p) {
    (*this)("name", p.name)("mesh", p.mesh)("mesh_ref", p.mesh_ref)("color", p.color)("material", p.material)(
        "texture", p.texture)("transformed", p.transformed)("linear.x", p.linear[0])("linear.y", p.linear[1])(
        "linear.z", p.linear[2])("offset", p.offset);
  }
  void put(const std::shared_ptr<const MeshData>& m) {
    if (!m) return;
    (*this)("vertices", m->vertices)("faces", m->faces)("normals", m->normals)("uvs", m->uvs);
  }
  void put(const std::vector<uint32_t>& face) {
    for (uint32_t i : face) out_ << i << ',';
  }
  void put(const Room& r) {
    (*this)("id", r.id)("points", r.points)("elevation", r.elevation)("floor", r.floor)("floor_color", r.floor_color)(
        "floor_texture", r.floor_texture)("material", r.floor_material)("ceiling", r.ceiling)(
        "ceiling_height", r.ceiling_height)("ceiling_color", r.ceiling_color)("ceiling_texture", r.ceiling_texture)(
        "level", r.level);
  }
  void put(const Level& l) {
    (*this)("id", l.id)("elevation", l.elevation)("height", l.height)("viewable", l.viewable);
  }
  void put(const Light& l) {
    (*this)("type", l.type)("id", l.id)("direction", l.direction)("position", l.position)("color", l.color)(
        "intensity", l.intensity)("attenuation", l.attenuation);
  }

  std::ostringstream out_;
};

std::string dump(const RenderRequest& r) {
  Dump d;
  const Scene& s = r.scene;
  const Floor& f = s.geometry.floor;
  d("background", s.background)("ambient.color", s.ambient.color)("ambient.intensity", s.ambient.intensity);
  d("has_floor", s.geometry.has_floor)("floor.id", f.id)("floor.origin", f.origin)("floor.cells_x", f.cells_x)(
      "floor.cells_z", f.cells_z)("floor.cell_size", f.cell_size)("floor.elevation", f.elevation)(
      "floor.colors", f.colors)("floor.material", f.material)("floor.texture", f.texture);
  d("walls", s.geometry.walls)("solids", s.geometry.solids)("lights", s.lights);
  d("rooms", s.geometry.rooms)("levels", s.geometry.levels);
  const Camera& c = r.camera;
  d("camera.position", c.position)("camera.target", c.target)("camera.up", c.up)("camera.fov_y", c.fov_y_deg)(
      "camera.near", c.near)("camera.far", c.far);
  const RenderOptions& o = r.options;
  d("width", o.width)("height", o.height)("pipeline", o.pipeline)("shading", o.shading)("painter_key", o.painter_key)(
      "shadows", o.shadows)("png", o.png_compression);
  d("levels_given", o.levels_given)("levels", o.levels)("ceilings", o.ceilings)("culling", o.culling)("texture_filter",
                                                                                                      o.texture_filter);
  d("bsp.w1", o.bsp.w1)("bsp.w2", o.bsp.w2)("bsp.w3", o.bsp.w3)("bsp.epsilon", o.bsp.epsilon)(
      "bsp.max_candidates", o.bsp.max_candidates)("bsp.traversal", o.bsp.traversal);
  d("shadow.size", o.shadow.size)("shadow.pcf", o.shadow.pcf)("shadow.bias", o.shadow.bias)(
      "shadow.slope_bias", o.shadow.slope_bias)("shadow.fit", o.shadow.fit)("shadow.method", o.shadow.method);
  return d.str();
}

// The first field (of dump()'s "name=value;" list) where two dumps differ, or "" when they match.
std::string first_difference(const std::string& a, const std::string& b) {
  size_t start = 0;
  while (start < a.size() && start < b.size()) {
    size_t end_a = a.find(';', start), end_b = b.find(';', start);
    std::string field_a = a.substr(start, end_a - start), field_b = b.substr(start, end_b - start);
    if (field_a != field_b) return field_a + "  vs  " + field_b;
    if (end_a == std::string::npos) break;
    start = end_a + 1;
  }
  return a == b ? "" : "the dumps differ in length";
}

// Where each schema object with defaults sits in a minimal valid request, with its required members.
struct Site {
  std::string schema;     // file in schemas/
  std::string def;        // "" for the schema's root, else a $defs name
  json::json_pointer at;  // where the object sits in the request
  json request;           // a minimal valid request holding the object at `at`
};

std::vector<Site> sites() {
  const json wall = {{"start", {0, 0}}, {"end", {4, 0}}};
  auto with_wall_opening = [&](json opening) {
    json w = wall;
    w["openings"] = {std::move(opening)};
    return json{{"scene", {{"walls", {w}}}}};
  };
  auto with_solid = [](json solid) { return json{{"scene", {{"solids", {std::move(solid)}}}}}; };
  auto with_light = [](json light) { return json{{"scene", {{"lights", {std::move(light)}}}}}; };
  // A 1 x 1 PNG.
  const json texture = {{"image",
                         "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAIAAACQd1PeAAAADElEQVR4nGP438AAAAQBAYD"
                         "FKhhdAAAAAElFTkSuQmCC"}};
  const json piece = {{"type", "piece"},
                      {"center", {0, 0}},
                      {"size", {1, 1, 1}},
                      {"parts", {{{"vertices", {{0, 0, 0}, {0.5, 0, 0}, {0, 0, 0.5}}}, {"faces", {{0, 1, 2}}}}}}};
  return {
      {"request.schema.json", "", json::json_pointer(""), json::object()},
      {"request.schema.json", "camera", json::json_pointer("/camera"), json::object()},
      {"request.schema.json", "options", json::json_pointer("/options"), json::object()},
      {"view.schema.json", "", json::json_pointer(""), json::object()},
      {"scene.schema.json", "", json::json_pointer("/scene"), json::object()},
      {"scene.schema.json", "ambient", json::json_pointer("/scene/ambient"), json::object()},
      {"scene.schema.json", "floor", json::json_pointer("/scene/floor"), {{"scene", {{"floor", {{"cells", {2, 2}}}}}}}},
      {"scene.schema.json",
       "material",
       json::json_pointer("/scene/walls/0/material"),
       {{"scene", {{"walls", {wall}}}}}},
      {"scene.schema.json", "wall", json::json_pointer("/scene/walls/0"), {{"scene", {{"walls", {wall}}}}}},
      {"scene.schema.json", "door", json::json_pointer("/scene/walls/0/openings/0"),
       with_wall_opening({{"type", "door"}, {"offset", 0.5}, {"width", 0.9}})},
      {"scene.schema.json", "window", json::json_pointer("/scene/walls/0/openings/0"),
       with_wall_opening({{"type", "window"}, {"offset", 0.5}, {"width", 1.0}})},
      {"scene.schema.json", "box", json::json_pointer("/scene/solids/0"),
       with_solid({{"type", "box"}, {"center", {0, 0}}, {"size", {1, 1, 1}}})},
      {"scene.schema.json", "pyramid", json::json_pointer("/scene/solids/0"),
       with_solid({{"type", "pyramid"}, {"center", {0, 0}}, {"size", {1, 1, 1}}})},
      {"scene.schema.json", "cylinder", json::json_pointer("/scene/solids/0"),
       with_solid({{"type", "cylinder"}, {"center", {0, 0}}, {"radius", 0.5}, {"height", 1}})},
      {"scene.schema.json", "prism", json::json_pointer("/scene/solids/0"),
       with_solid({{"type", "prism"}, {"points", {{0, 0}, {1, 0}, {0, 1}}}, {"height", 1}})},
      {"scene.schema.json", "mesh", json::json_pointer("/scene/solids/0"),
       with_solid({{"type", "mesh"}, {"vertices", {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}}}, {"faces", {{0, 1, 2}}}})},
      {"scene.schema.json", "piece", json::json_pointer("/scene/solids/0"), with_solid(piece)},
      {"scene.schema.json", "piece_part", json::json_pointer("/scene/solids/0/parts/0"), with_solid(piece)},
      {"scene.schema.json", "texture", json::json_pointer("/scene/solids/0/texture"),
       with_solid({{"type", "box"}, {"center", {0, 0}}, {"size", {1, 1, 1}}, {"texture", texture}})},
      {"scene.schema.json", "directional_light", json::json_pointer("/scene/lights/0"),
       with_light({{"type", "directional"}})},
      {"scene.schema.json", "point_light", json::json_pointer("/scene/lights/0"),
       with_light({{"type", "point"}, {"position", {0, 2, 0}}})},
      {"scene.schema.json",
       "room",
       json::json_pointer("/scene/rooms/0"),
       {{"scene", {{"rooms", {{{"points", {{0, 0}, {1, 0}, {0, 1}}}}}}}}}},
      {"scene.schema.json",
       "level",
       json::json_pointer("/scene/levels/0"),
       {{"scene", {{"levels", {{{"id", "ground"}}}}}}}},
  };
}

// Calls check(pointer, default) for every property under `object` (its nested objects too) that
// states a default, with the property's pointer relative to the object.
template <class Check>
void each_default(const json& object, const json::json_pointer& at, const Check& check) {
  if (!object.contains("properties")) return;
  for (const auto& [key, property] : object["properties"].items()) {
    if (property.contains("default")) check(at / key, property["default"]);
    each_default(property, at / key, check);
  }
}

TEST(SchemaTables, SchemaDefaultsAreTheParsersDefaults) {
  int checked = 0;
  for (const Site& site : sites()) {
    const json schema = read_schema(site.schema);
    const json& object = site.def.empty() ? schema : schema["$defs"][site.def];
    ASSERT_TRUE(object.is_object()) << site.schema << " has no $defs/" << site.def;
    const std::string without = dump(request_from_json(site.request));
    each_default(object, site.at, [&](const json::json_pointer& at, const json& value) {
      json request = site.request;
      if (request.contains(at)) return;  // a member the minimal request needs: no default to test
      request[at] = value;
      SCOPED_TRACE(site.schema + " " + (site.def.empty() ? "" : "$defs/" + site.def + " ") + at.to_string() +
                   " default " + value.dump());
      try {
        EXPECT_EQ(first_difference(dump(request_from_json(request)), without), "")
            << "parsed with the default given  vs  parsed without it";
      } catch (const InputError& e) {
        ADD_FAILURE() << "the parser refuses the schema's default: " << e.pointer() << ": " << e.what();
      }
      ++checked;
    });
  }
  EXPECT_GT(checked, 80);  // every site contributes; a schema reshuffle that hides them fails here
}

}  // namespace
}  // namespace rr
