// The request format's name for every value of the enums in scene.hpp, one name table each (row
// order = the order the schema lists them). The parser reads every enum field through these, the
// writers and GET /v1/pipelines print them, and tests/unit/test_schema_tables.cpp holds
// schemas/*.json to them. Solid types are named in solids.hpp, pipelines in the pipeline table.
#pragma once

#include "render/core/names.hpp"
#include "render/core/scene.hpp"

#include <array>

namespace rr {

inline constexpr std::array<NameRow<ShadingMode>, 3> shading_rows = {{
    {ShadingMode::flat, "flat"},
    {ShadingMode::gouraud, "gouraud"},
    {ShadingMode::phong, "phong"},
}};
inline constexpr NameTable<NameRow<ShadingMode>> shading_names{shading_rows};

inline constexpr std::array<NameRow<PngCompression>, 3> png_compression_rows = {{
    {PngCompression::fast, "fast"},
    {PngCompression::small, "small"},
    {PngCompression::none, "none"},
}};
inline constexpr NameTable<NameRow<PngCompression>> png_compression_names{png_compression_rows};

inline constexpr std::array<NameRow<PainterKey>, 4> painter_key_rows = {{
    {PainterKey::mean, "mean"},
    {PainterKey::min, "min"},
    {PainterKey::max, "max"},
    {PainterKey::newell, "newell"},
}};
inline constexpr NameTable<NameRow<PainterKey>> painter_key_names{painter_key_rows};

inline constexpr std::array<NameRow<BspTraversal>, 2> bsp_traversal_rows = {{
    {BspTraversal::front_to_back, "front_to_back"},
    {BspTraversal::back_to_front, "back_to_front"},
}};
inline constexpr NameTable<NameRow<BspTraversal>> bsp_traversal_names{bsp_traversal_rows};

inline constexpr std::array<NameRow<ShadowFit>, 2> shadow_fit_rows = {{
    {ShadowFit::view, "view"},
    {ShadowFit::scene, "scene"},
}};
inline constexpr NameTable<NameRow<ShadowFit>> shadow_fit_names{shadow_fit_rows};

inline constexpr std::array<NameRow<ShadowMethod>, 2> shadow_method_rows = {{
    {ShadowMethod::map, "map"},
    {ShadowMethod::rays, "rays"},
}};
inline constexpr NameTable<NameRow<ShadowMethod>> shadow_method_names{shadow_method_rows};

inline constexpr std::array<NameRow<LightType>, 2> light_type_rows = {{
    {LightType::directional, "directional"},
    {LightType::point, "point"},
}};
inline constexpr NameTable<NameRow<LightType>> light_type_names{light_type_rows};

inline constexpr std::array<NameRow<OpeningType>, 2> opening_type_rows = {{
    {OpeningType::door, "door"},
    {OpeningType::window, "window"},
}};
inline constexpr NameTable<NameRow<OpeningType>> opening_type_names{opening_type_rows};

inline constexpr std::array<NameRow<CeilingMode>, 3> ceiling_mode_rows = {{
    {CeilingMode::automatic, "auto"},
    {CeilingMode::on, "on"},
    {CeilingMode::off, "off"},
}};
inline constexpr NameTable<NameRow<CeilingMode>> ceiling_mode_names{ceiling_mode_rows};

inline constexpr std::array<NameRow<CullingMode>, 2> culling_mode_rows = {{
    {CullingMode::on, "on"},
    {CullingMode::off, "off"},
}};
inline constexpr NameTable<NameRow<CullingMode>> culling_mode_names{culling_mode_rows};

inline constexpr std::array<NameRow<TextureFilter>, 4> texture_filter_rows = {{
    {TextureFilter::nearest, "nearest"},
    {TextureFilter::bilinear, "bilinear"},
    {TextureFilter::trilinear, "trilinear"},
    {TextureFilter::anisotropic, "anisotropic"},
}};
inline constexpr NameTable<NameRow<TextureFilter>> texture_filter_names{texture_filter_rows};

}  // namespace rr
