// Scene identity: the static geometry (everything the tessellator reads) -> 16 lowercase hex digits,
// the 64-bit FNV-1a hash (hash.hpp) of a canonical binary form of the structs, never of JSON. The
// parser has applied every default and made every number a double before this runs, so one scene
// written differently (1 or 1.0, any key order, defaults omitted or spelt out) keeps one id. It is
// X-Scene-Id and the key of the BSP and shadow caches; it is not persisted, so the encoding may change.
#pragma once

#include "render/core/scene.hpp"

#include <string>

namespace rr {

std::string scene_id(const StaticGeometry& geometry);

}  // namespace rr
