// The solid table: the rows live in their solids' own files, this lists them in the schema's order.
#include "render/core/solids.hpp"

#include <array>

namespace rr {

namespace detail {
extern const SolidInfo box_solid, cylinder_solid, pyramid_solid, prism_solid, mesh_solid, piece_solid;
}

NameTable<SolidInfo> solid_table() {
  // A function-local copy: the rows are constant-initialized in their own files, so copying them on
  // first use is safe whatever the order of static initialization.
  static const auto rows = std::to_array<SolidInfo>({detail::box_solid, detail::cylinder_solid, detail::pyramid_solid,
                                                     detail::prism_solid, detail::mesh_solid, detail::piece_solid});
  return rows;
}

}  // namespace rr
