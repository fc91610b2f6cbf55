// Encoded bytes -> images: PNG or JPEG -> TextureImage (RGB8 level 0 and its mip chain), `data:` URIs
// -> bytes, and decode_png's decoder (image_decode.hpp). PNG is read by libpng, JPEG by libjpeg-turbo's
// TurboJPEG API: both fuzzed for years upstream, where Debian's stb_image wrote past a Huffman table
// and passed a null pointer to memcpy on inputs libFuzzer found in seconds (docs/textures.md). Limits
// are checked on the header before any pixel is decoded.
#include "render/core/hash.hpp"
#include "render/core/image_decode.hpp"
#include "render/core/texture.hpp"

#include <png.h>
#include <turbojpeg.h>

#include <algorithm>
#include <cassert>
#include <climits>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <utility>

namespace rr {
namespace {

bool is_jpeg(std::span<const uint8_t> bytes) { return bytes.size() >= 2 && bytes[0] == 0xFF && bytes[1] == 0xD8; }

// Sides beyond this are refused from a PNG's header, also by decode_png, which has no other limit:
// twice the largest render side (65536, --max-image-side), so it still reads every image a render
// writes.
constexpr uint32_t max_png_side = 1u << 17;
// Ancillary chunks (text, ICC profiles) are never used; none may make libpng allocate more than this.
constexpr png_alloc_size_t max_png_chunk_bytes = 8u << 20;

struct PngInput {
  const uint8_t* data;
  size_t size;
  size_t at;
};

void png_read_bytes(png_structp png, png_bytep out, size_t n) {
  auto* in = static_cast<PngInput*>(png_get_io_ptr(png));
  if (n > in->size - in->at) png_error(png, "truncated");
  std::memcpy(out, in->data + in->at, n);
  in->at += n;
}

void png_on_error(png_structp png, png_const_charp message) {
  static_cast<std::string*>(png_get_error_ptr(png))->assign(message);
  png_longjmp(png, 1);
}

void png_on_warning(png_structp, png_const_charp) {}

// One libpng read, destroyed on every path.
struct PngReader {
  png_structp png = nullptr;
  png_infop info = nullptr;
  PngReader() = default;
  PngReader(const PngReader&) = delete;
  PngReader& operator=(const PngReader&) = delete;
  ~PngReader() { png_destroy_read_struct(&png, info ? &info : nullptr, nullptr); }
};

// The header's size (`image` null) or the whole image as RGB8: 16-bit samples keep their high byte,
// palettes and grey are expanded, alpha (and tRNS) is dropped, gamma and other colour chunks are
// ignored (a texel is the file's 8-bit value). libpng reports errors by longjmp back here, so every
// object with a destructor is made before setjmp and nothing the error path reads changes after it.
bool read_png(std::span<const uint8_t> bytes, Image* image, int* width, int* height, std::string* failure) {
  PngReader reader;
  PngInput input{bytes.data(), bytes.size(), 0};
  std::vector<uint8_t> rgb;
  std::vector<png_bytep> rows;
  reader.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, failure, png_on_error, png_on_warning);
  if (reader.png) reader.info = png_create_info_struct(reader.png);
  if (!reader.png || !reader.info) {
    *failure = "cannot start the PNG decoder";
    return false;
  }
  if (setjmp(png_jmpbuf(reader.png))) return false;
  png_set_read_fn(reader.png, &input, png_read_bytes);
  png_set_user_limits(reader.png, max_png_side, max_png_side);
  png_set_chunk_malloc_max(reader.png, max_png_chunk_bytes);
  png_read_info(reader.png, reader.info);
  const png_uint_32 w = png_get_image_width(reader.png, reader.info);
  const png_uint_32 h = png_get_image_height(reader.png, reader.info);
  *width = int(w);
  *height = int(h);
  if (!image) return true;
  const int colour = png_get_color_type(reader.png, reader.info);
  png_set_strip_16(reader.png);
  png_set_expand(reader.png);  // palette -> RGB, grey under 8 bits -> 8, tRNS -> alpha
  png_set_strip_alpha(reader.png);
  if (colour == PNG_COLOR_TYPE_GRAY || colour == PNG_COLOR_TYPE_GRAY_ALPHA) png_set_gray_to_rgb(reader.png);
  png_set_interlace_handling(reader.png);
  png_read_update_info(reader.png, reader.info);
  if (png_get_rowbytes(reader.png, reader.info) != size_t(w) * 3) png_error(reader.png, "unexpected row layout");
  rgb.resize(size_t(w) * size_t(h) * 3);
  rows.resize(h);
  for (png_uint_32 y = 0; y < h; ++y) rows[y] = rgb.data() + size_t(y) * size_t(w) * 3;
  png_read_image(reader.png, rows.data());
  image->width = int(w);
  image->height = int(h);
  image->rgb = std::move(rgb);
  return true;
}

// One TurboJPEG decompressor, destroyed on every path.
struct JpegDecoder {
  tjhandle handle = tjInitDecompress();
  JpegDecoder() = default;
  JpegDecoder(const JpegDecoder&) = delete;
  JpegDecoder& operator=(const JpegDecoder&) = delete;
  ~JpegDecoder() {
    if (handle) tjDestroy(handle);
  }
  std::string reason() const { return handle ? tjGetErrorStr2(handle) : "cannot start the JPEG decoder"; }
};

// TurboJPEG counts bytes in unsigned long; the header gives the size and colour space. A file that
// ends before its frame header is "read" with only a warning (premature end) and no size: refused.
bool read_jpeg_header(JpegDecoder& decoder, std::span<const uint8_t> bytes, int* width, int* height) {
  int subsampling = 0, colorspace = 0, w = 0, h = 0;
  if (!decoder.handle || bytes.size() > ULONG_MAX ||
      tjDecompressHeader3(decoder.handle, bytes.data(), static_cast<unsigned long>(bytes.size()), &w, &h, &subsampling,
                          &colorspace) != 0 ||
      w <= 0 || h <= 0) {
    return false;
  }
  *width = w, *height = h;
  return true;
}

// The accurate integer IDCT and smooth chroma upsampling (TurboJPEG's defaults), whose SIMD paths
// give the C code's bytes, so a texel depends on the file alone. A warning (corrupt or missing data,
// which libjpeg would fill with grey) is a refusal, and so is a progressive file of more than 500
// scans (TJFLAG_LIMITSCANS: a few bytes that would cost minutes of decoding).
bool decode_jpeg(std::span<const uint8_t> bytes, Image& image, std::string* failure) {
  JpegDecoder decoder;
  int w = 0, h = 0;
  if (!read_jpeg_header(decoder, bytes, &w, &h)) {
    *failure = decoder.reason();
    return false;
  }
  std::vector<uint8_t> rgb(size_t(w) * size_t(h) * 3);
  if (tjDecompress2(decoder.handle, bytes.data(), static_cast<unsigned long>(bytes.size()), rgb.data(), w, w * 3, h,
                    TJPF_RGB, TJFLAG_STOPONWARNING | TJFLAG_LIMITSCANS) != 0) {
    *failure = decoder.reason();
    return false;
  }
  image.width = w;
  image.height = h;
  image.rgb = std::move(rgb);
  return true;
}

}  // namespace

bool decode_rgb8(std::span<const uint8_t> encoded, Image& image, std::string* failure) {
  int w = 0, h = 0;
  return is_jpeg(encoded) ? decode_jpeg(encoded, image, failure) : read_png(encoded, &image, &w, &h, failure);
}

namespace {

// The header's size, or the decoder's reason for refusing it.
bool read_image_size(std::span<const uint8_t> encoded, int* width, int* height, std::string* reason) {
  if (!is_jpeg(encoded)) return read_png(encoded, nullptr, width, height, reason);
  JpegDecoder decoder;
  if (read_jpeg_header(decoder, encoded, width, height)) return true;
  *reason = decoder.reason();
  return false;
}

// A PNG's size from the fixed offsets of its IHDR (signature, length, "IHDR", width, height), for
// naming the size of one libpng refused (a side over max_png_side).
std::optional<std::pair<uint32_t, uint32_t>> png_ihdr_size(std::span<const uint8_t> png) {
  if (png.size() < 24 || !std::equal(png.begin() + 12, png.begin() + 16, "IHDR")) return std::nullopt;
  auto u32 = [&](size_t at) {
    return uint32_t(png[at]) << 24 | uint32_t(png[at + 1]) << 16 | uint32_t(png[at + 2]) << 8 | png[at + 3];
  };
  return std::pair{u32(16), u32(20)};
}

enum class Format { png, jpeg };
const char* format_name(Format f) { return f == Format::png ? "PNG" : "JPEG"; }

std::optional<Format> sniff(std::span<const uint8_t> bytes) {
  static constexpr uint8_t png[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  static constexpr uint8_t jpeg[3] = {0xFF, 0xD8, 0xFF};
  if (bytes.size() >= 8 && std::equal(png, png + 8, bytes.begin())) return Format::png;
  if (bytes.size() >= 3 && std::equal(jpeg, jpeg + 3, bytes.begin())) return Format::jpeg;
  return std::nullopt;
}

bool starts_with(std::span<const uint8_t> bytes, std::string_view prefix, size_t at = 0) {
  return bytes.size() >= at + prefix.size() && std::equal(prefix.begin(), prefix.end(), bytes.begin() + ptrdiff_t(at),
                                                          [](char a, uint8_t b) { return uint8_t(a) == b; });
}

// What an unsupported file looks like: a format people often try by name, else its first bytes in hex.
std::string describe_start(std::span<const uint8_t> bytes) {
  if (bytes.empty()) return "no bytes";
  std::string seen;
  if (starts_with(bytes, "GIF8")) seen = "a GIF";
  if (starts_with(bytes, "BM")) seen = "a BMP";
  if (starts_with(bytes, "RIFF") && starts_with(bytes, "WEBP", 8)) seen = "a WebP";
  if (starts_with(bytes, "<")) seen = "text (SVG or HTML?)";
  std::string hex;
  for (size_t i = 0; i < std::min<size_t>(bytes.size(), 8); ++i) {
    char b[4];
    std::snprintf(b, sizeof b, i ? " %02x" : "%02x", bytes[i]);
    hex += b;
  }
  return (seen.empty() ? "" : seen + ", ") + "starting " + hex;
}

// The source texels under destination texel d of one axis of a level, as integer numerators over
// `denominator`. Each destination texel is the exact box filter of its footprint: an even side
// averages pairs; an odd side n = 2m + 1 (m > 0) maps m texels onto n, so texel d covers 2 + 1/m
// source texels, 2d partly (m - d), 2d + 1 fully (m), 2d + 2 partly (d + 1), all over n. A side of 1
// stays 1.
struct AxisTaps {
  int first = 0, count = 0;
  uint64_t weight[3] = {0, 0, 0};
};

std::vector<AxisTaps> axis_taps(int n, uint64_t* denominator) {
  const int m = std::max(1, n / 2);
  std::vector<AxisTaps> taps(static_cast<size_t>(m));
  *denominator = n == 1 ? 1 : n % 2 == 0 ? 2 : uint64_t(n);
  for (int d = 0; d < m; ++d) {
    AxisTaps& t = taps[size_t(d)];
    t.first = n == 1 ? 0 : 2 * d;
    if (n == 1) {
      t.count = 1, t.weight[0] = 1;
    } else if (n % 2 == 0) {
      t.count = 2, t.weight[0] = t.weight[1] = 1;
    } else {
      t.count = 3, t.weight[0] = uint64_t(m - d), t.weight[1] = uint64_t(m), t.weight[2] = uint64_t(d + 1);
    }
  }
  return taps;
}

// The next mip level. Integer sums rounded to nearest (ties up), so the chain is exact and the same
// everywhere.
MipLevel halve(const MipLevel& src) {
  uint64_t dx = 1, dy = 1;
  const std::vector<AxisTaps> tx = axis_taps(src.width, &dx), ty = axis_taps(src.height, &dy);
  const uint64_t denominator = dx * dy;
  MipLevel dst;
  dst.width = int(tx.size());
  dst.height = int(ty.size());
  dst.rgb.resize(size_t(dst.width) * size_t(dst.height) * 3);
  uint8_t* out = dst.rgb.data();
  for (const AxisTaps& y : ty) {
    for (const AxisTaps& x : tx) {
      uint64_t sum[3] = {0, 0, 0};
      for (int j = 0; j < y.count; ++j) {
        const uint8_t* row = src.rgb.data() + size_t(y.first + j) * size_t(src.width) * 3;
        for (int i = 0; i < x.count; ++i) {
          const uint8_t* texel = row + size_t(x.first + i) * 3;
          const uint64_t w = y.weight[j] * x.weight[i];
          for (int c = 0; c < 3; ++c) sum[c] += w * texel[c];
        }
      }
      for (int c = 0; c < 3; ++c) *out++ = uint8_t((2 * sum[c] + denominator) / (2 * denominator));
    }
  }
  return dst;
}

}  // namespace

size_t TextureImage::bytes() const {
  size_t total = levels.capacity() * sizeof(MipLevel);
  for (const MipLevel& level : levels) total += level.rgb.capacity();
  return total;
}

bool read_texture_header(std::span<const uint8_t> encoded, const TextureLimits& limits, int* width_out, int* height_out,
                         TextureError* error) {
  auto refuse = [&](TextureError::Kind kind, std::string message) {
    if (error) *error = {kind, std::move(message)};
    return false;
  };
  const std::optional<Format> format = sniff(encoded);
  if (!format) {
    return refuse(TextureError::Kind::unreadable, "not a PNG or JPEG image: " + describe_start(encoded));
  }
  const std::string name = format_name(*format);
  const std::string allowed = "textures may be at most " + std::to_string(limits.max_side) + " pixels a side and " +
                              std::to_string(limits.max_pixels) + " pixels in all";
  int w = 0, h = 0;
  std::string reason;
  const bool header_read = read_image_size(encoded, &w, &h, &reason);
  uint64_t width = uint64_t(w), height = uint64_t(h);
  if (!header_read) {
    // libpng refuses a side over max_png_side; the IHDR still names the size. A JPEG's sides fit 16
    // bits, and TurboJPEG reads them from any header it can parse.
    const auto ihdr = *format == Format::png ? png_ihdr_size(encoded) : std::nullopt;
    if (!ihdr) {
      return refuse(TextureError::Kind::unreadable,
                    name + " header unreadable (" + (reason.empty() ? "truncated or corrupt" : reason) + ")");
    }
    width = ihdr->first, height = ihdr->second;
  }
  if (width > uint64_t(limits.max_side) || height > uint64_t(limits.max_side) || width * height > limits.max_pixels) {
    return refuse(TextureError::Kind::too_large, name + " header says " + std::to_string(width) + " x " +
                                                     std::to_string(height) + " pixels; " + allowed);
  }
  if (!header_read) {
    return refuse(TextureError::Kind::unreadable,
                  name + " header unreadable (" + (reason.empty() ? "corrupt or unsupported" : reason) + ")");
  }
  if (width_out) *width_out = w;
  if (height_out) *height_out = h;
  return true;
}

std::shared_ptr<const TextureImage> decode_texture(std::span<const uint8_t> encoded, const TextureLimits& limits,
                                                   TextureError* error) {
  int w = 0, h = 0;
  if (!read_texture_header(encoded, limits, &w, &h, error)) return nullptr;
  // Decoded to RGB: an alpha channel is dropped (a texture colours an opaque surface), grey is expanded.
  Image decoded;
  std::string failure;
  if (!decode_rgb8(encoded, decoded, &failure)) {
    const std::string name = format_name(*sniff(encoded));
    if (error) *error = {TextureError::Kind::unreadable, name + " data unreadable: " + failure};
    return nullptr;
  }
  assert(decoded.width == w && decoded.height == h);

  auto image = std::make_shared<TextureImage>();
  image->content_id = hex64(fnv1a({reinterpret_cast<const char*>(encoded.data()), encoded.size()}));
  image->levels.push_back({decoded.width, decoded.height, std::move(decoded.rgb)});
  while (image->levels.back().width > 1 || image->levels.back().height > 1) {
    MipLevel next = halve(image->levels.back());
    image->levels.push_back(std::move(next));
  }
  return image;
}

namespace {

int base64_value(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
}

bool equals_ignoring_case(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return (x >= 'A' && x <= 'Z' ? char(x - 'A' + 'a') : x) == (y >= 'A' && y <= 'Z' ? char(y - 'A' + 'a') : y);
         });
}

}  // namespace

// Strict RFC 4648 base64: the standard alphabet, no whitespace or line breaks, '=' only as the last one
// or two characters of a padded payload (padding is optional). Bits left over after the last byte are
// ignored, as every browser does.
bool decode_data_uri(std::string_view uri, size_t max_bytes, std::vector<uint8_t>& bytes, std::string* error) {
  bytes.clear();
  auto refuse = [&](std::string message) {
    bytes.clear();
    if (error) *error = std::move(message);
    return false;
  };
  constexpr std::string_view scheme = "data:", marker = ";base64";
  if (uri.size() < scheme.size() || !equals_ignoring_case(uri.substr(0, scheme.size()), scheme)) {
    return refuse("not a data: URI (expected \"data:<media type>;base64,<base64>\")");
  }
  const size_t comma = uri.find(',');
  if (comma == std::string_view::npos) return refuse("data: URI without the comma that starts its payload");
  const std::string_view header = uri.substr(scheme.size(), comma - scheme.size());
  if (header.size() < marker.size() || !equals_ignoring_case(header.substr(header.size() - marker.size()), marker)) {
    return refuse("data: URI is not base64: \";base64,\" must end its media type (\"data:image/png;base64,...\")");
  }
  const std::string_view payload = uri.substr(comma + 1);
  size_t padding = 0;
  while (padding < 2 && padding < payload.size() && payload[payload.size() - 1 - padding] == '=') ++padding;
  const std::string_view digits = payload.substr(0, payload.size() - padding);
  const size_t length = digits.size() / 4 * 3 + (digits.size() % 4 == 0 ? 0 : digits.size() % 4 - 1);
  if (length > max_bytes) {
    return refuse("data: URI holds " + std::to_string(length) + " bytes; at most " + std::to_string(max_bytes) +
                  " are allowed");
  }
  bytes.reserve(length);
  uint32_t bits = 0;
  int bit_count = 0;
  for (size_t i = 0; i < digits.size(); ++i) {
    const int value = base64_value(digits[i]);
    if (value < 0) {
      const char c = digits[i];
      const std::string what = c == ' ' || c == '\t' || c == '\r' || c == '\n' ? "whitespace"
                               : c == '='                                      ? "'=' before the end"
                               : c > ' ' && c < 127                            ? std::string("'") + c + "'"
                                                    : "byte " + std::to_string(int(uint8_t(c)));
      return refuse("base64 payload has " + what + " at offset " + std::to_string(i) +
                    ": only A-Z a-z 0-9 + / and final '=' padding are allowed");
    }
    bits = (bits << 6) | uint32_t(value);
    bit_count += 6;
    if (bit_count >= 8) {
      bit_count -= 8;
      bytes.push_back(uint8_t(bits >> bit_count));
      bits &= (1u << bit_count) - 1;
    }
  }
  // After the characters, so that a stray one is named rather than the length it spoils.
  if (padding > 0 && payload.size() % 4 != 0) {
    return refuse("base64 payload of " + std::to_string(payload.size()) +
                  " characters is padded with '=' but is not a multiple of 4 long");
  }
  if (digits.size() % 4 == 1) {
    return refuse("base64 payload of " + std::to_string(digits.size()) + " digits is truncated (4k + 1 digits)");
  }
  assert(bytes.size() == length);
  return true;
}

}  // namespace rr
