// TEMPORARY: stands in for texture.hpp's decoding until its implementation lands, so the request
// format can be linked and tested; drop this file at that merge. decode_data_uri is real (base64);
// decode_texture reads only the PNG (IHDR) or JPEG (SOF) header, applies the limits and returns a
// 1 x 1 grey level whose content id is the hash of the encoded bytes.
#include "render/core/hash.hpp"
#include "render/core/texture.hpp"

#include <algorithm>
#include <cstring>

namespace rr {

namespace {

int base64_value(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
}

uint32_t big_endian(std::span<const uint8_t> b, size_t at, int n) {
  uint32_t v = 0;
  for (int k = 0; k < n; ++k) v = (v << 8) | b[at + size_t(k)];
  return v;
}

// The size a PNG or JPEG header states; false when neither is recognised.
bool header_size(std::span<const uint8_t> b, uint32_t& w, uint32_t& h) {
  static const uint8_t png[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (b.size() >= 24 && std::memcmp(b.data(), png, 8) == 0 && std::memcmp(b.data() + 12, "IHDR", 4) == 0) {
    w = big_endian(b, 16, 4), h = big_endian(b, 20, 4);
    return true;
  }
  if (b.size() < 4 || b[0] != 0xFF || b[1] != 0xD8) return false;
  for (size_t at = 2; at + 9 < b.size();) {
    if (b[at] != 0xFF) return false;
    const uint8_t marker = b[at + 1];
    const bool sof = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (sof) {
      h = big_endian(b, at + 5, 2), w = big_endian(b, at + 7, 2);
      return true;
    }
    at += 2 + big_endian(b, at + 2, 2);
  }
  return false;
}

}  // namespace

size_t TextureImage::bytes() const {
  size_t out = 0;
  for (const MipLevel& level : levels) out += level.rgb.size();
  return out;
}

bool decode_data_uri(std::string_view uri, size_t max_bytes, std::vector<uint8_t>& bytes, std::string* error) {
  const size_t comma = uri.find(',');
  if (!uri.starts_with("data:") || comma == std::string_view::npos || !uri.substr(0, comma).ends_with(";base64")) {
    *error = "must be a data: URI with base64 content (\"data:image/png;base64,...\")";
    return false;
  }
  std::string_view payload = uri.substr(comma + 1);
  if (payload.size() / 4 * 3 > max_bytes + 2) {
    *error = "holds more than " + std::to_string(max_bytes) + " bytes";
    return false;
  }
  bytes.clear();
  uint32_t acc = 0;
  int bits = 0;
  size_t k = 0;
  for (; k < payload.size() && payload[k] != '='; ++k) {
    const int v = base64_value(payload[k]);
    if (v < 0) {
      *error = "is not valid base64 at character " + std::to_string(k);
      return false;
    }
    acc = (acc << 6) | uint32_t(v), bits += 6;
    if (bits >= 8) bits -= 8, bytes.push_back(uint8_t(acc >> bits));
  }
  for (; k < payload.size(); ++k) {
    if (payload[k] != '=') {
      *error = "is not valid base64 at character " + std::to_string(k);
      return false;
    }
  }
  if (bytes.size() > max_bytes) {
    *error = "holds more than " + std::to_string(max_bytes) + " bytes";
    return false;
  }
  return true;
}

std::shared_ptr<const TextureImage> decode_texture(std::span<const uint8_t> encoded, const TextureLimits& limits,
                                                   TextureError* error) {
  uint32_t w = 0, h = 0;
  if (!header_size(encoded, w, h) || w == 0 || h == 0) {
    *error = {TextureError::Kind::unreadable, "is neither a PNG nor a JPEG image"};
    return nullptr;
  }
  if (w > uint32_t(limits.max_side) || h > uint32_t(limits.max_side) || size_t(w) * h > limits.max_pixels) {
    *error = {TextureError::Kind::too_large, "the image header says " + std::to_string(w) + " x " + std::to_string(h) +
                                                 " pixels; at most " + std::to_string(limits.max_side) +
                                                 " per side and " + std::to_string(limits.max_pixels) +
                                                 " in all are allowed"};
    return nullptr;
  }
  auto image = std::make_shared<TextureImage>();
  image->levels.push_back(MipLevel{1, 1, {128, 128, 128}});
  Fnv1a hash;
  hash.add_bytes(std::string_view(reinterpret_cast<const char*>(encoded.data()), encoded.size()));
  image->content_id = hex64(hash.value());
  return image;
}

}  // namespace rr
