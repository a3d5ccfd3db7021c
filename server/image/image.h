// 8-bit RGBA images on the CPU: PNG files, reading JPEG files, and quality metrics (PSNR, SSIM).
// The lowest layer of images, below the JPEG encoder: writing JPEG, and writing a file in the
// format its name asks for (writeImage), are the encoding layer's.
#pragma once

#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace hdof {

// A file that cannot be read or written, or is not an image: a message for the user.
struct ImageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct ImageRgba8 {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> pixels;  // row-major, top row first, 4 bytes a pixel
};

// The PNG file's bytes, alpha kept. Throws std::invalid_argument on a bad image,
// std::runtime_error when encoding fails.
std::vector<uint8_t> encodePng(const ImageRgba8& image);
// Writes a PNG file. Throws ImageError naming the path and the reason.
void writePng(const std::string& path, const ImageRgba8& image);
// Writes an encoded image's bytes (PNG, JPEG) to a file. Throws ImageError naming the path and
// the reason.
void writeImageBytes(const std::string& path, std::span<const uint8_t> bytes);
// Reads a PNG or JPEG file. Throws ImageError.
ImageRgba8 readImage(const std::string& path);

struct ImageComparison {
  double psnrDb = 0.0;  // infinity when identical
  double ssim = 0.0;
  uint64_t pixels = 0;  // pixels compared
};

// PSNR over RGB and SSIM over luma (Rec. 601 weights, as in Wang et al. 2004: 11x11 Gaussian
// window with sigma 1.5, C1 = (0.01*255)^2, C2 = (0.03*255)^2; at the image border the window
// shrinks to the pixels inside) between two images of equal size. Where a mask (same size) is
// given, only pixels whose mask red value is >= 128 count: PSNR over their RGB, SSIM as the mean
// of the SSIM map over them, whose windows still read the neighbours outside the mask.
// Throws ImageError when the sizes differ or nothing is selected.
ImageComparison compareImages(const ImageRgba8& a, const ImageRgba8& b,
                              const ImageRgba8* mask = nullptr);

}  // namespace hdof
