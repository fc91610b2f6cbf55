// JSON texture objects -> SurfaceTexture (docs/scene-format.md, "Textures"): {"image", "width",
// "height", "x_offset", "y_offset", "angle"}, the angle in degrees as every angle of the format and
// stored in radians. `image` is a data: URI of a PNG or JPEG, or the 16-hex-digit id of a stored
// image, found through the limits' resolver. Each distinct image is decoded once per request; its
// size is checked from the URI's length and the image's header before anything is decoded. A stored
// image's pixels count against the request's decoded budget as an inline one's do.
#include "render/scene_io/errors.hpp"
#include "render/scene_io/scene_json_detail.hpp"

#include <algorithm>
#include <numbers>

namespace rr {

using nlohmann::json;

namespace {

// 3 bytes per pixel, and the mip chain below level 0 adds a third again (1/4 + 1/16 + ... < 1/3).
constexpr size_t decoded_bytes_per_pixel = 4;

bool is_image_id(const std::string& text) {
  return text.size() == 16 &&
         std::all_of(text.begin(), text.end(), [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); });
}

// The most bytes the base64 after the URI's comma can decode to ('=' padding and the partial last
// quantum counted exactly; characters that are not base64 are refused by the decoder later).
size_t base64_decoded_bound(const std::string& uri) {
  const size_t comma = uri.find(',');
  if (comma == std::string::npos) return 0;
  size_t length = uri.size() - comma - 1;
  for (int pad = 0; pad < 2 && length > 0 && uri[comma + length] == '='; ++pad) --length;
  return length / 4 * 3 + (length % 4) * 3 / 4;
}

std::string bytes_text(size_t bytes) { return std::to_string(bytes) + " bytes"; }

// Decodes a data: URI the request has not named before. Throws too_large (413) for an image over
// the byte or size caps and invalid (422) for one that cannot be read, the latter remembered so a
// second surface naming it is told the same without decoding it again.
std::shared_ptr<const TextureImage> decode_image(const std::string& uri, const std::string& pointer, const Bounds& b) {
  TextureImages& images = *b.images;
  const ParseLimits& limits = b.limits;
  auto refuse = [&](const std::string& problem) -> std::shared_ptr<const TextureImage> {
    images.by_image[uri] = TextureImages::Entry{nullptr, problem};
    throw_invalid(pointer, problem);
  };
  if (size_t bound = base64_decoded_bound(uri); bound > limits.max_texture_image_bytes) {
    throw_too_large(pointer, "the image holds " + bytes_text(bound) + "; at most " +
                                 bytes_text(limits.max_texture_image_bytes) + " are allowed per image");
  }
  std::vector<uint8_t> encoded;
  std::string problem;
  if (!decode_data_uri(uri, limits.max_texture_image_bytes, encoded, &problem)) return refuse(problem);
  // The request's remaining budget bounds this image's pixels, so an image over it is refused from
  // its header like one over the per-image limits.
  const size_t remaining =
      limits.max_texture_decoded_bytes - std::min(images.decoded_bytes, limits.max_texture_decoded_bytes);
  TextureLimits image_limits = limits.texture;
  image_limits.max_pixels = std::min(image_limits.max_pixels, remaining / decoded_bytes_per_pixel);
  TextureError error;
  std::shared_ptr<const TextureImage> image = decode_texture(encoded, image_limits, &error);
  if (!image) {
    if (error.kind == TextureError::Kind::unreadable) return refuse(error.message);
    std::string detail = error.message;
    if (image_limits.max_pixels < limits.texture.max_pixels) {
      detail += " (the request's images may decode to at most " + bytes_text(limits.max_texture_decoded_bytes) +
                " in all, mip chains included, and earlier images take " + bytes_text(images.decoded_bytes) + ")";
    }
    throw_too_large(pointer, detail);
  }
  images.decoded_bytes += size_t(image->width()) * size_t(image->height()) * decoded_bytes_per_pixel;
  images.by_image[uri] = TextureImages::Entry{image, ""};
  return image;
}

// A stored image by id. Its decoded pixels count against the request's budget like an inline
// image's; it was checked against the per-image caps when it was stored.
std::shared_ptr<const TextureImage> resolve_image(const std::string& id, const std::string& pointer, const Bounds& b) {
  TextureImages& images = *b.images;
  const ParseLimits& limits = b.limits;
  std::shared_ptr<const TextureImage> image = limits.resolve_texture ? limits.resolve_texture(id) : nullptr;
  if (!image) {  // remembered, so another surface naming it is told the same without asking again
    const std::string problem = "there is no stored image \"" + id + "\"";
    images.by_image[id] = TextureImages::Entry{nullptr, problem};
    throw_invalid(pointer, problem);
  }
  const size_t bytes = size_t(image->width()) * size_t(image->height()) * decoded_bytes_per_pixel;
  if (images.decoded_bytes + bytes > limits.max_texture_decoded_bytes) {
    throw_too_large(pointer,
                    "the stored image " + id + " decodes to " + bytes_text(bytes) +
                        "; the request's images may decode to at most " + bytes_text(limits.max_texture_decoded_bytes) +
                        " in all, mip chains included, and earlier images take " + bytes_text(images.decoded_bytes));
  }
  images.decoded_bytes += bytes;
  images.by_image[id] = TextureImages::Entry{image, ""};
  return image;
}

std::shared_ptr<const TextureImage> read_image(const json& value, const std::string& pointer, const Bounds& b) {
  if (!value.is_string()) {
    throw_invalid(pointer, "must be a string: a data: URI of a PNG or JPEG image, or a stored image's id");
  }
  const std::string& text = value.get_ref<const std::string&>();
  if (!b.images) throw_invalid(pointer, "textures are not read here");
  if (auto it = b.images->by_image.find(text); it != b.images->by_image.end()) {
    if (!it->second.image) throw_invalid(pointer, it->second.problem);
    return it->second.image;
  }
  if (text.starts_with("data:")) return decode_image(text, pointer, b);
  if (is_image_id(text)) return resolve_image(text, pointer, b);
  throw_invalid(pointer,
                "must be a data: URI (\"data:image/png;base64,...\") of a PNG or JPEG image or the 16-hex-digit id "
                "of a stored image (POST /v1/textures), not \"" +
                    quote_input(text) + "\"");
}

std::shared_ptr<const SurfaceTexture> read_texture_object(const json& value, const std::string& pointer,
                                                          const Bounds& b) {
  ObjectReader r(value, pointer, b.errors, {"image", "width", "height", "x_offset", "y_offset", "angle"});
  auto texture = std::make_shared<SurfaceTexture>();
  b.errors.attempt([&] {
    const json& image = r.require("image");
    texture->decoded = read_image(image, r.at("image"), b);
    texture->image = image.get<std::string>();
  });
  texture->width = r.number("width", 1.0, b.length);
  texture->height = r.number("height", 1.0, b.length);
  texture->x_offset = r.number("x_offset", 0.0, b.coordinate);
  texture->y_offset = r.number("y_offset", 0.0, b.coordinate);
  texture->angle = r.number("angle", 0.0, NumberRange{}) * (std::numbers::pi / 180.0);
  if (!texture->decoded) return nullptr;  // "never null once read": a refused image leaves no texture
  return texture;
}

}  // namespace

std::shared_ptr<const SurfaceTexture> read_texture(const ObjectReader& owner, std::string_view key, const Bounds& b) {
  std::shared_ptr<const SurfaceTexture> out;
  owner.member(key,
               [&](const json& value, const std::string& pointer) { out = read_texture_object(value, pointer, b); });
  return out;
}

Color read_surface_color(const ObjectReader& owner, std::string_view key, std::string_view texture_key,
                         Color fallback) {
  return owner.color(key, owner.find(texture_key) ? textured_default_color : fallback);
}

}  // namespace rr
