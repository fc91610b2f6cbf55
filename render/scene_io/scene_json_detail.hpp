// Internal to the request reader (scene_json.cpp, solid_readers.cpp); nothing else includes it.
// Shared ranges and readers, and the table of solid readers: one row per solid type, keyed by the
// type of render/core/solids.hpp's table, reading the members that type has (JSON -> Solid).
#pragma once

#include "render/core/scene.hpp"
#include "render/scene_io/json_reader.hpp"
#include "render/scene_io/scene_json.hpp"

#include <nlohmann/json.hpp>

#include <memory>
#include <span>
#include <string>
#include <unordered_map>

namespace rr {

// The images of one request: each distinct `image` string decoded once and its result shared by
// every surface naming it; the decoded bytes count against ParseLimits::max_texture_decoded_bytes.
struct TextureImages {
  struct Entry {
    std::shared_ptr<const TextureImage> image;  // null: refused as unreadable, for `problem`
    std::string problem;
  };
  std::unordered_map<std::string, Entry> by_image;
  size_t decoded_bytes = 0;
};

// Ranges derived from the limits, shared by every reader, and the request's list of problems.
struct Bounds {
  Bounds(const ParseLimits& l, ErrorList& e)
      : limits(l),
        errors(e),
        coordinate{-l.max_abs_coordinate, l.max_abs_coordinate},
        length{0.0, l.max_abs_coordinate, true},
        distance{0.0, l.max_abs_coordinate} {}
  const ParseLimits& limits;
  ErrorList& errors;
  NumberRange coordinate;                      // positions, centres, elevations, bases
  NumberRange length;                          // sizes, thickness, heights, radii: > 0
  NumberRange distance;                        // offsets and sills: >= 0
  const std::vector<Level>* levels = nullptr;  // the scene's levels, once read: "level" members name them
  TextureImages* images = nullptr;             // the request's images; null where no texture is read
};

// Runs read(items[i], pointer of i) for each element of an array, adding what it throws to `errors`,
// so one bad element does not hide the next.
template <class Read>
void for_each_element(const nlohmann::json& items, const std::string& pointer, ErrorList& errors, Read&& read) {
  for (size_t i = 0; i < items.size(); ++i) {
    errors.attempt([&] { read(items[i], pointer_append(pointer, i)); });
  }
}

MaterialParams read_material(const ObjectReader& owner);  // the optional "material" member

// The optional texture member `key` of an object (texture_json.cpp): null when absent or refused
// (its problems added to b.errors; too_large is thrown). A surface whose colour member is absent
// takes white when it has a texture (textured_color), so the image shows as it is.
std::shared_ptr<const SurfaceTexture> read_texture(const ObjectReader& owner, std::string_view key, const Bounds& b);
inline constexpr Color textured_default_color{1.0f, 1.0f, 1.0f};
// The colour member `key`: as given; else white when the texture member `texture_key` is present; else fallback.
Color read_surface_color(const ObjectReader& owner, std::string_view key, std::string_view texture_key, Color fallback);

// An inline mesh's "vertices", "faces", "normals" and "uvs" (mesh_json.cpp): the mesh, or nullptr after
// adding its problems to b.errors. Throws too_large and what stops reading.
std::shared_ptr<const MeshData> read_mesh_geometry(const ObjectReader& r, const Bounds& b);

struct SolidReader {
  SolidType type;
  // Reads every member of `value` but "type" (already read into s.type) into `s`, adding invalid
  // members to b.errors; throws when it cannot read on.
  void (*read)(const nlohmann::json& value, const std::string& pointer, Solid& s, const Bounds& b);
};
std::span<const SolidReader> solid_readers();  // a row for every row of solid_table()

// Levels and rooms (room_readers.cpp). read_level_ref: an element's optional "level" member as an
// index into *b.levels, -1 when absent; an unknown id is added to b.errors.
Level read_level(const nlohmann::json& value, const std::string& pointer, const Bounds& b);
void check_level_ids(const std::vector<Level>& levels, const std::string& pointer, ErrorList& errors);
Room read_room(const nlohmann::json& value, const std::string& pointer, const Bounds& b);
int read_level_ref(const nlohmann::json& element, const std::string& pointer, const Bounds& b);
// Each id of options.levels must name one of `levels`; problems at pointer/i.
void check_view_levels(const RenderOptions& options, const std::vector<Level>& levels, const std::string& pointer,
                       ErrorList& errors);

}  // namespace rr
