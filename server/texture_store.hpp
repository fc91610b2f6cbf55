// Stored images: the encoded bytes of a PNG or JPEG as they were sent (in a DocumentStore), its id
// hash_hex of those bytes, which is the decoder's TextureImage::content_id, so one image is one
// document however often it is sent and a texture naming it by id draws what its data: URI draws.
// The decoded image with its mip chain is a StoredTexture, kept in the prepared cache
// (prepared_cache.hpp) and decoded again from the bytes when evicted. TexturePins records which
// stored scenes name which stored images: an image is pinned (neither deleted nor expired) while a
// stored scene's texture names it.
#pragma once

#include "render/core/texture.hpp"
#include "render/scene_io/scene_json.hpp"
#include "server/content_store.hpp"
#include "server/mesh_store.hpp"  // MeshPins

#include <memory>
#include <string>
#include <string_view>

namespace rr::server {

struct StoredTexture {
  static constexpr const char* kind = "texture";  // in answers, log events and file or table names
  static constexpr const char* plural = "textures";
  std::string id;    // image->content_id: hash_hex(text)
  std::string text;  // the encoded PNG or JPEG bytes, served byte for byte
  size_t bytes = 0;  // what it costs in memory (bytes, decoded levels): charged against the prepared cache
  std::shared_ptr<const TextureImage> image;
};

// Encoded bytes -> a StoredTexture, decoded with the limits' caps (the same as an inline image's:
// max_texture_image_bytes, then TextureLimits from the header). Throws InputError at pointer "":
// too_large (413) over a cap, invalid (422) for what is not a readable PNG or JPEG.
std::shared_ptr<const StoredTexture> read_stored_texture(const std::string& bytes, const ParseLimits& limits);
// What a store keeps of an image.
StoredDocument texture_document(const StoredTexture& texture);
// A stored image file's bytes -> its document (start-up), not decoded: only its hash names it, and
// the prepared cache decodes it when a texture first uses it.
StoredDocument read_texture_document(const std::string& bytes);
// "image/png" or "image/jpeg", from the first bytes (as the decoder tells them apart).
std::string_view texture_media_type(std::string_view bytes);

using TextureStoreConfig = ContentStoreConfig<StoredTexture>;
using TextureStore = ContentStore<StoredTexture>;       // the embedded store
using TextureDocuments = DocumentStore<StoredTexture>;  // either store, as the handlers see it
// Which stored scenes name which stored images: the same bookkeeping as MeshPins.
using TexturePins = MeshPins;

}  // namespace rr::server
