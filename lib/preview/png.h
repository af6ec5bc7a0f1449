#pragma once
// Images as PNG bytes (libpng), for the tools to write atomically like any other output.
#include <string>

#include "sweep/preview/render.h"

namespace sweep::preview {

// The image as a PNG file's bytes: 8-bit RGB, no interlace, default compression.
std::string encode_png(const Image& image);

}  // namespace sweep::preview
