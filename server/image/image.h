// 8-bit RGBA images on the CPU: files (PNG, JPEG) and quality metrics (PSNR, SSIM).
#pragma once

#include <cstdint>
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

// Writes PNG or JPEG by the file's extension (.png, .jpg, .jpeg). Throws ImageError.
void writeImage(const std::string& path, const ImageRgba8& image, int jpegQuality = 92);
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
