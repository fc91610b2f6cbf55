// StoredTexture and its documents (texture_store.hpp); the stores themselves are content_store.cpp
// and postgres_store.cpp.
#include "server/texture_store.hpp"

#include "render/core/hash.hpp"
#include "render/scene_io/errors.hpp"

#include <span>

namespace rr::server {

std::shared_ptr<const StoredTexture> read_stored_texture(const std::string& bytes, const ParseLimits& limits) {
  if (bytes.size() > limits.max_texture_image_bytes) {
    throw InputError(InputError::Kind::too_large, "",
                     "the image holds " + std::to_string(bytes.size()) + " bytes; at most " +
                         std::to_string(limits.max_texture_image_bytes) + " bytes are allowed per image");
  }
  TextureError error;
  std::shared_ptr<const TextureImage> image =
      decode_texture(std::span(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()), limits.texture, &error);
  if (!image) {
    throw InputError(
        error.kind == TextureError::Kind::too_large ? InputError::Kind::too_large : InputError::Kind::invalid, "",
        error.message);
  }
  auto out = std::make_shared<StoredTexture>();
  out->id = image->content_id;
  out->text = bytes;
  out->bytes = sizeof(StoredTexture) + bytes.size() + image->bytes();
  out->image = std::move(image);
  return out;
}

StoredDocument texture_document(const StoredTexture& texture) { return {texture.id, texture.text, {}, {}}; }

StoredDocument read_texture_document(const std::string& bytes) { return {hash_hex(bytes), bytes, {}, {}}; }

std::string_view texture_media_type(std::string_view bytes) {
  return bytes.starts_with("\x89PNG") ? "image/png" : "image/jpeg";
}

}  // namespace rr::server
