// PNG output of an ImageRGB through libpng (8-bit RGB, no interlace).
#pragma once

#include "rgvc/render/Image.hpp"

#include <string>

namespace rgvc {

/// Writes `image` to `path` as an 8-bit RGB PNG, replacing any existing file.
/// @throws std::runtime_error "<path>: <reason>" when the image is empty, the file cannot be opened or
///         written (reason from errno), or libpng reports an error; a partly written file is removed.
void writePng(const std::string& path, const ImageRGB& image);

} // namespace rgvc
