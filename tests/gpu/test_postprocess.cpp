// The post-process depth of field: in-focus stays sharp, out-of-focus blurs, and a small bright
// light becomes a bokeh disc of its CoC's size (and of the aperture's shape).
#include "quality/occlusion_mask.h"
#include "render_fixture.h"

#include <gtest/gtest.h>
#include <shared/dof.h>
#include <glm/gtc/packing.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace hdof::test {
namespace {

// The pinhole and post-process frames of one view, with the sharp colour and the post-process
// output also read back in HDR.
class PostProcessRig {
 public:
  PostProcessRig(const std::string& sceneSpec, uint32_t width, uint32_t height)
      : scene_(testScene(sceneSpec)),
        // Made for another size, as a session's is before its viewport changes.
        pipeline_(testContext(), scene_.scene, *scene_.gpu, width / 2 + 1, height / 2 + 1) {
    pipeline_.resize(width, height);
    request_.camera = Camera::fromScene(scene_.scene.cameras.front());
    request_.settings.width = width;
    request_.settings.height = height;
    suggestedFocus_ = scene_.scene.cameras.front().focusDistance.value_or(5.0f);
  }

  struct Frame {
    ImageRgba8 sharp;    // the G-buffer colour, tonemapped: the pinhole image
    ImageRgba8 blurred;  // the post-process output, tonemapped
    std::vector<glm::vec3> sharpHdr, blurredHdr;
    std::vector<std::pair<std::string, double>> passMs;  // the post-process's steps
    double wallMs = 0.0;  // the post-process frame's submission, as the CPU saw it
  };

  // lens.focusDistance 0: the scene camera's suggestion. frames: how many frames of the still
  // view the post-process renders (its raster averaging a sample more each), the last one read.
  Frame render(Lens lens, int frames = 1) {
    if (lens.focusDistance <= 0.0f) lens.focusDistance = suggestedFocus_;
    lens = onSceneCameraSensor(lens, scene_.scene.cameras.front(), request_.settings.width,
                               request_.settings.height);
    request_.lens = lens;
    uniforms = makeFrameUniforms(scene_.scene, request_.camera, lens, request_.settings);
    Frame frame;
    request_.mode = RenderMode::PostProcess;
    pipeline_.resetHistory();
    FrameStats stats;
    for (int i = 0; i < frames; ++i) stats = pipeline_.render(request_);
    for (const auto& pass : stats.passMs)
      if (pass.first.starts_with("dof_")) frame.passMs.push_back(pass);
    frame.wallMs = stats.wallMs;
    frame.blurred = pipeline_.image();
    frame.blurredHdr = rgb(readImage(pipeline_.images().dof.output));
    frame.sharpHdr = rgb(readImage(pipeline_.images().gbuffer.color));
    // The same raster sample as the post-process's, not the anti-aliasing's next one.
    request_.mode = RenderMode::Pinhole;
    pipeline_.resetHistory();
    pipeline_.render(request_);
    frame.sharp = pipeline_.image();
    return frame;
  }

  gpu::FrameUniforms uniforms{};
  const FrameImages& images() const { return pipeline_.images(); }

 private:
  static std::vector<glm::vec3> rgb(const std::vector<glm::vec4>& texels) {
    return std::vector<glm::vec3>(texels.begin(), texels.end());
  }

  SceneOnGpu& scene_;
  FramePipeline pipeline_;
  FrameRequest request_;
  float suggestedFocus_ = 5.0f;
};

float luminance(const glm::vec3& c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

double totalLuminance(const std::vector<glm::vec3>& pixels) {
  double sum = 0.0;
  for (const glm::vec3& p : pixels) sum += luminance(p);
  return sum;
}

struct BrightRegion {
  float width = 0.0f, height = 0.0f;  // extent, pixels
  float area = 0.0f;                  // pixels
  float plateau = 0.0f;               // median luminance of the disc's inner part
  float peak = 0.0f;
};

// The region brighter than half the disc's typical luminance, the disc centred on the brightest
// pixel and about expectedRadius wide.
BrightRegion measureBokeh(const std::vector<glm::vec3>& hdr, uint32_t width, uint32_t height,
                          float expectedRadius) {
  std::vector<float> lum(hdr.size());
  for (size_t i = 0; i < hdr.size(); ++i) lum[i] = luminance(hdr[i]);
  size_t peakIndex = std::max_element(lum.begin(), lum.end()) - lum.begin();
  glm::vec2 center(float(peakIndex % width), float(peakIndex / width));
  std::vector<float> inner;
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x)
      if (glm::length(glm::vec2(x, y) - center) < 0.6f * expectedRadius)
        inner.push_back(lum[y * width + x]);
  std::nth_element(inner.begin(), inner.begin() + inner.size() / 2, inner.end());
  BrightRegion region;
  region.plateau = inner[inner.size() / 2];
  region.peak = lum[peakIndex];
  int x0 = int(width), x1 = -1, y0 = int(height), y1 = -1;
  for (uint32_t y = 0; y < height; ++y) {
    for (uint32_t x = 0; x < width; ++x) {
      if (lum[y * width + x] < 0.5f * region.plateau) continue;
      x0 = std::min(x0, int(x)), x1 = std::max(x1, int(x));
      y0 = std::min(y0, int(y)), y1 = std::max(y1, int(y));
      region.area += 1.0f;
    }
  }
  region.width = float(x1 - x0 + 1);
  region.height = float(y1 - y0 + 1);
  return region;
}

constexpr uint32_t kWidth = 640, kHeight = 360;

TEST(PostProcess, InFocusWallStaysSharp) {
  // The wall is square-on at the focus distance: every CoC is zero, so the output must be the
  // sharp colour, however wide the aperture. An odd size checks the half-resolution edges.
  const Lens lens{50.0f, 1.4f, 3.0f};
  PostProcessRig rig("builtin:wall", 321, 181);
  PostProcessRig::Frame frame = rig.render(lens);
  RenderSpec pinhole;
  pinhole.scene = "builtin:wall";
  pinhole.width = 321;
  pinhole.height = 181;
  pinhole.lens = lens;
  EXPECT_GE(compareImages(frame.blurred, renderImage(pinhole)).psnrDb, 45.0);
  EXPECT_GE(compareImages(frame.blurred, frame.sharp).psnrDb, 45.0);
}

// builtin:wall, square-on 3 m away, through lenses focused nearer so that the wall's CoC is a
// given size, and its thin-lens references.
class WallOutOfFocus {
 public:
  static constexpr uint32_t kWidth = 320, kHeight = 180;

  WallOutOfFocus() { rig.render(Lens{50.0f, 1.4f, 3.0f}); }  // for the frame uniforms

  Lens lens(float coc) const {
    Lens lens{50.0f, 1.4f, 3.0f};
    lens.focusDistance =
        1.0f / (1.0f / 3.0f + coc / (lens.apertureDiameter() * rig.uniforms.focalLengthPixels));
    return lens;
  }

  static ImageRgba8 reference(const Lens& lens, uint32_t raysPerPixel) {
    RenderSpec spec;
    spec.scene = "builtin:wall";
    spec.width = kWidth;
    spec.height = kHeight;
    spec.lens = lens;
    spec.mode = RenderMode::Reference;
    spec.raysPerPixel = raysPerPixel;
    return renderImage(spec);
  }

  PostProcessRig rig{"builtin:wall", kWidth, kHeight};
};

// A surface just out of focus (a CoC under a pixel or two) is softer than the raster already: a
// pixel's neighbours take a third of it at a 1 px CoC. The post-process's first frame shows that
// softness, not the raster's sharp colour.
TEST(PostProcess, ASurfaceJustOutOfFocusIsAsSoftAsTheLensMakesIt) {
  WallOutOfFocus wall;
  for (float coc : {0.5f, 1.0f, 2.0f}) {
    Lens lens = wall.lens(coc);
    PostProcessRig::Frame frame = wall.rig.render(lens);
    ImageRgba8 reference = WallOutOfFocus::reference(lens, 64);
    double sharp = compareImages(frame.sharp, reference).psnrDb;
    double blurred = compareImages(frame.blurred, reference).psnrDb;
    std::printf("CoC %.1f px: the raster %.2f dB, the post-process %.2f dB\n", coc, sharp, blurred);
    EXPECT_GT(blurred, sharp + 1.0) << "CoC " << coc;
  }
}

// Once the raster averages its samples over each pixel (a box filter, as the reference's jittered
// rays), a blur under 3 px adds the lens's disc and no second box: after a still view's 16
// frames a wall just out of focus is as sharp as the reference, not softer.
TEST(PostProcess, AStillViewJustOutOfFocusConvergesToTheLensBlur) {
  WallOutOfFocus wall;
  for (float coc : {1.0f, 2.0f}) {
    Lens lens = wall.lens(coc);
    PostProcessRig::Frame still = wall.rig.render(lens, 16);
    double psnr = compareImages(still.blurred, WallOutOfFocus::reference(lens, 256)).psnrDb;
    std::printf("CoC %.1f px: the post-process after 16 frames %.2f dB\n", coc, psnr);
    // With the disc integrated over pixel cells, which counts the box twice more: 43.3 and 42.9 dB.
    EXPECT_GE(psnr, 45.0) << "CoC " << coc;
  }
}

// Beside a near object's silhouette whose blur is small, the farther surface behind it shows
// through the blurred edge. In builtin:dof wide open a post (CoC -3.3 px) stands in front of the
// floor (-2.1 px); with the floor counted as the post's own surface (a tap counted as behind
// only at half the CoC), the post's edges stayed opaque: 28.42 dB over the occlusion region.
TEST(PostProcess, TheSurfaceBehindASmallNearBlurShowsThroughItsEdges) {
  RenderSpec spec;
  spec.width = 640;
  spec.height = 360;
  spec.lens.fNumber = 1.4f;
  ImageRgba8 region = maskImage(occlusionRegion(spec), spec.width, spec.height);
  ImageRgba8 reference = renderImage(spec, RenderMode::Reference, 128);
  double psnr =
      compareImages(renderImage(spec, RenderMode::PostProcess), reference, &region).psnrDb;
  std::printf("occlusion region, first frame: %.2f dB\n", psnr);
  EXPECT_GE(psnr, 28.7);
}

TEST(PostProcess, OutOfFocusBlurs) {
  PostProcessRig rig("builtin:dof", 320, 180);
  PostProcessRig::Frame frame = rig.render(Lens{50.0f, 1.4f, 0.0f});
  double psnr = compareImages(frame.blurred, frame.sharp).psnrDb;
  EXPECT_LT(psnr, 32.0) << "near and far objects blur";
  EXPECT_GT(psnr, 15.0) << "but the image is still the same scene";
}

// The 2 cm light at 10 m with focus at 2 m: a disc whose diameter is the CoC at 10 m, with the
// light's energy. Returns the disc's area.
float expectBokehDisc(float fNumber, uint32_t blades) {
  PostProcessRig rig("builtin:bokeh", kWidth, kHeight);
  Lens lens{100.0f, fNumber, 2.0f, blades, 0.0f};
  PostProcessRig::Frame frame = rig.render(lens);
  float coc = std::abs(
      gpu::signedCocPixels(10.0f, lens.apertureDiameter(), 2.0f, rig.uniforms.focalLengthPixels));
  BrightRegion disc = measureBokeh(frame.blurredHdr, kWidth, kHeight, 0.5f * coc);
  SCOPED_TRACE("f/" + std::to_string(fNumber) + ", " + std::to_string(blades) + " blades, CoC " +
               std::to_string(coc) + " px, disc " + std::to_string(disc.width) + " x " +
               std::to_string(disc.height) + " px");
  EXPECT_NEAR(disc.width, coc, 0.25f * coc);
  EXPECT_NEAR(disc.height, coc, 0.25f * coc);
  // Filled, not a ring of dots: most of the disc is bright.
  EXPECT_GT(disc.area, 0.6f * 3.14159f * 0.25f * disc.width * disc.height);
  // No sharp speck left where the light is.
  EXPECT_LT(disc.peak, 4.0f * disc.plateau);
  // Spread, not made or lost: the image holds the light it held.
  EXPECT_NEAR(totalLuminance(frame.blurredHdr) / totalLuminance(frame.sharpHdr), 1.0, 0.15);
  return disc.area;
}

TEST(PostProcess, SmallBrightLightBecomesADiscOfItsCoc) {
  expectBokehDisc(1.0f, 0);
  expectBokehDisc(0.5f, 0);
}

TEST(PostProcess, ApertureBladesShapeTheBokeh) {
  float circle = expectBokehDisc(0.5f, 0);
  float hexagon = expectBokehDisc(0.5f, 6);
  // A hexagon inscribed in the circle covers 3 sqrt(3) / (2 pi) = 0.83 of it.
  EXPECT_NEAR(hexagon / circle, 0.83f, 0.1f);
}

// Width and height of the pixels brighter than `threshold` (HDR luminance).
glm::vec2 brightExtent(const std::vector<glm::vec3>& hdr, uint32_t width, float threshold) {
  int x0 = int(width), x1 = -1, y0 = int(hdr.size()), y1 = -1;
  for (size_t i = 0; i < hdr.size(); ++i) {
    if (luminance(hdr[i]) <= threshold) continue;
    int x = int(i % width), y = int(i / width);
    x0 = std::min(x0, x), x1 = std::max(x1, x);
    y0 = std::min(y0, y), y1 = std::max(y1, y);
  }
  return glm::vec2(float(x1 - x0 + 1), float(y1 - y0 + 1));
}

TEST(PostProcess, ABrightLightSlightlyOutOfFocusKeepsItsSize) {
  // The light's blur is 2.5-5 px, behind the focus and in front of it: the half-resolution
  // layers' round trip (downsample, gather ramp, upsample) would widen it by as much, and a light
  // 20000 times brighter than the wall shows every bit of that spread as white.
  PostProcessRig rig("builtin:bokeh", kWidth, kHeight);
  const Lens lenses[] = {{100.0f, 4.0f, 2.0f},
                         {100.0f, 5.6f, 2.0f},
                         {100.0f, 8.0f, 2.0f},
                         {100.0f, 0.7f, 30.0f},
                         {100.0f, 1.0f, 30.0f}};
  for (const Lens& lens : lenses) {
    PostProcessRig::Frame frame = rig.render(lens);
    float coc = std::abs(gpu::signedCocPixels(10.0f, lens.apertureDiameter(), lens.focusDistance,
                                              rig.uniforms.focalLengthPixels));
    float light = 2.0f * 0.02f / 10.0f * rig.uniforms.focalLengthPixels;
    glm::vec2 sharp = brightExtent(frame.sharpHdr, kWidth, 1.0f);
    glm::vec2 blurred = brightExtent(frame.blurredHdr, kWidth, 1.0f);
    SCOPED_TRACE("f/" + std::to_string(lens.fNumber) + ", focus " +
                 std::to_string(lens.focusDistance) + " m: CoC " + std::to_string(coc) +
                 " px, light " + std::to_string(light) + " px, sharp " + std::to_string(sharp.x) +
                 " px, blurred " + std::to_string(blurred.x) + " x " + std::to_string(blurred.y) +
                 " px");
    EXPECT_GT(blurred.x, sharp.x) << "the light blurs";
    EXPECT_LE(blurred.x, coc + light + 1.5f);
    EXPECT_LE(blurred.y, coc + light + 1.5f);
  }
}

// Background pixels beside an in-focus silhouette: blurred (|CoC| of at least 3 px) and between
// nearest and farthest pixels from a pixel in focus that is at least 20% nearer.
std::vector<uint8_t> besideInFocusSilhouettes(const std::vector<float>& depth, uint32_t width,
                                              uint32_t height, const CocParameters& coc,
                                              int nearest, int farthest) {
  auto cocAt = [&](size_t i) {
    return gpu::signedCocPixels(depth[i], coc.apertureDiameter, coc.focusDistance,
                                coc.focalLengthPixels);
  };
  std::vector<uint8_t> band(depth.size(), 0);
  for (int y = 0; y < int(height); ++y)
    for (int x = 0; x < int(width); ++x) {
      size_t i = size_t(y) * width + x;
      if (std::abs(cocAt(i)) < 3.0f) continue;
      int closest = farthest + 1;
      for (int dy = -farthest; dy <= farthest; ++dy)
        for (int dx = -farthest; dx <= farthest; ++dx) {
          int px = x + dx, py = y + dy;
          if (px < 0 || py < 0 || px >= int(width) || py >= int(height)) continue;
          size_t j = size_t(py) * width + px;
          int distance = std::max(std::abs(dx), std::abs(dy));
          if (std::abs(cocAt(j)) < gpu::kDofFocusZone && depth[j] < 0.8f * depth[i])
            closest = std::min(closest, distance);
        }
      band[i] = closest >= nearest && closest <= farthest ? 255 : 0;
    }
  return band;
}

double meanAbsoluteError(const ImageRgba8& a, const ImageRgba8& b,
                         const std::vector<uint8_t>& mask) {
  double sum = 0.0;
  size_t count = 0;
  for (size_t i = 0; i < mask.size(); ++i) {
    if (!mask[i]) continue;
    for (int c = 0; c < 3; ++c)
      sum += std::abs(int(a.pixels[i * 4 + c]) - int(b.pixels[i * 4 + c]));
    count += 3;
  }
  return count ? sum / double(count) : 0.0;
}

// The living room's closeup at 480x270 (f/1.4, focus 2.4 m), its depth and its lens's CoC.
struct CloseupView {
  RenderSpec spec;
  std::vector<float> depth;
  CocParameters coc;
};

CloseupView closeupView() {
  CloseupView view;
  view.spec.scene = kLivingRoom;
  view.spec.camera = "closeup";
  view.spec.width = 480;
  view.spec.height = 270;
  view.spec.lens = Lens{50.0f, 1.4f, 2.4f};
  FrameRequest request;
  view.depth = renderDepth(view.spec, &request);
  view.coc = cocParameters(request.lens, view.spec.width, view.spec.height);
  return view;
}

// The blurred background 2-4 px beside the in-focus bottle and table of the living room holds no
// colour of them (a halo).
TEST(PostProcess, NoHaloAroundInFocusSilhouettes) {
  auto [spec, depth, coc] = closeupView();
  std::vector<uint8_t> beside = besideInFocusSilhouettes(depth, spec.width, spec.height, coc, 2, 4);
  std::vector<uint8_t> further =
      besideInFocusSilhouettes(depth, spec.width, spec.height, coc, 6, 9);
  // Where a blurred near object covers them, the post-process must invent what is hidden: that
  // is the partial-occlusion region's error, not a halo.
  std::vector<uint8_t> occluded = occlusionRegion(spec);
  for (size_t i = 0; i < occluded.size(); ++i)
    if (occluded[i]) beside[i] = further[i] = 0;
  ASSERT_GT(maskCount(beside), 200u);
  ASSERT_GT(maskCount(further), 200u);
  spec.mode = RenderMode::Reference;
  spec.raysPerPixel = 64;
  ImageRgba8 reference = renderImage(spec);
  spec.mode = RenderMode::PostProcess;
  spec.frames = 16;
  ImageRgba8 postProcess = renderImage(spec);
  double besideError = meanAbsoluteError(postProcess, reference, beside);
  double furtherError = meanAbsoluteError(postProcess, reference, further);
  std::printf("beside in-focus silhouettes: %.2f, further out: %.2f (mean absolute error, 8 bit)\n",
              besideError, furtherError);
  // With the bottle's colour gathered into the background around it this error was 5.3; with the
  // pixels beside the silhouettes (which hold some of its colour) blurred as background, 1.7;
  // what is left (about 0.6) is mostly the background hidden behind the silhouettes, which the
  // reference sees through the lens and a post-process has to invent.
  EXPECT_LT(besideError, 1.0);
  EXPECT_LT(furtherError, besideError);
}

// The view's in-focus pixels within `reach` pixels (along a row or column) of a wide near-field
// blur (CoC -9 px or more).
std::vector<uint8_t> besideWideNearBlur(const CloseupView& view, int reach) {
  const RenderSpec& spec = view.spec;
  int width = int(spec.width), height = int(spec.height);
  auto cocAt = [&](int x, int y) {
    x = std::clamp(x, 0, width - 1);
    y = std::clamp(y, 0, height - 1);
    return gpu::signedCocPixels(view.depth[size_t(y) * width + x], view.coc.apertureDiameter,
                                view.coc.focusDistance, view.coc.focalLengthPixels);
  };
  std::vector<uint8_t> beside(view.depth.size(), 0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      if (std::abs(cocAt(x, y)) >= gpu::kDofFocusZone) continue;
      for (int d = 1; d <= reach; ++d)
        for (glm::ivec2 step :
             {glm::ivec2(d, 0), glm::ivec2(-d, 0), glm::ivec2(0, d), glm::ivec2(0, -d)})
          if (cocAt(x + step.x, y + step.y) <= -gpu::kDofHalfResCoc)
            beside[size_t(y) * width + x] = 255;
    }
  return beside;
}

// The in-focus pixels beside a widely blurred near object hold none of its colour sharp under its
// blur (an outline of the object inside the blur): the raster's averaged samples give such a
// pixel some of the object's colour under the background's depth.
TEST(PostProcess, NoOutlineOfANearObjectInsideItsBlur) {
  CloseupView view = closeupView();
  std::vector<uint8_t> beside = besideWideNearBlur(view, 1);
  ASSERT_GT(maskCount(beside), 100u);
  ImageRgba8 reference = renderImage(view.spec, RenderMode::Reference, 64);
  ImageRgba8 postProcess = renderImage(view.spec, RenderMode::PostProcess, 1, 16);
  double error = meanAbsoluteError(postProcess, reference, beside);
  std::printf("in focus beside a wide near blur: %zu pixels, mean absolute error %.2f\n",
              maskCount(beside), error);
  // 7.6 with the near colour left in those pixels, 5.9 without it.
  EXPECT_LT(error, 6.7);
}

// ... nor in motion: there the anti-aliasing's history of such a pixel trails the near object's
// colour, which its neighbourhood (the object's own pixels beside it) no longer bounds.
TEST(PostProcess, NoOutlineOfANearObjectInsideItsBlurInMotion) {
  CloseupView view = closeupView();
  std::vector<uint8_t> beside = besideWideNearBlur(view, 2);
  ASSERT_GT(maskCount(beside), 200u);
  ImageRgba8 reference = renderImage(view.spec, RenderMode::Reference, 64);
  SceneOnGpu& scene = testScene(view.spec.scene);
  FramePipeline pipeline(testContext(), scene.scene, *scene.gpu, view.spec.width, view.spec.height);
  FrameRequest request = requestFor(view.spec, scene.scene);
  request.mode = RenderMode::PostProcess;
  renderTruckOnto(pipeline, request, 13, 0.004f);
  double error = meanAbsoluteError(pipeline.image(), reference, beside);
  std::printf("in focus within 2 px of a wide near blur, in motion: %zu pixels, error %.2f\n",
              maskCount(beside), error);
  // 7.5 with the near object's pixels bounding the history, 4.8 without them.
  EXPECT_LT(error, 6.0);
}

// A bright near light a little out of focus (CoC 5-9 px) is a round disc of its CoC's size, as
// the lens makes it: around the light, as far as its blur reaches, the post-process holds the
// reference's colour. Blurred over the half-resolution layers for most of that range, the disc
// was larger and a rounded square (the HDR light saturates even the layers' small share).
TEST(PostProcess, ASlightlyBlurredNearLightIsARoundDisc) {
  RenderSpec spec;  // builtin:dof, looking at its nearest light, with a CoC of about -5.5 px
  spec.width = 480;
  spec.height = 270;
  spec.lens = Lens{50.0f, 0.9f, 4.0f};
  spec.eye = glm::vec3(0.0f, 1.25f, 0.0f);
  spec.target = glm::vec3(-0.7f, 1.45f, -1.8f);
  FrameRequest request;
  std::vector<float> depth = renderDepth(spec, &request);
  CocParameters coc = cocParameters(request.lens, spec.width, spec.height);
  ImageRgba8 sharp = renderImage(spec);
  // The light's pixels (white in the sharp image, their CoC in that range), and a box around
  // them as wide as their blur reaches.
  int width = int(spec.width), height = int(spec.height);
  glm::ivec2 low(width, height), high(-1);
  int reach = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      size_t i = size_t(y) * width + x;
      float c = gpu::signedCocPixels(depth[i], coc.apertureDiameter, coc.focusDistance,
                                     coc.focalLengthPixels);
      bool white = sharp.pixels[i * 4] >= 250 && sharp.pixels[i * 4 + 1] >= 250 &&
                   sharp.pixels[i * 4 + 2] >= 250;
      if (!white || c > -gpu::kDofWideCoc || c <= -gpu::kDofHalfResCoc) continue;
      low = glm::min(low, glm::ivec2(x, y));
      high = glm::max(high, glm::ivec2(x, y));
      reach = std::max(reach, int(std::ceil(-c)));
    }
  ASSERT_GT(high.x - low.x, 4);
  std::vector<uint8_t> around(depth.size(), 0);
  for (int y = std::max(low.y - reach, 0); y <= std::min(high.y + reach, height - 1); ++y)
    for (int x = std::max(low.x - reach, 0); x <= std::min(high.x + reach, width - 1); ++x)
      around[size_t(y) * width + x] = 255;
  ImageRgba8 reference = renderImage(spec, RenderMode::Reference, 128);
  ImageRgba8 postProcess = renderImage(spec, RenderMode::PostProcess, 1, 16);
  double error = meanAbsoluteError(postProcess, reference, around);
  std::printf("around the near light: %zu pixels, mean absolute error %.2f\n", maskCount(around),
              error);
  // 10.8 with the disc a rounded square (full-resolution blurs up to 5 px), 4.3 round.
  EXPECT_LT(error, 7.0);
}

// The composite's tile lists: every tile once; a tile handed to the pass of the layers alone has
// no pixel whose blur is in the range of the full-resolution blurs nor, with a near field in
// reach, a small near blur within the 3 pixels around it that the composite reads; of the tiles
// with full-resolution blurs, the near lists' alone have a near field in reach, the narrow
// list's pixels have blurs that read only the pixels next to their quad, and the wide and near
// lists' blurs (and, for the near list, the near blurs within 3 pixels) read no more than 2.
TEST(PostProcess, EachTileGoesToTheListOfTheBlursItNeeds) {
  PostProcessRig rig("builtin:dof", kWidth, kHeight);
  std::array<int, gpu::kDofListCount> tilesOf{};
  // At f/1.0 the wall is 4 px wide blurs, at f/0.7 about 6.
  for (float fNumber : {8.0f, 2.8f, 1.4f, 1.0f, 0.7f}) {
    rig.render(Lens{50.0f, fNumber, 0.0f});
    const DofImages& dof = rig.images().dof;
    std::vector<glm::vec4> colorCoc = readImage(dof.colorCoc);
    std::vector<glm::vec4> dilated = readImage(dof.dilatedTiles);
    int tilesX = int(dof.tiles.width()), tilesY = int(dof.tiles.height());
    size_t tileCount = size_t(tilesX) * tilesY;
    gpu::Buffer lists(testContext(), dof.tileLists.size(), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                      gpu::MemoryUse::Readback, "test tile lists");
    testContext().submitAndWait([&](VkCommandBuffer cmd) {
      gpu::copyBufferToHost(cmd, dof.tileLists, lists, lists.size());
    });
    gpu::DofTileLists header;
    std::memcpy(&header, lists.mapped(), sizeof(header));
    const auto* entries = reinterpret_cast<const uint32_t*>(
        static_cast<const char*>(lists.mapped()) + sizeof(header));
    std::vector<int> listed(tileCount, 0);
    for (uint32_t list = 0; list < gpu::kDofListCount; ++list) {
      const gpu::DofTileList& arguments = header.lists[list];
      ASSERT_LE(arguments.groupsX, tileCount);
      EXPECT_EQ(arguments.groupsY * arguments.groupsZ, 1u);
      tilesOf[list] += int(arguments.groupsX);
      for (uint32_t i = 0; i < arguments.groupsX; ++i) {
        uint32_t entry = entries[list * tileCount + i];
        int tx = int(entry & 0xffff), ty = int(entry >> 16);
        ASSERT_LT(tx, tilesX);
        ASSERT_LT(ty, tilesY);
        ++listed[size_t(ty) * tilesX + tx];
        bool nearInReach = dilated[size_t(ty) * tilesX + tx].y <= -gpu::kDofFocusZone;
        if (list != gpu::kDofListLayers) {
          EXPECT_EQ(nearInReach, list == gpu::kDofListNear || list == gpu::kDofListNearWider)
              << "f/" << fNumber << " tile " << tx << "," << ty << " list " << list;
        }
        int tile = int(gpu::kDofTileSize);
        for (int y = ty * tile - 3; y < (ty + 1) * tile + 3; ++y)
          for (int x = tx * tile - 3; x < (tx + 1) * tile + 3; ++x) {
            if (x < 0 || y < 0 || x >= int(kWidth) || y >= int(kHeight)) continue;
            float coc = colorCoc[size_t(y) * kWidth + x].a;
            bool inTile =
                x >= tx * tile && x < (tx + 1) * tile && y >= ty * tile && y < (ty + 1) * tile;
            if (list == gpu::kDofListNarrow && inTile) {
              EXPECT_LT(std::abs(coc), gpu::kDofNarrowCoc)
                  << "f/" << fNumber << " " << x << "," << y;
              EXPECT_GT(coc, gpu::kDofNarrowNearCoc) << "f/" << fNumber << " " << x << "," << y;
            }
            bool wider = std::abs(coc) >= gpu::kDofWideCoc && std::abs(coc) < gpu::kDofHalfResCoc;
            if (list == gpu::kDofListWide || list == gpu::kDofListNear) {
              EXPECT_FALSE(inTile && wider) << "f/" << fNumber << " " << x << "," << y;
            }
            if (list == gpu::kDofListNear) {
              EXPECT_FALSE(wider && coc < 0.0f) << "f/" << fNumber << " " << x << "," << y;
            }
            if (list != gpu::kDofListLayers) continue;
            EXPECT_FALSE(inTile && std::abs(coc) >= gpu::kDofSubPixelBlurCoc &&
                         std::abs(coc) < gpu::kDofHalfResCoc)
                << "f/" << fNumber << " pixel " << x << "," << y << " CoC " << coc;
            EXPECT_FALSE(nearInReach && coc <= -gpu::kDofFocusZone && coc > -gpu::kDofHalfResCoc)
                << "f/" << fNumber << " pixel " << x << "," << y << " CoC " << coc;
          }
      }
    }
    for (int count : listed) EXPECT_EQ(count, 1);
  }
  for (uint32_t list = 0; list < gpu::kDofListCount; ++list)
    EXPECT_GT(tilesOf[list], 0) << "list " << list;
}

// Not a test of speed (that is for benchmarks): prints each pass's GPU time at 640x360.
TEST(PostProcess, ReportsEveryPassTime) {
  PostProcessRig rig("builtin:dof", kWidth, kHeight);
  constexpr int kFrames = 10;
  for (float fNumber : {2.8f, 1.4f}) {
    std::vector<std::pair<std::string, std::vector<double>>> times;  // in recording order
    std::vector<double> wallMs;
    for (int frame = 0; frame <= kFrames; ++frame) {
      PostProcessRig::Frame result = rig.render(Lens{50.0f, fNumber, 0.0f});
      if (frame == 0) continue;  // shader compilation
      times.resize(result.passMs.size());
      for (size_t i = 0; i < result.passMs.size(); ++i) {
        times[i].first = result.passMs[i].first;
        times[i].second.push_back(result.passMs[i].second);
      }
      wallMs.push_back(result.wallMs);
    }
    EXPECT_EQ(times.size(), 14u);
    auto median = [](std::vector<double>& values) {
      std::sort(values.begin(), values.end());
      return values[values.size() / 2];
    };
    double total = 0.0;
    std::printf("builtin:dof %ux%u f/%.1f, median of %d frames:\n", kWidth, kHeight, fNumber,
                kFrames);
    for (auto& [name, ms] : times) {
      total += median(ms);
      std::printf("  %-24s %6.2f ms\n", name.c_str(), median(ms));
    }
    std::printf("  %-24s %6.2f ms (wall clock of the frame: %.2f ms)\n", "sum", total,
                median(wallMs));
  }
}

}  // namespace
}  // namespace hdof::test
