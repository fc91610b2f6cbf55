// The table of solid types: one row per type, defined in the type's own file (solid_<name>.cpp)
// next to its geometry, holding every fact the tessellator needs (name, faces, a polygon bound,
// closed and smooth). World space, metres; the Solid is validated (scene_io reads its fields, in
// render/scene_io/solid_readers.cpp). Row order is the order the schema lists the types in.
#pragma once

#include "render/core/names.hpp"
#include "render/core/scene.hpp"

#include <cstddef>
#include <cstdint>

namespace rr {

namespace detail {
class SoupBuilder;
}

struct SolidInfo {
  SolidType value;
  const char* name;  // the request's "type"
  // Appends the solid's faces, every one under `material` and `object`.
  void (*add)(detail::SoupBuilder& out, const Solid& s, uint32_t material, uint32_t object);
  size_t (*estimate)(const Solid& s);  // an upper bound on the polygons add() emits, built from nothing
  bool (*closed)(const Solid& s);      // the faces bound a volume and wind outward
  bool (*smooth)(const Solid& s);      // shading normals are averaged across faces
};

NameTable<SolidInfo> solid_table();

}  // namespace rr
