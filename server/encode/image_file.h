// Image files in the format their name asks for: PNG (image/) or JPEG (encode/jpeg.h).
#pragma once

#include "image/image.h"

#include <string>

namespace hdof {

// Writes PNG or JPEG by the file's extension (.png, .jpg, .jpeg, any case). Throws ImageError,
// or std::invalid_argument on an image that is not a valid RGBA8 image.
void writeImage(const std::string& path, const ImageRgba8& image, int jpegQuality = 92);

}  // namespace hdof
