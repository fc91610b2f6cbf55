// PNG encoders of options.png.compression, used by render() for every render. `fast` (the default)
// chooses Sub or Up per row and deflates horizontal strips of rows in parallel with zlib's fastest
// level, joining the strips into one valid zlib stream (each strip ends on a byte boundary with a
// sync flush; the Adler-32s are combined). `small` is the same strip encoder trying all five filters
// per row at zlib level 9: the smallest of the three on rendered rooms, several times slower than
// `fast`. `none` stores the rows unfiltered in stored deflate blocks: no compression work at all.
// stb_image_write (encode_png(image) in image.hpp) is not a mode: it is the tests' reference.
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
