// Image files (PNG, JPEG) and the PSNR / SSIM metrics that quality is judged by.
#include "image/image.h"

#include "encode/image_file.h"
#include "encode/jpeg.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <thread>

#include <unistd.h>

namespace hdof {
namespace {

using Rgba = std::array<uint8_t, 4>;

ImageRgba8 makeImage(uint32_t width, uint32_t height,
                     const std::function<Rgba(uint32_t, uint32_t)>& colour) {
  ImageRgba8 image{width, height, std::vector<uint8_t>(size_t{width} * height * 4)};
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      Rgba c = colour(x, y);
      std::copy(c.begin(), c.end(), &image.pixels[(size_t{y} * width + x) * 4]);
    }
  return image;
}

ImageRgba8 solid(uint32_t width, uint32_t height, Rgba c) {
  return makeImage(width, height, [c](uint32_t, uint32_t) { return c; });
}

uint8_t& channel(ImageRgba8& image, uint32_t x, uint32_t y, int c) {
  return image.pixels[(size_t{y} * image.width + x) * 4 + c];
}

// A texture with detail at several scales, so that blurring it loses structure.
ImageRgba8 texture(uint32_t width, uint32_t height) {
  return makeImage(width, height, [](uint32_t x, uint32_t y) {
    uint32_t h = (x * 73856093u) ^ (y * 19349663u);
    h = (h ^ (h >> 13)) * 0x5bd1e995u;
    auto v = [&](int shift, int scale) {
      return static_cast<uint8_t>(((x / scale + y / scale) % 2) * 128 + ((h >> shift) & 63) + 32);
    };
    return Rgba{v(0, 1), v(8, 2), v(16, 4), 255};
  });
}

ImageRgba8 boxBlur(const ImageRgba8& image, int radius) {
  return makeImage(image.width, image.height, [&](uint32_t x, uint32_t y) {
    Rgba out{0, 0, 0, 255};
    for (int c = 0; c < 3; ++c) {
      int sum = 0, count = 0;
      for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx) {
          int sx = static_cast<int>(x) + dx, sy = static_cast<int>(y) + dy;
          if (sx < 0 || sy < 0 || sx >= static_cast<int>(image.width) ||
              sy >= static_cast<int>(image.height))
            continue;
          sum += image.pixels[(size_t(sy) * image.width + sx) * 4 + c];
          ++count;
        }
      out[c] = static_cast<uint8_t>(sum / count);
    }
    return out;
  });
}

// Expects `f` to throw ImageError with a one-line message containing `part`.
template <typename F>
void expectImageError(F&& f, const std::string& part) {
  try {
    f();
    ADD_FAILURE() << "no ImageError; expected one mentioning: " << part;
  } catch (const ImageError& e) {
    std::string message = e.what();
    EXPECT_NE(message.find(part), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

class ImageFileTest : public testing::Test {
 protected:
  void SetUp() override {
    const auto* info = testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() /
           ("hdof-image-" + std::string(info->name()) + "-" + std::to_string(getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  void writeBytes(const std::string& name, const std::string& bytes) const {
    std::ofstream(path(name), std::ios::binary) << bytes;
  }
  std::string readBytes(const std::string& name) const {
    std::ifstream in(path(name), std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }

  std::filesystem::path dir_;
};

TEST_F(ImageFileTest, PngRoundTripIsExactIncludingAlpha) {
  ImageRgba8 image = makeImage(37, 23, [](uint32_t x, uint32_t y) {
    return Rgba{uint8_t(x * 7), uint8_t(y * 11), uint8_t(x * y), uint8_t(255 - x - y)};
  });
  writeImage(path("a.png"), image);
  ImageRgba8 back = readImage(path("a.png"));
  EXPECT_EQ(back.width, 37u);
  EXPECT_EQ(back.height, 23u);
  EXPECT_EQ(back.pixels, image.pixels);
}

TEST_F(ImageFileTest, JpegRoundTripOfSmoothGradientIsClose) {
  ImageRgba8 image = makeImage(96, 64, [](uint32_t x, uint32_t y) {
    return Rgba{uint8_t(x * 255 / 95), uint8_t(y * 255 / 63), uint8_t(128 + (x + y) / 2), 255};
  });
  writeImage(path("a.jpg"), image);
  ImageRgba8 back = readImage(path("a.jpg"));
  ASSERT_EQ(back.width, 96u);
  ASSERT_EQ(back.height, 64u);
  EXPECT_GT(compareImages(image, back).psnrDb, 30.0);
  EXPECT_EQ(back.pixels[3], 255);  // JPEG has no alpha: it reads back opaque
}

TEST_F(ImageFileTest, ExtensionChoosesTheFormatWhateverItsCase) {
  ImageRgba8 image = solid(8, 8, {10, 20, 30, 255});
  writeImage(path("a.PNG"), image);
  writeImage(path("b.JpEg"), image);
  writeImage(path("c.JPG"), image);
  EXPECT_EQ(readBytes("a.PNG").substr(1, 3), "PNG");
  EXPECT_EQ(readBytes("b.JpEg").substr(0, 2), "\xff\xd8");
  EXPECT_EQ(readBytes("c.JPG").substr(0, 2), "\xff\xd8");
  EXPECT_EQ(readImage(path("a.PNG")).pixels, image.pixels);
}

TEST_F(ImageFileTest, WritePngWritesPngWhateverTheName) {
  ImageRgba8 image = solid(3, 2, {1, 2, 3, 4});
  writePng(path("a.jpg"), image);
  EXPECT_EQ(readBytes("a.jpg").substr(1, 3), "PNG");
  EXPECT_EQ(readImage(path("a.jpg")).pixels, image.pixels);
  EXPECT_THROW(encodePng(ImageRgba8{}), std::invalid_argument);
  EXPECT_THROW(encodePng(ImageRgba8{4, 4, std::vector<uint8_t>(10)}), std::invalid_argument);
}

TEST_F(ImageFileTest, WritingAnUnknownExtensionIsAnError) {
  expectImageError([&] { writeImage("x.bmp", solid(2, 2, {})); },
                   "cannot write 'x.bmp': use a .png or .jpg file name");
  expectImageError([&] { writeImage(path("noextension"), solid(2, 2, {})); }, "use a .png");
}

TEST_F(ImageFileTest, WritingToAnUnwritablePathNamesPathAndReason) {
  const std::string target = path("missing-dir/a.png");
  expectImageError([&] { writeImage(target, solid(2, 2, {})); },
                   "cannot write '" + target + "': No such file or directory");
}

TEST_F(ImageFileTest, ReadingAMissingFileNamesPathAndReason) {
  const std::string target = path("nothing.png");
  expectImageError([&] { readImage(target); },
                   "cannot read '" + target + "': No such file or directory");
}

TEST_F(ImageFileTest, ReadingSomethingElseIsAnError) {
  writeBytes("text.png", "this is not an image");
  expectImageError([&] { readImage(path("text.png")); }, "not a PNG or JPEG file");
  writeBytes("empty.jpg", "");
  expectImageError([&] { readImage(path("empty.jpg")); }, "not a PNG or JPEG file");
  expectImageError([&] { readImage(dir_.string()); }, "cannot read '" + dir_.string() + "'");
}

TEST_F(ImageFileTest, ReadingATruncatedPngIsAnError) {
  writeImage(path("whole.png"), texture(40, 40));
  writeBytes("cut.png", readBytes("whole.png").substr(0, 100));
  expectImageError([&] { readImage(path("cut.png")); }, "cannot read '" + path("cut.png") + "'");
}

TEST_F(ImageFileTest, JpegWithFullChromaKeepsColourEdgesBetter) {
  // One-pixel red/blue stripes: 4:2:0 averages their chroma away, 4:4:4 keeps it.
  ImageRgba8 stripes = makeImage(64, 64, [](uint32_t x, uint32_t) {
    return x % 2 ? Rgba{255, 0, 0, 255} : Rgba{0, 0, 255, 255};
  });
  auto roundTripPsnr = [&](bool subsample420) {
    std::vector<uint8_t> jpeg = encodeJpeg(stripes, 90, subsample420);
    writeBytes("stripes.jpg", std::string(jpeg.begin(), jpeg.end()));
    return compareImages(stripes, readImage(path("stripes.jpg"))).psnrDb;
  };
  EXPECT_GT(roundTripPsnr(false), roundTripPsnr(true) + 3.0);
}

TEST(EncodeJpeg, GivesTheSameBytesOnEveryThread) {
  ImageRgba8 image = texture(160, 90);
  const std::vector<uint8_t> expected = encodeJpeg(image, 75);
  ASSERT_GT(expected.size(), 100u);
  std::vector<std::vector<uint8_t>> results(4);
  std::vector<std::thread> threads;
  for (auto& result : results)
    threads.emplace_back([&] {
      for (int i = 0; i < 20; ++i) result = encodeJpeg(image, 75);
    });
  for (auto& thread : threads) thread.join();
  for (const auto& result : results) EXPECT_EQ(result, expected);
}

TEST(EncodeJpeg, RejectsBadArguments) {
  EXPECT_THROW(encodeJpeg(solid(4, 4, {}), 0), std::invalid_argument);
  EXPECT_THROW(encodeJpeg(solid(4, 4, {}), 101), std::invalid_argument);
  EXPECT_THROW(encodeJpeg(ImageRgba8{}, 90), std::invalid_argument);
  EXPECT_THROW(encodeJpeg(ImageRgba8{4, 4, std::vector<uint8_t>(10)}, 90), std::invalid_argument);
}

TEST(CompareImages, IdenticalImagesHaveInfinitePsnrAndSsimOne) {
  ImageRgba8 image = texture(50, 30);
  ImageComparison result = compareImages(image, image);
  EXPECT_EQ(result.psnrDb, std::numeric_limits<double>::infinity());
  EXPECT_EQ(result.ssim, 1.0);
  EXPECT_EQ(result.pixels, 50u * 30u);
}

TEST(CompareImages, PsnrOfAKnownNoiseLevel) {
  // Every channel off by +-10: MSE 100, so PSNR = 10 log10(255^2 / 100).
  ImageRgba8 a = solid(16, 16, {100, 100, 100, 255});
  ImageRgba8 b = makeImage(16, 16, [](uint32_t x, uint32_t y) {
    uint8_t v = (x + y) % 2 ? 110 : 90;
    return Rgba{v, v, v, 0};  // alpha differs too, and must not count
  });
  EXPECT_NEAR(compareImages(a, b).psnrDb, 28.130803608679106, 1e-9);
}

TEST(CompareImages, SsimOfFlatImagesFollowsTheLuminanceTerm) {
  // No variance: SSIM = (2 mu_a mu_b + C1) / (mu_a^2 + mu_b^2 + C1), C1 = (0.01 * 255)^2.
  ImageRgba8 a = solid(20, 20, {100, 100, 100, 255});
  ImageRgba8 b = solid(20, 20, {110, 110, 110, 255});
  EXPECT_NEAR(compareImages(a, b).ssim, 0.9954764440915066, 1e-5);  // moments are floats
}

TEST(CompareImages, SsimIsOnLuma) {
  // Pure red and pure green of nearly equal luma (0.299 R + 0.587 G + 0.114 B: 76.2 and 76.3):
  // far apart in RGB, so PSNR is low, but alike for an SSIM over luma.
  ImageComparison result =
      compareImages(solid(12, 12, {255, 0, 0, 255}), solid(12, 12, {0, 130, 0, 255}));
  EXPECT_LT(result.psnrDb, 5.0);
  EXPECT_GT(result.ssim, 0.9999);
}

TEST(CompareImages, BlurLowersSsimMoreTheMoreItBlurs) {
  ImageRgba8 sharp = texture(64, 48);
  double slightly = compareImages(sharp, boxBlur(sharp, 1)).ssim;
  double heavily = compareImages(sharp, boxBlur(sharp, 3)).ssim;
  EXPECT_LT(slightly, 0.95);
  EXPECT_LT(heavily, slightly);
  EXPECT_GT(heavily, 0.0);
}

TEST(CompareImages, SsimIsSymmetric) {
  ImageRgba8 sharp = texture(30, 30), blurred = boxBlur(sharp, 2);
  EXPECT_NEAR(compareImages(sharp, blurred).ssim, compareImages(blurred, sharp).ssim, 1e-9);
}

// A 32x32 mask selecting the 8x8 block at (4, 4); elsewhere red is just below the threshold,
// and green is set everywhere, so only the red channel can be what selects.
ImageRgba8 blockMask() {
  return makeImage(32, 32, [](uint32_t x, uint32_t y) {
    bool inside = x >= 4 && x < 12 && y >= 4 && y < 12;
    return Rgba{uint8_t(inside ? 128 : 127), 255, 255, 255};
  });
}

TEST(CompareImages, MaskedComparisonIgnoresDifferencesOutsideTheMask) {
  ImageRgba8 a = texture(32, 32), b = a, mask = blockMask();
  // More than the window radius (5 px) away from the block, so no window of it sees them.
  for (uint32_t y = 0; y < 32; ++y)
    for (uint32_t x = 20; x < 32; ++x) channel(b, x, y, 1) ^= 0xff;
  ImageComparison result = compareImages(a, b, &mask);
  EXPECT_EQ(result.pixels, 64u);
  EXPECT_EQ(result.psnrDb, std::numeric_limits<double>::infinity());
  EXPECT_EQ(result.ssim, 1.0);
  EXPECT_LT(compareImages(a, b).ssim, 0.9);
}

TEST(CompareImages, MaskedPsnrAveragesOverMaskPixelsOnly) {
  ImageRgba8 a = solid(32, 32, {50, 60, 70, 255}), b = a, mask = blockMask();
  for (int c = 0; c < 3; ++c) channel(b, 6, 6, c) += 16;
  // One pixel of 64 off by 16 in every channel: MSE = 256 / 64 = 4.
  EXPECT_NEAR(compareImages(a, b, &mask).psnrDb, 42.11020369539948, 1e-9);
}

TEST(CompareImages, MaskedSsimWindowsStillSeeNeighboursOutsideTheMask) {
  ImageRgba8 a = texture(32, 32), b = a, mask = blockMask();
  for (int c = 0; c < 3; ++c) channel(b, 12, 8, c) ^= 0xff;  // just right of the block
  ImageComparison result = compareImages(a, b, &mask);
  EXPECT_EQ(result.psnrDb, std::numeric_limits<double>::infinity());
  EXPECT_LT(result.ssim, 1.0);
}

TEST(CompareImages, SizeMismatchIsAnError) {
  expectImageError([] { compareImages(solid(4, 4, {}), solid(4, 5, {})); },
                   "images differ in size: 4x4 and 4x5");
  ImageRgba8 wrongMask = solid(5, 4, {255, 255, 255, 255});
  expectImageError([&] { compareImages(solid(4, 4, {}), solid(4, 4, {}), &wrongMask); },
                   "mask is 5x4 but the images are 4x4");
}

TEST(CompareImages, EmptyMaskIsAnError) {
  ImageRgba8 mask = solid(4, 4, {127, 255, 255, 255});
  expectImageError([&] { compareImages(solid(4, 4, {}), solid(4, 4, {}), &mask); },
                   "the mask selects no pixels");
}

TEST(CompareImages, TinyImagesWork) {
  // Smaller than the 11x11 window in both directions.
  ImageComparison result = compareImages(solid(1, 1, {9, 9, 9, 9}), solid(1, 1, {9, 9, 9, 9}));
  EXPECT_EQ(result.ssim, 1.0);
  EXPECT_EQ(result.pixels, 1u);
  EXPECT_LT(compareImages(texture(3, 2), boxBlur(texture(3, 2), 1)).ssim, 1.0);
}

}  // namespace
}  // namespace hdof
