// JSON text -> RenderRequest (docs/scene-format.md). Every error is an InputError carrying the JSON
// Pointer of the offending value: malformed text -> Kind::malformed, schema or semantic violations ->
// Kind::invalid, documented limits -> Kind::too_large. On success every default is applied.
#pragma once

#include "render/core/scene.hpp"
#include "render/core/texture.hpp"
#include "render/scene_io/errors.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

namespace rr {

// The bytes one texture image may have, as its data: URI decodes (docs/scene-format.md, "Textures"):
// 4 MiB is about 5.6 MiB of base64, so an image fits in a request under the server's 8 MiB body limit.
// The importers skip larger image files with a warning.
inline constexpr size_t texture_image_bytes_cap = size_t{4} << 20;

struct ParseLimits {
  size_t max_depth = 64;                     // JSON nesting, checked while parsing
  int max_image_side = 4096;                 // width and height
  long long max_pixels = 16'800'000;         // width * height
  long long max_render_bytes = 512LL << 20;  // a frame's buffers, the A-buffer included (render_bytes)
  size_t max_polygons = 2'000'000;           // after tessellation, estimated before it runs
  int max_cylinder_segments = 1024;
  long long max_floor_cells = 1'000'000;
  double max_abs_coordinate = 1e7;  // metres, every position-like number (national grids reach 1e7)
  double max_far_over_near = 1e7;
  size_t max_mesh_vertices = 4'000'000;  // one mesh's vertices (its faces count against max_polygons)
  size_t max_texture_image_bytes = texture_image_bytes_cap;  // one image's encoded bytes
  TextureLimits texture;                                     // one image's sides and pixels, from its header
  // Every distinct image of a request decoded, mip chains counted as 4/3 of their level 0 (RGB): four
  // images of the largest size TextureLimits allows.
  size_t max_texture_decoded_bytes = size_t{256} << 20;
  // Finds a stored mesh for a mesh solid's "ref" (nullptr: none). Unset, every ref is refused (422).
  std::function<std::shared_ptr<const MeshData>(const std::string& id)> resolve_mesh;
  // Whether a ref names a mesh that is always there (the server's catalogue): a stored scene placing
  // it depends on no stored document. Unset: none is.
  std::function<bool(const std::string& id)> builtin_mesh;
  // Finds a stored image for a texture's "image" given as a 16-hex-digit id (nullptr: none). Unset,
  // every id is refused (422).
  std::function<std::shared_ptr<const TextureImage>(const std::string& id)> resolve_texture;
  // Whether an image id names an image that is always there (the server's texture catalogue): a
  // stored scene naming it depends on no stored document. Unset: none is.
  std::function<bool(const std::string& id)> builtin_texture;
};

// Parses JSON text, rejecting what nlohmann would accept but we will not: nesting deeper than
// limits.max_depth (checked during parsing, before memory grows), duplicate object keys, NaN/Infinity
// and numbers that overflow a double. Throws InputError(malformed).
nlohmann::json parse_json_text(std::string_view text, const ParseLimits& limits = {});

// Builds a request from parsed JSON, validating every field. Throws InputError.
RenderRequest request_from_json(const nlohmann::json& request, const ParseLimits& limits = {});

// Throws InputError(invalid) at /options/levels/i when a selected level is not one of `levels`: a
// stored scene's view is read without its scene, so the selection is checked against it afterwards.
void check_view_levels(const RenderOptions& options, const std::vector<Level>& levels);

// parse_json_text + request_from_json.
RenderRequest parse_request(std::string_view text, const ParseLimits& limits = {});

}  // namespace rr
