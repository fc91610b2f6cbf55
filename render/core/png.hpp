// PNG encoders. `small` is stb_image_write at its defaults (five filters tried per row, its own
// deflate at level 8): the reference, and the smallest of the three on rendered rooms, but slow
// (tens of milliseconds for 1280x720). `fast` chooses a cheap filter per row and deflates
// horizontal strips of rows in parallel with zlib's fastest level, joining the strips into one valid
// zlib stream (each strip ends on a byte boundary with a sync flush; the Adler-32s are combined).
// `none` stores the rows unfiltered in stored deflate blocks: no compression work at all.
//
// Every mode decodes to the same pixels. The strip layout depends only on the image size, never on
// the thread count, so `fast` output is byte-identical for any number of threads.
#pragma once

#include "render/core/image.hpp"
#include "render/core/scene.hpp"

#include <string>

namespace rr {

// `threads` = 0 uses the hardware concurrency; only `fast` uses more than one.
std::string encode_png(const Image& image, PngCompression mode, unsigned threads = 0);

}  // namespace rr
