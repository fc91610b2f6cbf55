// PNG encoders: every mode decodes to exactly the pixels it was given (checked with decode_png, which
// is libpng, and, for the container and zlib stream, independently with zlib, which verifies the
// Adler-32, and the test's own chunk reader, which checks the CRCs), and `fast` is byte-identical for
// any thread count.
#include "render/core/png.hpp"
#include "render/core/scene_names.hpp"
#include "render/pipelines/pipeline.hpp"
#include "render/scene_io/errors.hpp"
#include "render/scene_io/scene_json.hpp"
#include "support/render_helpers.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <zlib.h>
#include <nlohmann/json.hpp>

#include <cstring>
#include <random>

namespace rr {
namespace {

uint32_t read_u32(const std::string& s, size_t at) {
  return uint32_t(uint8_t(s[at])) << 24 | uint32_t(uint8_t(s[at + 1])) << 16 | uint32_t(uint8_t(s[at + 2])) << 8 |
         uint32_t(uint8_t(s[at + 3]));
}

// Walks the chunks (checking every CRC), inflates the IDAT stream with zlib (checking its Adler-32)
// and undoes the row filters: the pixels as an independent decoder sees them.
std::vector<uint8_t> decode_with_zlib(const std::string& png, int width, int height) {
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  std::string idat;
  for (size_t at = 8; at + 12 <= png.size();) {
    uint32_t length = read_u32(png, at);
    std::string type = png.substr(at + 4, 4);
    uLong crc = crc32(0L, reinterpret_cast<const Bytef*>(png.data() + at + 4), uInt(length + 4));
    EXPECT_EQ(uint32_t(crc), read_u32(png, at + 8 + length)) << "CRC of chunk " << type;
    if (type == "IHDR") {
      EXPECT_EQ(read_u32(png, at + 8), uint32_t(width));
      EXPECT_EQ(read_u32(png, at + 12), uint32_t(height));
    }
    if (type == "IDAT") idat += png.substr(at + 8, length);
    at += 12 + length;
  }
  const size_t row_bytes = size_t(width) * 3;
  std::vector<uint8_t> raw(size_t(height) * (row_bytes + 1));
  uLongf raw_size = uLongf(raw.size());
  EXPECT_EQ(uncompress(raw.data(), &raw_size, reinterpret_cast<const Bytef*>(idat.data()), uLong(idat.size())), Z_OK);
  EXPECT_EQ(raw_size, raw.size());
  std::vector<uint8_t> pixels(size_t(height) * row_bytes);
  for (int y = 0; y < height; ++y) {
    const uint8_t* in = raw.data() + size_t(y) * (row_bytes + 1);
    uint8_t* row = pixels.data() + size_t(y) * row_bytes;
    const uint8_t* prev = y > 0 ? row - row_bytes : nullptr;
    for (size_t i = 0; i < row_bytes; ++i) {
      int a = i >= 3 ? row[i - 3] : 0, b = prev ? prev[i] : 0, c = prev && i >= 3 ? prev[i - 3] : 0;
      int predictor = 0;
      switch (in[0]) {
        case 0:
          break;
        case 1:
          predictor = a;
          break;
        case 2:
          predictor = b;
          break;
        case 3:
          predictor = (a + b) / 2;
          break;
        case 4: {
          int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
          predictor = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
          break;
        }
        default:
          ADD_FAILURE() << "filter type " << int(in[0]) << " in row " << y;
          return {};
      }
      row[i] = uint8_t(in[1 + i] + predictor);
    }
  }
  return pixels;
}

Image noise_image(int width, int height, uint32_t seed) {
  Image image(width, height, Color(0.0f));
  std::mt19937 rng(seed);
  for (uint8_t& v : image.rgb) v = uint8_t(rng());
  // Flat spans and repeated rows too, as rendered rooms have.
  for (int y = height / 3; y < height / 2; ++y) std::memset(image.pixel(0, y), 90, size_t(width) * 3);
  return image;
}

Image rendered_example(const std::string& name, int width, int height) {
  nlohmann::json request = nlohmann::json::parse(testing::read_file(testing::examples_dir() / (name + ".json")));
  request["options"]["width"] = width;
  request["options"]["height"] = height;
  return rr::testing::render_text(request.dump()).result.frame.image;
}

void expect_round_trip(const Image& image, const std::string& what) {
  for (const auto& m : png_compression_names) {
    SCOPED_TRACE(what + ", compression " + m.name);
    std::string png = encode_png(image, m.value);
    Image decoded = decode_png(png);
    ASSERT_EQ(decoded.width, image.width);
    ASSERT_EQ(decoded.height, image.height);
    EXPECT_TRUE(decoded.rgb == image.rgb) << "decode_png (libpng) decodes other pixels";
    EXPECT_TRUE(decode_with_zlib(png, image.width, image.height) == image.rgb) << "zlib decodes other pixels";
  }
}

TEST(Png, EveryModeDecodesToTheSamePixelsOnRenderedRooms) {
  expect_round_trip(rendered_example("apartment", 320, 240), "apartment");
  expect_round_trip(rendered_example("four_cylinders", 173, 97), "four_cylinders");
}

TEST(Png, EveryModeDecodesToTheSamePixelsOnNoiseAndOddSizes) {
  const uint32_t seed = 20261122;
  SCOPED_TRACE("seed " + std::to_string(seed));
  // 1x1, one row, one column, a height of exactly one strip, one more than a strip, several strips,
  // and an image whose stored form needs more than one 65535-byte stored block.
  for (auto [w, h] : {std::pair{1, 1}, {200, 1}, {1, 200}, {31, 48}, {31, 49}, {64, 145}, {300, 160}}) {
    expect_round_trip(noise_image(w, h, seed), std::to_string(w) + "x" + std::to_string(h));
  }
}

TEST(Png, FastOutputIsByteIdenticalForAnyThreadCount) {
  Image image = rendered_example("studio", 400, 300);
  std::string one = encode_png(image, PngCompression::fast, 1);
  EXPECT_EQ(encode_png(image, PngCompression::fast, 2), one);
  EXPECT_EQ(encode_png(image, PngCompression::fast, 8), one);
  EXPECT_EQ(encode_png(image, PngCompression::fast, 0), one);
}

TEST(Png, SizesAgainstTheStbReferenceOnRenderedRooms) {
  // Size properties, not speed targets (bench/png.cpp measures speed): the cheap filter choice of
  // `fast` must not give away much compression on the images this service makes, and `small` must
  // earn its name against stb_image_write's defaults.
  for (const char* example : {"apartment", "studio", "four_cylinders"}) {
    Image image = rendered_example(example, 640, 480);
    double reference = double(encode_png(image).size());
    double fast = double(encode_png(image, PngCompression::fast).size());
    double small = double(encode_png(image, PngCompression::small).size());
    EXPECT_LE(fast, 1.5 * reference) << example << ": " << fast << " bytes vs " << reference;
    EXPECT_LE(small, reference) << example << ": " << small << " bytes vs " << reference;
  }
}

TEST(Png, CompressionOptionIsParsedAndValidated) {
  EXPECT_EQ(parse_request(R"({})").options.png_compression, PngCompression::fast);
  EXPECT_EQ(parse_request(R"({"options":{"png":{"compression":"small"}}})").options.png_compression,
            PngCompression::small);
  EXPECT_EQ(parse_request(R"({"options":{"png":{"compression":"none"}}})").options.png_compression,
            PngCompression::none);
  try {
    parse_request(R"({"options":{"png":{"compression":"zopfli"}}})");
    FAIL() << "accepted an unknown compression";
  } catch (const InputError& e) {
    EXPECT_EQ(e.pointer(), "/options/png/compression");
    EXPECT_NE(std::string(e.what()).find("fast, small, none"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rr
