// hdof compare: PSNR and SSIM between two images, for scripts that judge a mode against the
// reference, so the output is one machine-readable line.
#include "app/cli.h"
#include "app/commands.h"
#include "image/image.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <optional>

namespace hdof {

int runCompare(std::span<const std::string> args) {
  std::string pathA, pathB, maskPath;
  bool json = false;
  ArgParser parser("compare", "A.png B.png [--mask M.png] [--json]",
                   "Prints PSNR (dB, over RGB; inf when identical) and SSIM (over luma) between\n"
                   "two images of the same size, as one line: psnr_db=42.17 ssim=0.9871");
  parser.positional("A", "first image (PNG or JPEG)", &pathA);
  parser.positional("B", "second image, same size", &pathB);
  parser.option("--mask", "M.png", "compare only pixels whose mask red value is >= 128", &maskPath);
  parser.flag("--json",
              "print {\"psnr_db\":..,\"ssim\":..,\"pixels\":..} (psnr_db null when identical)",
              &json);
  if (!parser.parse(args)) return 0;

  const ImageRgba8 a = readImage(pathA), b = readImage(pathB);
  std::optional<ImageRgba8> mask;
  if (parser.given("--mask")) mask = readImage(maskPath);
  const ImageComparison result = compareImages(a, b, mask ? &*mask : nullptr);

  if (json) {
    nlohmann::ordered_json out;
    if (std::isinf(result.psnrDb))
      out["psnr_db"] = nullptr;  // JSON has no infinity
    else
      out["psnr_db"] = result.psnrDb;
    out["ssim"] = result.ssim;
    out["pixels"] = result.pixels;
    std::printf("%s\n", out.dump().c_str());
  } else if (std::isinf(result.psnrDb)) {
    std::printf("psnr_db=inf ssim=%.4f\n", result.ssim);
  } else {
    std::printf("psnr_db=%.2f ssim=%.4f\n", result.psnrDb, result.ssim);
  }
  return 0;
}

}  // namespace hdof
