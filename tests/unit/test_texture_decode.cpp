// Texture decoding (render/core/texture.hpp): PNG and JPEG decode to their exact texels, limits refuse
// a header before any decoding, bad bytes are refused with a reason, the mip chain is the exact box
// filter (checked against a slow interval-overlap reference), and data: URIs.
#include "render/core/hash.hpp"
#include "render/core/image.hpp"
#include "render/core/texture.hpp"
#include "support/image_bytes.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <zlib.h>

#include <filesystem>
#include <random>

namespace rr {
namespace texture_decode_tests {
namespace {

using testing::as_bytes;
using testing::decode_ok;
using testing::random_image;
using testing::texture_of;

// A grey 16 x 8 JPEG (cjpeg -quality 100 -grayscale): the left 8 x 8 block 64, the right one 192.
const uint8_t grey_jpeg[] = {
    0xff, 0xd8, 0xff, 0xe0, 0x00, 0x10, 0x4a, 0x46, 0x49, 0x46, 0x00, 0x01, 0x01, 0x00, 0x00, 0x01, 0x00, 0x01, 0x00,
    0x00, 0xff, 0xdb, 0x00, 0x43, 0x00, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01,
    0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01,
    0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01,
    0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0xff, 0xc0, 0x00, 0x0b, 0x08, 0x00,
    0x08, 0x00, 0x10, 0x01, 0x01, 0x11, 0x00, 0xff, 0xc4, 0x00, 0x15, 0x00, 0x01, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00,
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x0a, 0x0b, 0xff, 0xc4, 0x00, 0x14, 0x10, 0x01, 0x00, 0x00,
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xff, 0xda, 0x00, 0x08, 0x01,
    0x01, 0x00, 0x00, 0x3f, 0x00, 0x3f, 0xea, 0x00, 0x3f, 0xff, 0xd9,
};
// An RGB 16 x 8 JPEG (cjpeg -quality 100 -sample 1x1): the left block (200, 40, 40), the right one
// (40, 80, 220).
const uint8_t colour_jpeg[] = {
    0xff, 0xd8, 0xff, 0xe0, 0x00, 0x10, 0x4a, 0x46, 0x49, 0x46, 0x00, 0x01, 0x01, 0x00, 0x00, 0x01, 0x00, 0x01, 0x00,
    0x00, 0xff, 0xdb, 0x00, 0x43, 0x00, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01,
    0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01,
    0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01,
    0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0xff, 0xdb, 0x00, 0x43, 0x01, 0x01,
    0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01,
    0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01,
    0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01,
    0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0xff, 0xc0, 0x00, 0x11, 0x08, 0x00, 0x08, 0x00, 0x10, 0x03, 0x01, 0x11, 0x00,
    0x02, 0x11, 0x01, 0x03, 0x11, 0x01, 0xff, 0xc4, 0x00, 0x15, 0x00, 0x01, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x06, 0x09, 0xff, 0xc4, 0x00, 0x14, 0x10, 0x01, 0x00, 0x00, 0x00,
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xff, 0xc4, 0x00, 0x15, 0x01, 0x01,
    0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x0a, 0x08, 0xff, 0xc4,
    0x00, 0x14, 0x11, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
    0x00, 0xff, 0xda, 0x00, 0x0c, 0x03, 0x01, 0x00, 0x02, 0x11, 0x03, 0x11, 0x00, 0x3f, 0x00, 0x97, 0xe8, 0x9c, 0xa0,
    0x07, 0xcd, 0x00, 0x21, 0xdf, 0xff, 0xd9,
};

TextureError refusal(std::span<const uint8_t> bytes, const TextureLimits& limits = {}) {
  TextureError error;
  error.message = "(not refused)";
  EXPECT_FALSE(decode_texture(bytes, limits, &error));
  return error;
}

// A complete RGBA PNG, rows unfiltered.
std::string rgba_png(uint32_t w, uint32_t h, const std::vector<uint8_t>& rgba) {
  std::string raw;
  for (uint32_t y = 0; y < h; ++y) {
    raw.push_back(0);
    raw.append(reinterpret_cast<const char*>(rgba.data()) + size_t(y) * w * 4, size_t(w) * 4);
  }
  std::string idat(compressBound(uLong(raw.size())), '\0');
  uLongf size = uLongf(idat.size());
  EXPECT_EQ(compress(reinterpret_cast<Bytef*>(idat.data()), &size, reinterpret_cast<const Bytef*>(raw.data()),
                     uLong(raw.size())),
            Z_OK);
  idat.resize(size);
  return testing::png_head(w, h, 6) + testing::png_chunk("IDAT", idat) + testing::png_chunk("IEND", "");
}

TEST(TextureDecode, PngGivesItsExactTexelsAndContentId) {
  const Image image = random_image(5, 3, 11);
  const std::string png = encode_png(image);
  auto texture = decode_ok(as_bytes(png));
  ASSERT_TRUE(texture);
  EXPECT_EQ(texture->width(), 5);
  EXPECT_EQ(texture->height(), 3);
  EXPECT_EQ(texture->levels[0].rgb, image.rgb);
  EXPECT_EQ(texture->content_id, hash_hex(png));
  EXPECT_EQ(texture->content_id.size(), 16u);
  size_t texel_bytes = 0;
  for (const MipLevel& level : texture->levels) texel_bytes += level.rgb.size();
  EXPECT_GE(texture->bytes(), texel_bytes);
  EXPECT_NE(decode_ok(as_bytes(encode_png(random_image(5, 3, 12))))->content_id, texture->content_id);
}

TEST(TextureDecode, PngAlphaIsDroppedNotApplied) {
  // Alpha 0 and 128 must leave the colour alone: no premultiplication, no compositing on a background.
  const std::vector<uint8_t> rgba = {200, 100, 50, 0, 10, 20, 30, 128};
  auto texture = decode_ok(as_bytes(rgba_png(2, 1, rgba)));
  ASSERT_TRUE(texture);
  EXPECT_EQ(texture->levels[0].rgb, (std::vector<uint8_t>{200, 100, 50, 10, 20, 30}));
}

TEST(TextureDecode, JpegGivesItsTexels) {
  // Flat 8 x 8 blocks at quality 100 keep their DC exactly: grey decodes exactly, RGB within the
  // rounding of the YCbCr conversion (djpeg gives 41 for the 40 of the right block).
  auto grey = decode_ok(grey_jpeg);
  ASSERT_TRUE(grey);
  ASSERT_EQ(grey->width(), 16);
  ASSERT_EQ(grey->height(), 8);
  for (int j = 0; j < 8; ++j) {
    for (int i = 0; i < 16; ++i) {
      const uint8_t v = i < 8 ? 64 : 192;
      const uint8_t* t = grey->levels[0].rgb.data() + (size_t(j) * 16 + size_t(i)) * 3;
      EXPECT_EQ(t[0], v) << i << "," << j;
      EXPECT_EQ(t[1], v) << i << "," << j;
      EXPECT_EQ(t[2], v) << i << "," << j;
    }
  }
  auto colour = decode_ok(colour_jpeg);
  ASSERT_TRUE(colour);
  ASSERT_EQ(colour->width(), 16);
  for (int j = 0; j < 8; ++j) {
    for (int i = 0; i < 16; ++i) {
      const int expected[3] = {i < 8 ? 200 : 40, i < 8 ? 40 : 80, i < 8 ? 40 : 220};
      const uint8_t* t = colour->levels[0].rgb.data() + (size_t(j) * 16 + size_t(i)) * 3;
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(t[c], expected[c], 2) << i << "," << j << " channel " << c;
    }
  }
}

TEST(TextureDecode, SweetHomeJpegsDecodeWithFullChains) {
  const std::optional<std::filesystem::path> data = testing::shared_data_dir();
  const std::filesystem::path dir = data ? *data / "textures" / "sweethome3d" : std::filesystem::path();
  if (!data || !std::filesystem::is_directory(dir)) GTEST_SKIP() << "no textures (../shared/data absent)";
  int decoded = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".jpg") continue;
    const std::string bytes = testing::read_file(entry.path());
    auto texture = decode_ok(as_bytes(bytes));
    ASSERT_TRUE(texture) << entry.path();
    int levels = 1;
    for (int w = texture->width(), h = texture->height(); w > 1 || h > 1;
         w = std::max(1, w / 2), h = std::max(1, h / 2))
      ++levels;
    EXPECT_EQ(int(texture->levels.size()), levels) << entry.path();
    EXPECT_EQ(texture->levels.back().width, 1);
    EXPECT_EQ(texture->levels.back().height, 1);
    ++decoded;
  }
  EXPECT_GT(decoded, 0);
}

TEST(TextureDecode, DecodePngStillRefusesJpeg) {
  // decode_png reads PNGs only.
  EXPECT_THROW(decode_png({reinterpret_cast<const char*>(grey_jpeg), sizeof grey_jpeg}), std::runtime_error);
  const Image image = random_image(4, 3, 5);
  EXPECT_EQ(decode_png(encode_png(image)).rgb, image.rgb);
}

TEST(TextureDecode, HugeHeaderRefusedBeforeDecoding) {
  // IHDR only: there are no pixels, so decoding would be refused as unreadable; too_large shows the
  // header alone decided.
  const std::string head = testing::png_head(100000, 100000, 2);
  TextureError error = refusal(as_bytes(head));
  EXPECT_EQ(error.kind, TextureError::Kind::too_large);
  EXPECT_NE(error.message.find("100000 x 100000"), std::string::npos) << error.message;
  EXPECT_NE(error.message.find("8192"), std::string::npos) << error.message;

  // Within the side limit but over the pixel count; over the PNG decoder's own side bound; over a caller's.
  EXPECT_EQ(refusal(as_bytes(testing::png_head(5000, 5000, 2))).kind, TextureError::Kind::too_large);
  error = refusal(as_bytes(testing::png_head(1000000, 1, 2)));
  EXPECT_EQ(error.kind, TextureError::Kind::too_large) << error.message;
  TextureLimits small;
  small.max_side = 4;
  EXPECT_TRUE(decode_texture(as_bytes(encode_png(random_image(4, 4, 1))), small, nullptr));
  error = refusal(as_bytes(encode_png(random_image(5, 4, 1))), small);
  EXPECT_EQ(error.kind, TextureError::Kind::too_large);
  EXPECT_NE(error.message.find("5 x 4"), std::string::npos) << error.message;
}

// The texture decoder's fuzz seeds and findings.
const std::filesystem::path texture_seeds = std::filesystem::path(ROOMRENDER_SOURCE_DIR) / "fuzz" / "texture_seeds";

// Every prefix of the texture decoder's fuzz seeds (fuzz/texture_seeds: PNGs of three colour types,
// baseline, grey and progressive JPEGs, and the fuzzer's findings), and each with any one byte replaced by its
// complement: each decodes or is refused with a reason, and a decoded image has a whole mip chain (the sanitized run
// checks that no byte outside the input or the image is touched).
TEST(TextureDecode, EveryTruncationAndByteFlipOfTheSeedsDecodesOrIsRefused) {
  std::vector<std::string> seeds;
  for (const auto& entry : std::filesystem::directory_iterator(texture_seeds)) {
    seeds.push_back(testing::read_file(entry.path()));
  }
  ASSERT_GE(seeds.size(), 6u);
  size_t decoded = 0, refused = 0;
  auto check = [&](const std::string& bytes) {
    TextureError error;
    const auto image = decode_texture(as_bytes(bytes), {}, &error);
    if (!image) {
      EXPECT_FALSE(error.message.empty());
      ++refused;
      return;
    }
    EXPECT_GT(image->width() * image->height(), 0);
    EXPECT_EQ(image->levels.back().width * image->levels.back().height, 1);
    ++decoded;
  };
  for (const std::string& seed : seeds) {
    check(seed);
    for (size_t n = 0; n < seed.size(); ++n) check(seed.substr(0, n));
    for (size_t i = 0; i < seed.size(); ++i) {
      std::string flipped = seed;
      flipped[i] = char(~flipped[i]);
      check(flipped);
    }
  }
  EXPECT_GT(refused, seeds.size());  // every empty prefix at least
  EXPECT_GT(decoded, seeds.size());  // every seed, and bytes past the data (a JPEG's tail) are not all checked
}

// A Huffman table whose 16 code counts sum past 256 made Debian's stb_image write past its table,
// after the scan header (found by the test above under UBSan) and, in a file from libFuzzer, before
// the frame header, where reading the size alone wrote past it. Both are refused by their header.
TEST(TextureDecode, HuffmanTableOfMoreThan256CodesIsRefused) {
  const std::string found = testing::read_file(texture_seeds / "dht_259_codes_before_sof.jpg");
  TextureError before_frame = refusal(as_bytes(found));
  EXPECT_EQ(before_frame.kind, TextureError::Kind::unreadable);
  EXPECT_NE(before_frame.message.find("Huffman table"), std::string::npos) << before_frame.message;

  std::string jpeg(reinterpret_cast<const char*>(colour_jpeg), sizeof colour_jpeg);
  const size_t dht = jpeg.find("\xFF\xC4");
  ASSERT_NE(dht, std::string::npos);
  jpeg[dht + 5] = char(200);  // the first table's counts of 1- and 2-bit codes: 400 codes in all
  jpeg[dht + 6] = char(200);
  TextureError error = refusal(as_bytes(jpeg));
  EXPECT_EQ(error.kind, TextureError::Kind::unreadable);
  EXPECT_NE(error.message.find("Huffman table"), std::string::npos) << error.message;
}

// A PNG from libFuzzer on which Debian's stb_image passed a null pointer to memcpy (it skips CRCs and
// read on into a zero-length chunk): libpng refuses it at its IHDR's CRC.
TEST(TextureDecode, PngWithABadHeaderCrcIsRefused) {
  const std::string found = testing::read_file(texture_seeds / "png_ihdr_bad_crc_empty_chunk.png");
  TextureError error = refusal(as_bytes(found));
  EXPECT_EQ(error.kind, TextureError::Kind::unreadable);
  EXPECT_NE(error.message.find("CRC"), std::string::npos) << error.message;
}

TEST(TextureDecode, UnreadableBytesRefused) {
  const std::string png = encode_png(random_image(16, 16, 3));
  TextureError error = refusal(as_bytes(png.substr(0, png.size() / 2)));
  EXPECT_EQ(error.kind, TextureError::Kind::unreadable);
  EXPECT_NE(error.message.find("PNG"), std::string::npos) << error.message;

  error = refusal(std::span<const uint8_t>(grey_jpeg, sizeof grey_jpeg / 2));
  EXPECT_EQ(error.kind, TextureError::Kind::unreadable);
  EXPECT_NE(error.message.find("JPEG"), std::string::npos) << error.message;

  std::string garbage(64, '\0');
  std::mt19937 rng(7);
  for (char& c : garbage) c = char(rng() & 0x7F);  // never 0x89 or 0xFF: no signature by chance
  error = refusal(as_bytes(garbage));
  EXPECT_EQ(error.kind, TextureError::Kind::unreadable);
  EXPECT_NE(error.message.find("not a PNG or JPEG"), std::string::npos) << error.message;

  error = refusal(as_bytes(std::string("\x89PNG\r\n\x1a\n", 8) + garbage));
  EXPECT_EQ(error.kind, TextureError::Kind::unreadable);

  error = refusal(as_bytes(std::string("GIF89a\x01\x00\x01\x00", 10)));
  EXPECT_EQ(error.kind, TextureError::Kind::unreadable);
  EXPECT_NE(error.message.find("GIF"), std::string::npos) << error.message;

  EXPECT_EQ(refusal({}).kind, TextureError::Kind::unreadable);
}

// TurboJPEG "reads" a header that ends before the frame (SOF) with only a warning and no size; such
// a file is refused at its header, naming the premature end, and read_texture_header agrees.
TEST(TextureDecode, JpegEndingBeforeItsFrameHeaderIsRefusedAtTheHeader) {
  const std::string jpeg = testing::read_file(testing::source_dir() / "catalogue/textures/smallBricks.jpg");
  for (size_t cut : {size_t{3}, size_t{20}, size_t{100}}) {
    TextureError error = refusal(as_bytes(jpeg.substr(0, cut)));
    EXPECT_EQ(error.kind, TextureError::Kind::unreadable) << cut;
    EXPECT_NE(error.message.find("JPEG header unreadable"), std::string::npos) << cut << ": " << error.message;
    int w = -1, h = -1;
    EXPECT_FALSE(read_texture_header(as_bytes(jpeg.substr(0, cut)), TextureLimits{}, &w, &h, &error)) << cut;
    EXPECT_EQ(w, -1) << cut;
  }
  int w = 0, h = 0;
  TextureError error;
  ASSERT_TRUE(read_texture_header(as_bytes(jpeg), TextureLimits{}, &w, &h, &error)) << error.message;
  EXPECT_EQ(w, 256);
  EXPECT_EQ(h, 166);
}

// The mip filter's slow reference: destination texel d of an axis of n -> m texels covers source
// [d n / m, (d + 1) n / m); in units of 1/m that is [d n, (d + 1) n), and source texel s is
// [s m, (s + 1) m). Each source texel weighs its overlap; the sum is rounded to nearest, ties up.
MipLevel reference_halve(const MipLevel& src) {
  const int mw = std::max(1, src.width / 2), mh = std::max(1, src.height / 2);
  auto overlap = [](long a0, long a1, long b0, long b1) { return std::max(0L, std::min(a1, b1) - std::max(a0, b0)); };
  MipLevel dst{mw, mh, std::vector<uint8_t>(size_t(mw) * size_t(mh) * 3)};
  for (int y = 0; y < mh; ++y) {
    for (int x = 0; x < mw; ++x) {
      for (int c = 0; c < 3; ++c) {
        uint64_t sum = 0, total = 0;
        for (int j = 0; j < src.height; ++j) {
          for (int i = 0; i < src.width; ++i) {
            const uint64_t w =
                uint64_t(overlap(long(x) * src.width, long(x + 1) * src.width, long(i) * mw, long(i + 1) * mw)) *
                uint64_t(overlap(long(y) * src.height, long(y + 1) * src.height, long(j) * mh, long(j + 1) * mh));
            sum += w * src.rgb[(size_t(j) * size_t(src.width) + size_t(i)) * 3 + size_t(c)];
            total += w;
          }
        }
        dst.rgb[(size_t(y) * size_t(mw) + size_t(x)) * 3 + size_t(c)] = uint8_t((2 * sum + total) / (2 * total));
      }
    }
  }
  return dst;
}

TEST(TextureMips, FiveByThreeByHand) {
  // Red by column 10 20 30 40 50, green by row 0 90 210, blue 100 at (2, 0) only.
  Image image;
  image.width = 5, image.height = 3;
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 5; ++i) {
      image.rgb.push_back(uint8_t(10 * (i + 1)));
      image.rgb.push_back(uint8_t(j == 0 ? 0 : j == 1 ? 90 : 210));
      image.rgb.push_back(uint8_t(i == 2 && j == 0 ? 100 : 0));
    }
  }
  auto texture = texture_of(image);
  ASSERT_TRUE(texture);
  ASSERT_EQ(texture->levels.size(), 3u);
  EXPECT_EQ(texture->levels[1].width, 2);
  EXPECT_EQ(texture->levels[1].height, 1);
  EXPECT_EQ(texture->levels[2].width, 1);
  EXPECT_EQ(texture->levels[2].height, 1);
  // 5 -> 2 columns: weights (2, 2, 1) / 5 and (1, 2, 2) / 5; 3 -> 1 row: (1, 1, 1) / 3.
  // red: (20 + 40 + 30) / 5 = 18 and (30 + 80 + 100) / 5 = 42; green: 300 / 3 = 100;
  // blue: 100 * 1 / 15 = 6.67 -> 7 in both. Then 2 -> 1: red 30, green 100, blue 7.
  EXPECT_EQ(texture->levels[1].rgb, (std::vector<uint8_t>{18, 100, 7, 42, 100, 7}));
  EXPECT_EQ(texture->levels[2].rgb, (std::vector<uint8_t>{30, 100, 7}));
}

TEST(TextureMips, RoundsToNearestTiesUp) {
  Image image;
  image.width = 2, image.height = 2;
  // Per channel the four texels sum to 1 (0.25 -> 0), 2 (0.5 -> 1) and 3 (0.75 -> 1).
  image.rgb = {1, 1, 1, 0, 1, 1, 0, 0, 1, 0, 0, 0};
  auto texture = texture_of(image);
  ASSERT_TRUE(texture);
  EXPECT_EQ(texture->levels[1].rgb, (std::vector<uint8_t>{0, 1, 1}));
}

TEST(TextureMips, EveryLevelIsTheExactBoxOfThePrevious) {
  const int sizes[][2] = {{7, 5}, {9, 4}, {6, 1}, {1, 7}, {13, 13}, {16, 3}, {3, 3}};
  uint32_t seed = 100;
  for (const auto& size : sizes) {
    auto texture = texture_of(random_image(size[0], size[1], ++seed));
    ASSERT_TRUE(texture);
    for (size_t k = 1; k < texture->levels.size(); ++k) {
      const MipLevel expected = reference_halve(texture->levels[k - 1]);
      EXPECT_EQ(texture->levels[k].width, expected.width);
      EXPECT_EQ(texture->levels[k].height, expected.height);
      EXPECT_EQ(texture->levels[k].rgb, expected.rgb) << size[0] << " x " << size[1] << " level " << k;
    }
    EXPECT_EQ(texture->levels.back().width * texture->levels.back().height, 1);
  }
}

TEST(TextureDataUri, DecodesStrictBase64) {
  const std::string png = encode_png(random_image(3, 2, 91));
  std::vector<uint8_t> bytes;
  std::string error;
  for (bool pad : {true, false}) {
    ASSERT_TRUE(decode_data_uri("data:image/png;base64," + testing::base64_encode(png, pad), 1 << 20, bytes, &error))
        << error;
    EXPECT_EQ(std::string(bytes.begin(), bytes.end()), png);
  }
  auto texture = decode_ok(bytes);
  ASSERT_TRUE(texture);
  EXPECT_EQ(texture->content_id, hash_hex(png));
  // Every length modulo 3, padded and not; an empty payload is zero bytes.
  for (const std::string text : {"", "a", "ab", "abc", "abcd"}) {
    for (bool pad : {true, false}) {
      ASSERT_TRUE(decode_data_uri("data:text/plain;base64," + testing::base64_encode(text, pad), 100, bytes, &error))
          << error;
      EXPECT_EQ(std::string(bytes.begin(), bytes.end()), text);
    }
  }
  EXPECT_TRUE(decode_data_uri("data:image/png;base64,TWFu", 3, bytes, &error));
  EXPECT_EQ(std::string(bytes.begin(), bytes.end()), "Man");
}

TEST(TextureDataUri, RefusesWithReasons) {
  std::vector<uint8_t> bytes;
  auto refused = [&](const std::string& uri, size_t max_bytes, const std::string& says) {
    std::string error;
    EXPECT_FALSE(decode_data_uri(uri, max_bytes, bytes, &error)) << uri;
    EXPECT_NE(error.find(says), std::string::npos) << uri << ": " << error;
    EXPECT_TRUE(bytes.empty()) << uri;
  };
  refused("data:image/png;base64,TW Fu", 100, "whitespace at offset 2");
  refused("data:image/png;base64,TWFu\n", 100, "whitespace at offset 4");
  refused("data:image/png;base64,TW*u", 100, "'*' at offset 2");
  refused("data:image/png;base64,TW=u", 100, "'=' before the end");
  refused("data:image/png;base64,TWFuT", 100, "truncated");
  refused("data:image/png;base64,TQ=", 100, "multiple of 4");
  refused("data:image/png;base64,TQ===", 100, "'=' before the end");
  refused("data:image/png,TWFu", 100, ";base64,");
  refused("data:image/png;base64TWFu", 100, "comma");
  refused("http://example.com/a.png", 100, "not a data: URI");
  // "TWFuTWFu" is 6 bytes: counted from its length, refused before decoding.
  refused("data:image/png;base64,TWFuTWFu", 5, "6 bytes; at most 5");
  std::string error;
  EXPECT_TRUE(decode_data_uri("data:image/png;base64,TWFuTWFu", 6, bytes, &error)) << error;
}
}  // namespace
}  // namespace texture_decode_tests
}  // namespace rr
