// The command line through the real binary: bad input gives one line naming the problem and
// exit code 2, never a crash; good input writes the image.
#include "image/image.h"
#include "common/scratch_dir.h"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

struct Result {
  int exitCode = -1;
  std::string stdoutText, stderrText;
};

std::filesystem::path tempDir() { return hdof::test::scratchDir("cli"); }

std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

Result runHdof(const std::string& args) {
  auto dir = tempDir();
  std::string command = std::string(HDOF_BINARY) + " " + args + " >" + (dir / "out.txt").string() +
                        " 2>" + (dir / "err.txt").string();
  int status = std::system(command.c_str());
  Result result;
  result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  result.stdoutText = slurp(dir / "out.txt");
  result.stderrText = slurp(dir / "err.txt");
  return result;
}

// Bad usage: exit code 2 and exactly one line on stderr that mentions `expected`.
void expectUsageError(const std::string& args, const std::string& expected) {
  Result r = runHdof(args);
  EXPECT_EQ(r.exitCode, 2) << args << "\nstderr: " << r.stderrText;
  EXPECT_EQ(std::count(r.stderrText.begin(), r.stderrText.end(), '\n'), 1)
      << args << "\nstderr: " << r.stderrText;
  EXPECT_NE(r.stderrText.find(expected), std::string::npos) << args << "\nstderr: " << r.stderrText;
}

const std::string kOut = "--out " + (tempDir() / "x.png").string();
const std::string kExamplePath = std::string(HDOF_SOURCE_DIR) + "/docs/examples/dolly.json";

TEST(Cli, BadRenderInputIsAOneLineErrorWithExitCode2) {
  expectUsageError("render --scene /no/such/scene.gltf " + kOut, "/no/such/scene.gltf");
  expectUsageError("render --scene builtin:nope " + kOut, "nope");
  expectUsageError("render --camera nope " + kOut, "nope");
  expectUsageError("render --size 0x0 " + kOut, "0x0");
  expectUsageError("render --size 100000x100000 " + kOut, "100000x100000");
  expectUsageError("render --size wide " + kOut, "wide");
  expectUsageError("render --f-number -2 " + kOut, "--f-number");
  expectUsageError("render --f-number nan " + kOut, "nan");
  expectUsageError("render --mode blurry " + kOut, "blurry");
  expectUsageError("render --spp 0 --mode reference " + kOut, "--spp");
  expectUsageError("render --bogus " + kOut, "--bogus");
  expectUsageError("render", "--out");
  expectUsageError("render --out picture.bmp", "picture.bmp");
  expectUsageError("frobnicate", "frobnicate");
  expectUsageError("render --device no-such-gpu " + kOut, "no-such-gpu");
  expectUsageError("render --view mask " + kOut, "--mode hybrid");
  expectUsageError("render --mode hybrid --view sideways " + kOut, "sideways");
  expectUsageError("render --full-mask " + kOut, "--mode hybrid");
}

TEST(Cli, BadLensInputIsAOneLineError) {
  for (const char* bad : {"huge", "36", "36x", "x24", "36x0.5", "400x24", "36x24x2"})
    expectUsageError(std::string("render --sensor '") + bad + "' " + kOut,
                     "--sensor must be WxH in millimetres");
  expectUsageError("render --sensor bogus " + kOut, "full-frame, super35, aps-c, aps-c-canon, mft");
  expectUsageError("bench --sensor 36by24", "--sensor");
  expectUsageError("quality --sensor 36by24", "--sensor");
  expectUsageError("render --focal-length 6000 " + kOut, "--focal-length");
  // A camera path from when the field of view was the camera's would lose its zoom silently.
  auto path = tempDir() / "yfov-path.json";
  std::ofstream(path) << R"({"keyframes": [{"position": [0, 1, 5], "target": [0, 1, 0], "yfov_deg": 30}]})";
  expectUsageError("render --camera-path " + path.string() + " " + kOut, "focal_length_mm");
}

// bench prints its times to three significant digits at least: a GPU's passes take hundredths of
// a millisecond, and a frame one or two.
TEST(Cli, BenchTimesKeepThreeDigits) {
  Result r = runHdof("bench --scene builtin:dof --size 16x16 --frames 1");
  ASSERT_EQ(r.exitCode, 0) << r.stderrText;
  size_t from = r.stdoutText.find("hybrid_passes_ms:");
  ASSERT_NE(from, std::string::npos) << r.stdoutText;
  std::istringstream line(r.stdoutText.substr(from, r.stdoutText.find('\n', from) - from));
  int figures = 0;
  for (std::string word; line >> word;) {
    size_t equals = word.find('=');
    if (equals == std::string::npos) continue;
    std::string digits = word.substr(equals + 1);
    std::erase(digits, '.');
    digits.erase(0, digits.find_first_not_of('0'));
    EXPECT_GE(digits.size(), 3u) << word;
    ++figures;
  }
  EXPECT_GT(figures, 10) << r.stdoutText;
}

// The field of view follows focal length and sensor; without a focal length the scene camera's
// (builtin:dof: 40 degrees up) is kept. 64x36 is 16:9: 36 x 20.25 mm of a full-frame sensor.
TEST(Cli, TheLensSetsTheFieldOfView) {
  auto png = tempDir() / "lens.png";
  auto lensLine = [&](const std::string& options) {
    Result r = runHdof("render --scene builtin:dof --size 64x36 --verbose " + options + " --out " +
                       png.string());
    EXPECT_EQ(r.exitCode, 0) << r.stderrText;
    size_t at = r.stderrText.find("lens: ");
    return at == std::string::npos ? r.stderrText : r.stderrText.substr(at);
  };
  // 20.25 / (2 tan 20 degrees) = 27.8 mm, which sees 2 atan(18 / 27.818) = 65.8 degrees across.
  EXPECT_NE(lensLine("").find("focal_length_mm=27.8 "), std::string::npos) << lensLine("");
  EXPECT_NE(lensLine("").find("fov_deg=65.8x40.0"), std::string::npos) << lensLine("");
  // 50 mm: 2 atan(18 / 50) = 39.6 across, 2 atan(10.125 / 50) = 22.9 up.
  EXPECT_NE(lensLine("--focal-length 50").find("sensor_mm=36x24 fov_deg=39.6x22.9"),
            std::string::npos);
  // The same lens on Micro Four Thirds (17.3 mm across): 2 atan(8.65 / 50) = 19.6 across.
  EXPECT_NE(lensLine("--focal-length 50 --sensor mft").find("sensor_mm=17.3x13 fov_deg=19.6x11.1"),
            std::string::npos)
      << lensLine("--focal-length 50 --sensor mft");
  // bench --json says which lens its figures are for.
  Result bench = runHdof(
      "bench --scene builtin:dof --size 64x36 --frames 1 --focal-length 50 --sensor mft --json");
  ASSERT_EQ(bench.exitCode, 0) << bench.stderrText;
  EXPECT_NE(bench.stdoutText.find("\"lens\":{\"focal_length_mm\":50.000,"), std::string::npos)
      << bench.stdoutText;
  EXPECT_NE(bench.stdoutText.find("\"sensor_width_mm\":17.3,\"sensor_height_mm\":13,"
                                  "\"fov_x_deg\":19.6"),
            std::string::npos)
      << bench.stdoutText;
  // ... and what a lens-only frame, a frame after a cut, one at rest and one in motion cost.
  for (const char* figure : {"\"hybrid_focus_pull_ms\":", "\"hybrid_cut_frame_ms\":",
                             "\"hybrid_rest_frame_ms\":", "\"hybrid_moving_frame_ms\":"})
    EXPECT_NE(bench.stdoutText.find(figure), std::string::npos) << figure;
  // At rest every pixel gets rays.
  const std::string restRays = "\"hybrid_rest_rays_per_frame\":";
  size_t at = bench.stdoutText.find(restRays);
  ASSERT_NE(at, std::string::npos);
  EXPECT_GE(std::stod(bench.stdoutText.substr(at + restRays.size())), 64.0 * 36.0);
  // A figure's passes; a lens-only frame's: the DoF steps (and the hybrid's rays), no G-buffer
  // work.
  auto passesOf = [&](const std::string& figure) {
    const std::string member = "\"" + figure + "_passes_ms\":{";
    size_t from = bench.stdoutText.find(member);
    EXPECT_NE(from, std::string::npos) << member;
    if (from == std::string::npos) return std::string();
    return bench.stdoutText.substr(from, bench.stdoutText.find('}', from) - from);
  };
  // In motion the G-buffer runs every frame and the hybrid's history is reprojected.
  std::string movingPasses = passesOf("hybrid_moving");
  for (const char* pass : {"\"visibility\":", "\"gbuffer\":", "\"hybrid_temporal\":"})
    EXPECT_NE(movingPasses.find(pass), std::string::npos) << pass << " in " << movingPasses;
  std::string hybridPasses = passesOf("hybrid_focus_pull"),
              postProcessPasses = passesOf("postprocess_focus_pull");
  for (const char* pass : {"\"dof_gather\":", "\"hybrid_trace\":", "\"hybrid_temporal\":"})
    EXPECT_NE(hybridPasses.find(pass), std::string::npos) << pass << " in " << hybridPasses;
  EXPECT_NE(postProcessPasses.find("\"dof_gather\":"), std::string::npos) << postProcessPasses;
  EXPECT_EQ(postProcessPasses.find("\"hybrid_trace\":"), std::string::npos) << postProcessPasses;
  for (const char* pass : {"\"visibility\":", "\"gbuffer\":", "\"gbuffer_shared\":"}) {
    EXPECT_EQ(hybridPasses.find(pass), std::string::npos) << pass << " in " << hybridPasses;
    EXPECT_EQ(postProcessPasses.find(pass), std::string::npos)
        << pass << " in " << postProcessPasses;
  }
}

TEST(Cli, BadQualityInputIsAOneLineError) {
  expectUsageError("quality --modes pinhole,blurry", "blurry");
  expectUsageError("quality --modes reference", "reference");
  expectUsageError("quality --rays 0", "--rays");
  expectUsageError("quality --reference /no/such/reference.png", "/no/such/reference.png");
  expectUsageError("quality --camera-path /no/such/path.json", "/no/such/path.json");
  expectUsageError("quality --camera-path " + kExamplePath + " --frames 2", "--frames");
}

TEST(Cli, BadBudgetIsAOneLineError) {
  for (const char* bad : {"0", "-5", "abc", "250,", ",250", "250,,1000", "1.5", "60001",
                          "99999999999999", "250;1000", "250, 1000"})
    expectUsageError(std::string("quality --budget-ms '") + bad + "'",
                     "is not a whole number of milliseconds from 1 to 60000");
  expectUsageError("quality --budget-ms 250,abc", "--budget-ms: 'abc'");
  expectUsageError("quality --budget-ms ''", "--budget-ms: ''");
  expectUsageError("quality --budget-ms 250 --camera-path " + kExamplePath, "--camera-path");
}

// Equal time on a small image: one line per mode and budget, both region masks and each budget's
// last frame written.
TEST(Cli, QualityEqualTimeBudgets) {
  auto out = tempDir() / "quality-budget";
  Result r = runHdof(
      "quality --scene builtin:dof --size 96x54 --f-number 1.4 --reference-spp 16 "
      "--modes postprocess,hybrid --budget-ms 50,80 --out " +
      out.string());
  ASSERT_EQ(r.exitCode, 0) << r.stderrText;
  for (const char* line : {"budget_ms=50 mode=postprocess frames=", "budget_ms=80 mode=postprocess",
                           "budget_ms=50 mode=hybrid rays_per_pixel=4 frames=",
                           "budget_ms=80 mode=hybrid", "edge band: "})
    EXPECT_NE(r.stdoutText.find(line), std::string::npos) << line << "\n" << r.stdoutText;
  size_t budgetLines = 0;
  for (size_t at = 0; (at = r.stdoutText.find("\nbudget_ms=", at)) != std::string::npos; ++at)
    ++budgetLines;
  EXPECT_EQ(budgetLines, 4u) << r.stdoutText;
  EXPECT_NE(r.stdoutText.find("psnr_edge_db="), std::string::npos) << r.stdoutText;
  EXPECT_TRUE(std::filesystem::exists(out / "edge-mask.png"));
  EXPECT_TRUE(std::filesystem::exists(out / "occlusion-mask.png"));
  for (const char* file : {"postprocess-50ms.png", "hybrid-80ms.png"})
    EXPECT_EQ(hdof::readImage((out / file).string()).width, 96u) << file;
  hdof::ImageRgba8 mask = hdof::readImage((out / "edge-mask.png").string());
  EXPECT_EQ(mask.width, 96u);
  EXPECT_EQ(mask.height, 54u);

  Result json = runHdof(
      "quality --scene builtin:dof --size 96x54 --f-number 1.4 --modes "
      "postprocess --budget-ms 20 --json --reference " +
      (out / "reference.png").string() + " --out " + out.string());
  ASSERT_EQ(json.exitCode, 0) << json.stderrText;
  for (const char* key : {"\"budgets\"", "\"budget_ms\": 20", "\"elapsed_ms\"", "\"psnr_edge_db\"",
                          "\"ssim_edge\"", "\"edge_pixels\""})
    EXPECT_NE(json.stdoutText.find(key), std::string::npos) << key << "\n" << json.stdoutText;
}

// A still measured twice, the second time against the first run's reference; then in motion.
TEST(Cli, QualityReusesAReferenceAndMeasuresInMotion) {
  auto out = tempDir() / "quality";
  std::string common =
      "quality --size 64x36 --f-number 1.4 --reference-spp 16 --out " + out.string();
  Result first = runHdof(common + " --modes pinhole");
  ASSERT_EQ(first.exitCode, 0) << first.stderrText;
  EXPECT_NE(first.stdoutText.find("mode=pinhole frames=1 psnr_db="), std::string::npos)
      << first.stdoutText;
  EXPECT_NE(first.stdoutText.find("psnr_edge_db="), std::string::npos) << first.stdoutText;
  EXPECT_TRUE(std::filesystem::exists(out / "edge-mask.png"));
  Result again =
      runHdof(common + " --modes postprocess --reference " + (out / "reference.png").string());
  ASSERT_EQ(again.exitCode, 0) << again.stderrText;
  EXPECT_NE(again.stdoutText.find("mode=postprocess frames=16 psnr_db="), std::string::npos)
      << again.stdoutText;
  Result wrongSize = runHdof("quality --size 32x18 --modes pinhole --reference " +
                             (out / "reference.png").string());
  EXPECT_EQ(wrongSize.exitCode, 2) << wrongSize.stderrText;

  Result motion =
      runHdof(common + " --modes postprocess,hybrid --frames 4 --camera-path " + kExamplePath);
  ASSERT_EQ(motion.exitCode, 0) << motion.stderrText;
  EXPECT_NE(motion.stdoutText.find("mode=postprocess"), std::string::npos) << motion.stdoutText;
  EXPECT_NE(motion.stdoutText.find("mode=hybrid"), std::string::npos) << motion.stdoutText;
  EXPECT_NE(motion.stdoutText.find("psnr_edge_db="), std::string::npos) << motion.stdoutText;
  for (int frame : {0, 1, 2, 3})
    EXPECT_TRUE(
        std::filesystem::exists(out / ("motion-reference-" + std::to_string(frame) + ".png")))
        << frame;
  EXPECT_TRUE(std::filesystem::exists(out / "motion-edge-mask-3.png"));

  // A path of one keyframe is a still view that the scene does not name: measured as a still
  // (equal time included), from that view, not the scene camera's.
  auto still = out / "still.json";
  std::ofstream(still) << R"({"keyframes": [{"position": [1.5, 1.2, 4], "target": [0, 0.5, 0]}]})";
  auto stillOut = out / "still";
  Result path = runHdof(common + " --modes postprocess --budget-ms 20 --camera-path " +
                        still.string() + " --out " + stillOut.string());
  ASSERT_EQ(path.exitCode, 0) << path.stderrText;
  EXPECT_NE(path.stdoutText.find("mode=postprocess frames=16 psnr_db="), std::string::npos)
      << path.stdoutText;
  EXPECT_NE(path.stdoutText.find("budget_ms=20 mode=postprocess"), std::string::npos)
      << path.stdoutText;
  hdof::ImageRgba8 sceneView = hdof::readImage((out / "reference.png").string());
  hdof::ImageRgba8 pathView = hdof::readImage((stillOut / "reference.png").string());
  EXPECT_NE(sceneView.pixels, pathView.pixels);
}

TEST(Cli, CorruptSceneFileIsAOneLineError) {
  auto path = tempDir() / "corrupt.gltf";
  std::ofstream(path) << "{ this is not json";
  expectUsageError("render --scene " + path.string() + " " + kOut, "corrupt.gltf");
  auto binary = tempDir() / "corrupt.glb";
  std::ofstream(binary) << "glTF\x02garbage";
  expectUsageError("render --scene " + binary.string() + " " + kOut, "corrupt.glb");
}

TEST(Cli, CompareErrors) {
  expectUsageError("compare /no/a.png /no/b.png", "/no/a.png");
  expectUsageError("compare onlyone.png", "");
}

TEST(Cli, HelpListsCommandsAndOptions) {
  Result top = runHdof("--help");
  EXPECT_EQ(top.exitCode, 0);
  for (const char* command : {"render", "compare", "bench"})
    EXPECT_NE(top.stdoutText.find(command), std::string::npos) << command;
  Result render = runHdof("render --help");
  EXPECT_EQ(render.exitCode, 0);
  for (const char* option : {"--scene", "--camera", "--mode", "--spp", "--size", "--focal-length",
                             "--sensor", "--f-number", "--focus-distance", "--no-pixel-jitter", "--out"})
    EXPECT_NE(render.stdoutText.find(option), std::string::npos) << option;
  // Each command's help gives its own default aperture.
  EXPECT_NE(render.stdoutText.find("(default 2.8;"), std::string::npos) << render.stdoutText;
  Result quality = runHdof("quality --help");
  EXPECT_NE(quality.stdoutText.find("(default 1.4;"), std::string::npos) << quality.stdoutText;
  EXPECT_EQ(runHdof("").exitCode, 2);
}

TEST(Cli, RenderWritesTheImageAndCompareReadsIt) {
  auto png = tempDir() / "pinhole.png";
  Result r = runHdof("render --scene builtin:dof --size 64x36 --out " + png.string());
  ASSERT_EQ(r.exitCode, 0) << r.stderrText;
  EXPECT_NE(r.stdoutText.find("pinhole.png"), std::string::npos);
  hdof::ImageRgba8 image = hdof::readImage(png.string());
  EXPECT_EQ(image.width, 64u);
  EXPECT_EQ(image.height, 36u);
  Result same = runHdof("compare " + png.string() + " " + png.string());
  EXPECT_EQ(same.exitCode, 0);
  EXPECT_NE(same.stdoutText.find("psnr_db=inf ssim=1.0000"), std::string::npos) << same.stdoutText;
}

}  // namespace
