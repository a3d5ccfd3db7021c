// The circle of confusion against values worked out by hand.
#include "render/camera.h"

#include <gtest/gtest.h>
#include <shared/frame.h>

namespace hdof {
namespace {

TEST(CircleOfConfusion, SensorFormulaMatchesHandComputedValues) {
  // 50 mm at f/2 (aperture 25 mm) focused at 2 m; a point at 1 m:
  // 25 mm * |1 - 2| / 1 * 50 / (2000 - 50) = 0.641 mm on the sensor.
  EXPECT_NEAR(gpu::cocOnSensor(1.0f, 0.05f, 2.0f, 2.0f), 0.025f * 0.05f / 1.95f, 1e-9f);
  EXPECT_NEAR(gpu::cocOnSensor(1.0f, 0.05f, 2.0f, 2.0f) * 1000.0f, 0.641f, 0.001f);
  // At 4 m: 25 mm * 2 / 4 * 50 / 1950 = 0.3205 mm. In focus: 0.
  EXPECT_NEAR(gpu::cocOnSensor(4.0f, 0.05f, 2.0f, 2.0f) * 1000.0f, 0.3205f, 0.0005f);
  EXPECT_EQ(gpu::cocOnSensor(2.0f, 0.05f, 2.0f, 2.0f), 0.0f);
}

TEST(CircleOfConfusion, PixelsAreSignedAndFollowTheSensorFormula) {
  // 50 mm at f/2 focused at 2 m on a full-frame sensor, a 3:2 image 1200 pixels wide: the field of
  // view is the lens's at infinity, so the pixel CoC is the sensor CoC * width / 36 mm times
  // (S - f) / S (the image distance at focus, fS / (S - f), is left out: no focus breathing).
  const float f = 0.05f, n = 2.0f, s = 2.0f;
  const uint32_t width = 1200, height = 800;
  Lens lens;
  lens.focalLengthMm = 50.0f;
  lens.fNumber = n;
  float focalPixels = focalLengthPixels(lens, width, height);
  EXPECT_NEAR(focalPixels, 50.0f * float(width) / 36.0f, 0.01f);
  for (float z : {0.5f, 1.0f, 3.0f, 10.0f, 1000.0f}) {
    float pixels = gpu::signedCocPixels(z, lens.apertureDiameter(), s, focalPixels);
    float expected = gpu::cocOnSensor(z, f, n, s) * float(width) / 0.036f * (s - f) / s;
    EXPECT_NEAR(std::abs(pixels), expected, expected * 1e-4f) << z;
    EXPECT_EQ(pixels < 0.0f, z < s) << "near field negative, far field positive at " << z;
  }
}

}  // namespace
}  // namespace hdof
