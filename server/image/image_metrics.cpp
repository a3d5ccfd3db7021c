// PSNR and SSIM (Wang, Bovik, Sheikh, Simoncelli 2004, "Image Quality Assessment: From Error
// Visibility to Structural Similarity") for judging renders against the reference.
#include "image/image.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

namespace hdof {
namespace {

constexpr int kRadius = 5;  // the 11x11 window of the paper
constexpr double kSigma = 1.5;
constexpr double kC1 = (0.01 * 255) * (0.01 * 255);
constexpr double kC2 = (0.03 * 255) * (0.03 * 255);
constexpr uint8_t kMaskThreshold = 128;

using Kernel = std::array<float, 2 * kRadius + 1>;

const Kernel& gaussianKernel() {
  static const Kernel kernel = [] {
    Kernel k;
    double sum = 0;
    for (int i = -kRadius; i <= kRadius; ++i) sum += std::exp(-i * i / (2 * kSigma * kSigma));
    for (int i = -kRadius; i <= kRadius; ++i)
      k[i + kRadius] = static_cast<float>(std::exp(-i * i / (2 * kSigma * kSigma)) / sum);
    return k;
  }();
  return kernel;
}

// Weight of the taps of the window centred on `centre` that fall inside [0, size): near the
// border the window shrinks to the pixels that exist rather than inventing pixels beyond it.
float weightInside(int centre, int size) {
  const Kernel& w = gaussianKernel();
  float sum = 0;
  for (int k = -kRadius; k <= kRadius; ++k)
    if (centre + k >= 0 && centre + k < size) sum += w[k + kRadius];
  return sum;
}

// One row through the 1D Gaussian. The interior loop has no bounds checks so it vectorises.
void blurRow(const float* in, float* out, int size) {
  const Kernel& w = gaussianKernel();
  auto atBorder = [&](int i) {
    float sum = 0;
    for (int k = -kRadius; k <= kRadius; ++k)
      if (i + k >= 0 && i + k < size) sum += w[k + kRadius] * in[i + k];
    out[i] = sum / weightInside(i, size);
  };
  const int interiorBegin = std::min(kRadius, size);
  const int interiorEnd = std::max(interiorBegin, size - kRadius);
  for (int i = 0; i < interiorBegin; ++i) atBorder(i);
  for (int i = interiorBegin; i < interiorEnd; ++i) {
    float sum = 0;
    for (int k = 0; k <= 2 * kRadius; ++k) sum += w[k] * in[i - kRadius + k];
    out[i] = sum;
  }
  for (int i = interiorEnd; i < size; ++i) atBorder(i);
}

bool selected(const ImageRgba8* mask, size_t pixel) {
  return !mask || mask->pixels[pixel * 4] >= kMaskThreshold;
}

double meanSquaredErrorRgb(const ImageRgba8& a, const ImageRgba8& b, const ImageRgba8* mask,
                           uint64_t pixelCount) {
  uint64_t sum = 0;
  const size_t n = size_t{a.width} * a.height;
  for (size_t p = 0; p < n; ++p) {
    if (!selected(mask, p)) continue;
    for (int c = 0; c < 3; ++c) {
      int d = int{a.pixels[p * 4 + c]} - int{b.pixels[p * 4 + c]};
      sum += static_cast<uint64_t>(d * d);
    }
  }
  return static_cast<double>(sum) / (3.0 * static_cast<double>(pixelCount));
}

// Luma minus mid-grey: smaller squares lose less to the cancellation in the float variance
// E[x^2] - E[x]^2.
constexpr float kLumaOffset = 128;

std::vector<float> centredLuma(const ImageRgba8& image) {
  std::vector<float> y(size_t{image.width} * image.height);
  for (size_t p = 0; p < y.size(); ++p) {
    const uint8_t* rgb = &image.pixels[p * 4];
    y[p] = 0.299f * rgb[0] + 0.587f * rgb[1] + 0.114f * rgb[2] - kLumaOffset;
  }
  return y;
}

// Mean of the SSIM map over the selected pixels. The five local moments (means of x, y, x², y²,
// xy) go through the separable Gaussian: rows first into full planes, then columns one output
// row at a time, so the map itself is never stored.
double meanSsim(const ImageRgba8& a, const ImageRgba8& b, const ImageRgba8* mask,
                uint64_t pixelCount) {
  const int width = static_cast<int>(a.width), height = static_cast<int>(a.height);
  const size_t w = a.width;
  const std::vector<float> x = centredLuma(a), y = centredLuma(b);

  enum Moment { kX, kY, kXX, kYY, kXY, kMoments };
  std::array<std::vector<float>, kMoments> rowBlurred;
  for (auto& plane : rowBlurred) plane.resize(x.size());
  std::array<std::vector<float>, kMoments> line;
  for (auto& l : line) l.resize(w);
  for (int r = 0; r < height; ++r) {
    const float* xr = &x[r * w];
    const float* yr = &y[r * w];
    for (size_t i = 0; i < w; ++i) {
      line[kXX][i] = xr[i] * xr[i];
      line[kYY][i] = yr[i] * yr[i];
      line[kXY][i] = xr[i] * yr[i];
    }
    blurRow(xr, &rowBlurred[kX][r * w], width);
    blurRow(yr, &rowBlurred[kY][r * w], width);
    for (int m = kXX; m < kMoments; ++m) blurRow(line[m].data(), &rowBlurred[m][r * w], width);
  }

  const Kernel& kernel = gaussianKernel();
  double sum = 0;
  for (int r = 0; r < height; ++r) {
    for (auto& l : line) std::fill(l.begin(), l.end(), 0.0f);
    for (int k = -kRadius; k <= kRadius; ++k) {
      if (r + k < 0 || r + k >= height) continue;
      const float weight = kernel[k + kRadius];
      for (int m = 0; m < kMoments; ++m) {
        const float* in = &rowBlurred[m][(r + k) * w];
        float* out = line[m].data();
        for (size_t i = 0; i < w; ++i) out[i] += weight * in[i];
      }
    }
    // Double precision from here: identical images then give exactly 1.
    const double norm = 1.0 / weightInside(r, height);
    for (size_t i = 0; i < w; ++i) {
      if (!selected(mask, r * w + i)) continue;
      const double meanX = line[kX][i] * norm, meanY = line[kY][i] * norm;
      const double varX = line[kXX][i] * norm - meanX * meanX;
      const double varY = line[kYY][i] * norm - meanY * meanY;
      const double covXY = line[kXY][i] * norm - meanX * meanY;
      const double muX = meanX + kLumaOffset, muY = meanY + kLumaOffset;
      sum += ((2 * muX * muY + kC1) * (2 * covXY + kC2)) /
             ((muX * muX + muY * muY + kC1) * (varX + varY + kC2));
    }
  }
  return sum / static_cast<double>(pixelCount);
}

std::string sizeText(const ImageRgba8& image) {
  return std::to_string(image.width) + "x" + std::to_string(image.height);
}

void requireConsistent(const ImageRgba8& image, const char* what) {
  if (image.pixels.size() != size_t{image.width} * image.height * 4 ||
      image.width > static_cast<uint32_t>(std::numeric_limits<int>::max()) ||
      image.height > static_cast<uint32_t>(std::numeric_limits<int>::max()))
    throw std::invalid_argument(std::string("compareImages: ") + what + " is not a valid " +
                                sizeText(image) + " RGBA8 image");
}

}  // namespace

ImageComparison compareImages(const ImageRgba8& a, const ImageRgba8& b, const ImageRgba8* mask) {
  requireConsistent(a, "first image");
  requireConsistent(b, "second image");
  if (a.width != b.width || a.height != b.height)
    throw ImageError("images differ in size: " + sizeText(a) + " and " + sizeText(b));
  if (mask) {
    requireConsistent(*mask, "mask");
    if (mask->width != a.width || mask->height != a.height)
      throw ImageError("mask is " + sizeText(*mask) + " but the images are " + sizeText(a));
  }

  ImageComparison result;
  const size_t n = size_t{a.width} * a.height;
  for (size_t p = 0; p < n; ++p) result.pixels += selected(mask, p);
  if (result.pixels == 0)
    throw ImageError(mask ? "the mask selects no pixels (none has red >= 128)"
                          : "the images are empty");

  const double mse = meanSquaredErrorRgb(a, b, mask, result.pixels);
  result.psnrDb =
      mse == 0 ? std::numeric_limits<double>::infinity() : 10.0 * std::log10(255.0 * 255.0 / mse);
  result.ssim = meanSsim(a, b, mask, result.pixels);
  return result;
}

}  // namespace hdof
