// PNG encoders (see png.hpp). The container is written here; deflate is zlib's.
#include "render/core/png.hpp"

#include "render/core/parallel.hpp"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <thread>
#include <vector>

namespace rr {

namespace {

// Rows per deflate strip: large enough that the 32 KiB window restarting at each strip costs little
// (about 1 % in size on rendered rooms), small enough that a 720-row frame gives every core work.
constexpr int kStripRows = 48;

void put_u32(std::string& out, uint32_t v) {
  const char b[4] = {char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
  out.append(b, 4);
}

void put_chunk(std::string& out, const char type[4], std::string_view data) {
  put_u32(out, uint32_t(data.size()));
  size_t start = out.size();
  out.append(type, 4);
  out.append(data);
  uLong crc = crc32(0L, reinterpret_cast<const Bytef*>(out.data() + start), uInt(out.size() - start));
  put_u32(out, uint32_t(crc));
}

std::string png_container(const Image& image, std::string_view zlib_stream) {
  std::string out("\x89PNG\r\n\x1a\n", 8);
  std::string header;
  put_u32(header, uint32_t(image.width));
  put_u32(header, uint32_t(image.height));
  header += std::string("\x08\x02\x00\x00\x00", 5);  // 8 bits, RGB, deflate, adaptive filters, no interlace
  put_chunk(out, "IHDR", header);
  put_chunk(out, "IDAT", zlib_stream);
  put_chunk(out, "IEND", {});
  return out;
}

// Sum of the filtered bytes taken as signed: libpng's heuristic for how well a row will deflate.
uint32_t filter_cost(const uint8_t* bytes, size_t n) {
  uint32_t sum = 0;
  for (size_t i = 0; i < n; ++i) sum += uint32_t(std::abs(int(int8_t(bytes[i]))));
  return sum;
}

// Filters one row (`prev` is the row above, or null for the first row) into out[0] = filter type,
// out[1..] = filtered bytes, choosing Sub or Up by the smaller cost. Rendered rooms are flat spans
// and repeated rows, which these two catch; Paeth and Average would cost three times as much for a
// few per cent of size (measured by bench/png.cpp), which is what `small` is for. The loops are
// plain byte arithmetic so the compiler vectorizes them.
void filter_row(const uint8_t* row, const uint8_t* prev, size_t bytes, uint8_t* out, std::vector<uint8_t>& scratch) {
  constexpr size_t bpp = 3;
  scratch.resize(2 * bytes);
  uint8_t* sub = scratch.data();
  uint8_t* up = sub + bytes;
  for (size_t i = 0; i < std::min(bpp, bytes); ++i) sub[i] = row[i];
  for (size_t i = bpp; i < bytes; ++i) sub[i] = uint8_t(row[i] - row[i - bpp]);
  if (prev) {
    for (size_t i = 0; i < bytes; ++i) up[i] = uint8_t(row[i] - prev[i]);
  } else {
    std::memcpy(up, row, bytes);  // Up with no row above is the identity
  }
  bool use_up = filter_cost(up, bytes) < filter_cost(sub, bytes);
  out[0] = use_up ? 2 : 1;
  std::memcpy(out + 1, use_up ? up : sub, bytes);
}

int paeth(int a, int b, int c) {
  int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  if (pa <= pb && pa <= pc) return a;
  return pb <= pc ? b : c;
}

// As filter_row, but tries all five filters (None, Sub, Up, Average, Paeth) for `small`.
void filter_row_best(const uint8_t* row, const uint8_t* prev, size_t bytes, uint8_t* out,
                     std::vector<uint8_t>& scratch) {
  constexpr size_t bpp = 3;
  scratch.resize(5 * bytes);
  uint32_t best_cost = UINT32_MAX;
  int best = 0;
  for (int type = 0; type < 5; ++type) {
    uint8_t* f = scratch.data() + size_t(type) * bytes;
    for (size_t i = 0; i < bytes; ++i) {
      int a = i >= bpp ? row[i - bpp] : 0, b = prev ? prev[i] : 0, c = prev && i >= bpp ? prev[i - bpp] : 0;
      int predictor = type == 0 ? 0 : type == 1 ? a : type == 2 ? b : type == 3 ? (a + b) / 2 : paeth(a, b, c);
      f[i] = uint8_t(row[i] - predictor);
    }
    uint32_t cost = filter_cost(f, bytes);
    if (cost < best_cost) best_cost = cost, best = type;
  }
  out[0] = uint8_t(best);
  std::memcpy(out + 1, scratch.data() + size_t(best) * bytes, bytes);
}

struct Strip {
  std::string deflated;  // raw deflate, byte-aligned; the last strip carries the final block
  uLong adler = 1;
  size_t raw_bytes = 0;
};

// Filters and deflates rows [first, last) into `strip`.
void deflate_strip(const Image& image, int first, int last, bool is_last, bool best, Strip& strip) {
  const size_t row_bytes = size_t(image.width) * 3;
  std::vector<uint8_t> raw(size_t(last - first) * (row_bytes + 1));
  std::vector<uint8_t> scratch;
  for (int y = first; y < last; ++y) {
    const uint8_t* row = image.rgb.data() + size_t(y) * row_bytes;
    const uint8_t* prev = y > 0 ? row - row_bytes : nullptr;
    uint8_t* out = raw.data() + size_t(y - first) * (row_bytes + 1);
    if (best) {
      filter_row_best(row, prev, row_bytes, out, scratch);
    } else {
      filter_row(row, prev, row_bytes, out, scratch);
    }
  }
  strip.raw_bytes = raw.size();
  strip.adler = adler32(1L, raw.data(), uInt(raw.size()));

  z_stream z{};
  // Level 1 (zlib's fastest matcher) or 9 (its most thorough). windowBits -15: raw deflate, the
  // zlib header and Adler-32 are written once for the joined stream.
  if (deflateInit2(&z, best ? 9 : 1, Z_DEFLATED, -15, best ? 9 : 8, Z_DEFAULT_STRATEGY) != Z_OK) {
    throw std::runtime_error("PNG encoding failed: deflateInit2");
  }
  strip.deflated.resize(deflateBound(&z, uLong(raw.size())) + 16);
  z.next_in = raw.data();
  z.avail_in = uInt(raw.size());
  z.next_out = reinterpret_cast<Bytef*>(strip.deflated.data());
  z.avail_out = uInt(strip.deflated.size());
  // A sync flush ends the strip's blocks (not final) on a byte boundary, so the next strip's
  // independently deflated blocks can follow it directly in one stream.
  int rc = deflate(&z, is_last ? Z_FINISH : Z_SYNC_FLUSH);
  bool ok = is_last ? rc == Z_STREAM_END : (rc == Z_OK && z.avail_in == 0);
  strip.deflated.resize(strip.deflated.size() - z.avail_out);
  deflateEnd(&z);
  if (!ok) throw std::runtime_error("PNG encoding failed: deflate");
}

std::string encode_strips(const Image& image, bool best, unsigned threads) {
  const int strips_count = std::max(1, (image.height + kStripRows - 1) / kStripRows);
  std::vector<Strip> strips(static_cast<size_t>(strips_count));
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  // One task per strip on the render pool; an exception (out of memory) is carried out of the task.
  std::vector<std::exception_ptr> errors(threads);
  parallel_for(threads, size_t(strips_count), [&](size_t s, unsigned worker) {
    try {
      const int first = int(s) * kStripRows;
      const int last = std::min(image.height, first + kStripRows);
      deflate_strip(image, first, last, int(s) + 1 == strips_count, best, strips[s]);
    } catch (...) {
      errors[worker] = std::current_exception();
    }
  });
  for (auto& e : errors) {
    if (e) std::rethrow_exception(e);
  }
  // zlib header: deflate with a 32 KiB window, level hint fastest (0x01) or maximum (0xDA).
  std::string stream(best ? "\x78\xDA" : "\x78\x01", 2);
  uLong adler = 1;
  for (const Strip& s : strips) {
    stream += s.deflated;
    adler = adler32_combine(adler, s.adler, z_off_t(s.raw_bytes));
  }
  put_u32(stream, uint32_t(adler));
  return png_container(image, stream);
}

// Stored blocks (at most 65535 bytes each) of the unfiltered rows.
std::string encode_stored(const Image& image) {
  const size_t row_bytes = size_t(image.width) * 3;
  std::string raw;
  raw.reserve(size_t(image.height) * (row_bytes + 1));
  for (int y = 0; y < image.height; ++y) {
    raw.push_back('\0');
    raw.append(reinterpret_cast<const char*>(image.rgb.data()) + size_t(y) * row_bytes, row_bytes);
  }
  std::string stream("\x78\x01", 2);
  size_t pos = 0;
  do {
    size_t n = std::min<size_t>(65535, raw.size() - pos);
    bool final_block = pos + n == raw.size();
    stream.push_back(final_block ? '\x01' : '\x00');
    const char len[4] = {char(n & 0xFF), char(n >> 8), char(~n & 0xFF), char((~n >> 8) & 0xFF)};
    stream.append(len, 4);
    stream.append(raw, pos, n);
    pos += n;
  } while (pos < raw.size());
  put_u32(stream, uint32_t(adler32(1L, reinterpret_cast<const Bytef*>(raw.data()), uInt(raw.size()))));
  return png_container(image, stream);
}

}  // namespace

std::string encode_png(const Image& image, PngCompression mode, unsigned threads) {
  if (image.width <= 0 || image.height <= 0) throw std::runtime_error("PNG encoding failed: empty image");
  switch (mode) {
    case PngCompression::fast:
      return encode_strips(image, false, threads);
    case PngCompression::small:
      return encode_strips(image, true, threads);
    case PngCompression::none:
      return encode_stored(image);
  }
  throw std::logic_error("unknown PNG compression mode");
}

}  // namespace rr
