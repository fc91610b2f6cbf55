// Sweet Home 3D <texture> elements -> request textures (import_sh3d.hpp). Home.xml writes
// <texture attribute? catalogId? name width height xOffset? yOffset? angle? scale? fittingArea?
// leftToRightOriented? image/>: `width` and `height` are one tile in centimetres, the offsets are
// fractions of a tile, `angle` is in radians and `scale` multiplies the tile. `image` names the
// image's content: an entry of a .sh3d archive ("0", "12", ...) or a file beside Home.xml, whose
// format is told from its first bytes.
#include "render/import/import_obj.hpp"  // usable_image_data_uri
#include "render/import/import_sh3d.hpp"

#include <cmath>

namespace rr::import_detail {

namespace {

std::string describe(const Sh3dElement& e, const char* attribute) {
  return "line " + std::to_string(e.line) + ": <" + e.node.name() + "> " + (*attribute ? attribute : "texture");
}

}  // namespace

std::optional<nlohmann::json> sh3d_texture(const Sh3dElement& e, const char* attribute, const ImportOptions& options,
                                           Sh3dTextures& textures, const std::optional<PlanBox>& fit) {
  pugi::xml_node node;
  for (pugi::xml_node t : e.node.children("texture")) {
    if (std::string_view(t.attribute("attribute").as_string("")) == attribute) node = t;
  }
  if (!node) return std::nullopt;
  const Sh3dElement texture{node, e.pointer, e.line};
  const std::string image = node.attribute("image").as_string("");
  const std::string catalog_id = node.attribute("catalogId").as_string("");
  const std::string key = image + "\n" + catalog_id;
  auto [it, inserted] = textures.uris.try_emplace(key);
  if (inserted) {
    std::optional<std::string> bytes =
        !image.empty() && options.read_companion ? options.read_companion(image) : std::nullopt;
    if (!bytes && !catalog_id.empty()) {
      if (std::optional<std::string_view> bundled = catalogue_texture(catalog_id)) bytes = std::string(*bundled);
    }
    std::string problem;
    if (bytes) it->second = usable_image_data_uri(*bytes, &problem);
    if (!bytes) {
      textures.missing.push_back(describe(e, attribute) + " image '" + quote_input(image.empty() ? catalog_id : image) +
                                 "' is neither in the file nor in the default catalogue");
    } else if (!it->second) {
      textures.missing.push_back(describe(e, attribute) + " image '" + quote_input(image) + "' " + problem);
    }
  }
  if (!it->second) return std::nullopt;
  const double scale = number_attribute(texture, "scale", 1.0);
  double width = number_attribute(texture, "width", 100.0) / 100.0 * scale;
  double height = number_attribute(texture, "height", 100.0) / 100.0 * scale;
  double x_offset = number_attribute(texture, "xOffset", 0.0), y_offset = number_attribute(texture, "yOffset", 0.0);
  if (fit && node.attribute("fittingArea").as_bool(false)) {
    // One tile over the room's box: its left edge at the box's least x, its bottom (the plan's t = -z
    // is up the image) at the box's greatest z.
    width = fit->hi.x - fit->lo.x;
    height = fit->hi.y - fit->lo.y;
    x_offset = fit->lo.x / width;
    y_offset = -fit->hi.y / height;
  }
  if (!(width > 0.0) || !(height > 0.0)) {
    textures.missing.push_back(describe(e, attribute) + " has a tile of no size");
    return std::nullopt;
  }
  return nlohmann::json{{"image", *it->second},      {"width", round_m(width)},
                        {"height", round_m(height)}, {"x_offset", x_offset},
                        {"y_offset", y_offset},      {"angle", number_attribute(texture, "angle", 0.0) * 180.0 / pi}};
}

void add_texture_warnings(const Sh3dTextures& textures, std::vector<std::string>& warnings) {
  for (const std::string& missing : textures.missing) warnings.push_back(missing + ": drawn untextured");
}

}  // namespace rr::import_detail
