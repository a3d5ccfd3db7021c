// JPEG encoding of RGBA8 frames with TurboJPEG, for files and for the streamed frames.
#pragma once

#include "image/image.h"

#include <cstdint>
#include <span>
#include <vector>

namespace hdof {

// Returns the JPEG file's bytes; alpha is dropped. quality is 1..100; subsample420 halves the
// chroma resolution (smaller and faster, softer colour edges) instead of keeping it at 4:4:4.
// Safe to call from several threads at once: each thread keeps its own compressor.
// Throws std::invalid_argument on a bad image or quality, std::runtime_error when TurboJPEG fails.
std::vector<uint8_t> encodeJpeg(const ImageRgba8& image, int quality, bool subsample420 = true);

// Decodes a JPEG file's bytes to RGBA8 (alpha 255), for clients of the stream and tests.
// Throws std::invalid_argument when the bytes are not a JPEG TurboJPEG can read.
ImageRgba8 decodeJpeg(std::span<const uint8_t> jpeg);

}  // namespace hdof
