// Internals of the Sweet Home 3D importer shared by import_sweethome3d.cpp (the home: levels, rooms,
// furniture, lights, camera) and import_sh3d_walls.cpp (walls and the openings cut into them).
// Everything here is already in world units: metres, plan point (x, z) = (x_cm, y_cm) / 100, since
// the plan's y axis points down exactly as our +Z does when seen from above.
#pragma once

#include "render/import/import_common.hpp"

#include <pugixml.hpp>

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace rr::import_detail {

// One element of Home.xml with where it is: a pointer-like path ("/home/wall/3": the fourth <wall>
// child of <home>) and its 1-based line.
struct Sh3dElement {
  pugi::xml_node node;
  std::string pointer;
  size_t line = 0;
};

struct Sh3dLevel {
  std::string id;  // the level's id attribute, and its id in the scene's levels; empty: no level
  double elevation_m = 0.0;
  double floor_thickness_m = 0.12;
  double height_m = 2.5;  // floor to ceiling: its rooms' ceiling height
  bool viewable = true;   // Sweet Home 3D shows it (visible and viewable)
};

// What the readers share: levels by id, the default wall height, and the line table for messages.
struct Sh3dHome {
  std::map<std::string, Sh3dLevel> levels;
  std::vector<std::string> level_order;  // level ids in document order
  double wall_height_m = 2.5;
  std::vector<size_t> line_starts;  // byte offset of each line's first character
  size_t line_of(const pugi::xml_node& node) const;
};

// Elements by name in document order, furniture groups flattened (their children carry absolute
// coordinates in Home.xml). An explicit stack, so deep nesting cannot exhaust ours.
std::map<std::string, std::vector<Sh3dElement>> collect_elements(const pugi::xml_node& home, const Sh3dHome& h);

// Attribute readers: a missing optional attribute gives `fallback`; a present one that is not a
// finite number, or a missing required one, is an InputError naming the element, attribute and line.
double number_attribute(const Sh3dElement& e, const char* name, double fallback);
double required_number(const Sh3dElement& e, const char* name);
// "AARRGGBB" or "RRGGBB" hex -> colour (alpha ignored); nullopt when absent or not hex.
std::optional<Color> color_attribute(const pugi::xml_node& node, const char* name);

// The element's level (absent: the ground at elevation 0, with no id). Hidden levels are imported
// too, tagged with their level, which the scene marks not viewable. A level the home does not define
// is an InputError, since its elevation cannot be known.
const Sh3dLevel& element_level(const Sh3dElement& e, const Sh3dHome& h);

// Adds "level": the level's id to a scene element when the element is on a level.
void tag_level(nlohmann::json& element, const Sh3dLevel& level);

// A door or window as the walls see it: its span along its own x axis, in metres.
struct Sh3dOpening {
  const Sh3dElement* element = nullptr;
  std::string name;
  bool door = false;
  bool leaf = true;  // doors: false for open doors and bare frames (their names say so)
  Vec2 centre{0.0};
  Vec2 axis{1.0, 0.0};                                             // its width direction in the plan
  double width = 0.0, depth = 0.0, height = 0.0, elevation = 0.0;  // elevation above its level
  std::string level;
};

// Where a piece of furniture goes: the centre of its box on the plan, its bottom, its size (x along
// its width, y up, z along its depth) and its angle (Sweet Home 3D's: clockwise on the plan).
struct PiecePlacement {
  Vec2 centre{0.0};
  double base = 0.0;
  Vec3 size{1.0};
  double angle = 0.0;
};

struct Sh3dModel;  // a parsed furniture OBJ and its .mtl colours (import_sh3d_models.cpp)

// One model as pieces use it (model, modelRotation, modelMirrored): its groups as meshes normalised
// to the unit box centred on the origin (so a placement is scale = the piece's size, rotation_y and
// position), and which axes had no extent to normalise (scale 1 there).
struct Sh3dModelVariant {
  std::vector<std::string> mesh_keys;  // per OBJ group; "" when the group has no face left
  Vec3 extent{1.0};                    // of the model's box after modelRotation; 0: flat on that axis
};

// Furniture models read so far, by the `model` attribute; null when unavailable or unreadable.
struct Sh3dModelCache {
  std::map<std::string, std::shared_ptr<const Sh3dModel>> by_name;
  std::map<std::string, Sh3dModelVariant> variants;
  std::map<std::string, nlohmann::json> meshes;  // ImportResult::meshes
  std::vector<std::string> missing_names, unreadable_reasons;
  size_t polygons_repaired = 0;
};

struct Sh3dTextures;

// The parts of a piece's model, one per OBJ group with faces: {"name": its material, "ref": its mesh
// in cache.meshes (the unit box form), "color"[, "material"]} or, textured, {"name", "ref",
// "texture"}: the piece's color, else its <texture> on every part, else its <material>s' colours and
// textures by name, else the model's .mtl, else Sweet Home 3D's default library (whose materials
// bring their specular terms too), else grey; textures are read through `textures`. `extent` gets the model's extent
// after its modelRotation (0 on an axis where it is flat). nullopt when the model is not available through
// options.read_companion (its name as written, then furniture/<file name>) or has no faces.
std::optional<nlohmann::json> model_parts(const Sh3dElement& e, const ImportOptions& options, Sh3dModelCache& cache,
                                          Sh3dTextures& textures, Vec3& extent);

// Sweet Home 3D's modelRotation text (a row-major 3x3 matrix of 9 numbers), identity when absent or
// malformed.
glm::dmat3 model_rotation_matrix(std::string_view text);

// The key in cache.meshes of the unit cube [-0.5, 0.5]^3 (a group's member without a model).
std::string unit_box_mesh(Sh3dModelCache& cache);

// The warnings about models that were missing, unreadable or repaired.
void add_model_warnings(const Sh3dModelCache& cache, std::vector<std::string>& warnings);

// A lamp's light source as a point light lit the way Sweet Home 3D's photo renderer lights it: there
// a sphere of radius r (cm) and radiance 5 power^2 / r^2 x source colour x home light colour (both
// 0..255 per channel) gives a diffuse surface at d cm, facing it, the radiance
// albedo x 5 power^2 x source x home / d^2 (the sphere's pi r^2 cancels the r^2 and Lambert's 1/pi).
// In metres and colours 0..1 that is albedo x intensity x colour / (r_m^2 + d_m^2) with
// intensity = 5 x 255^2 / 100^2 x power^2, colour = source x home, attenuation (r_m^2, 0, 1):
// the sphere's radius keeps the light finite at its own centre.
struct Sh3dLampLight {
  Color color{1.0f};
  double intensity = 0.0;
  double radius_m = 0.0325;
};
Sh3dLampLight sh3d_lamp_light(double power, Color source_color, Color home_light_color, std::optional<double> diameter,
                              double lamp_width_m);

// Sweet Home 3D's default texture `catalog_id` ("eTeks#redTiles") as its JPEG bytes; nullopt for any
// other id (catalogue_textures.cpp, generated from catalogue/textures/).
std::optional<std::string_view> catalogue_texture(std::string_view catalog_id);

// The images of a home's <texture> elements, each read and encoded once (by `image` and catalogId),
// and the textures that could not be used, for the warnings.
struct Sh3dTextures {
  std::map<std::string, std::optional<std::string>> uris;  // data: URIs
  std::vector<std::string> missing;
};

// A plan rectangle in metres (x, z).
struct PlanBox {
  Vec2 lo, hi;
};

// The <texture attribute='`attribute`'> child of `e` as a request texture: {"image": a data: URI,
// "width", "height" (the tile in metres, times `scale`), "x_offset", "y_offset" (fractions of a tile),
// "angle" (degrees)}. Its image is the `image` entry read through options.read_companion, else the
// default catalogue's image of its catalogId. With fittingArea and `fit` (a room's box), one tile
// covers the box. nullopt without such a child, or when its image cannot be had (noted in
// textures.missing).
std::optional<nlohmann::json> sh3d_texture(const Sh3dElement& e, const char* attribute, const ImportOptions& options,
                                           Sh3dTextures& textures, const std::optional<PlanBox>& fit = std::nullopt);

// One warning per texture drawn untextured.
void add_texture_warnings(const Sh3dTextures& textures, std::vector<std::string>& warnings);

// Walls (arcs split into segments, sloped tops as a wall plus a wedge mesh) with every door and
// window cut into the walls it intersects, and the textures of their sides. Appends to `walls` and
// `solids`, warnings to `warnings`.
void add_sh3d_walls(const std::vector<Sh3dElement>& wall_elements, const std::vector<Sh3dOpening>& openings,
                    const Sh3dHome& h, const ImportOptions& options, Sh3dTextures& textures, nlohmann::json& walls,
                    nlohmann::json& solids, std::vector<std::string>& warnings, Box3& box);

}  // namespace rr::import_detail
