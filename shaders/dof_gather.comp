// Post-process DoF (stage 2), gather (half resolution): scatter-as-gather (Jimenez 2014). Each
// pixel looks at a disc of rings as wide as its tile's largest CoC and asks, of every tap, how much
// of the tap's blur (its energy spread over its CoC disc, alpha = 1 / area) covers this pixel. Taps
// are presorted into two layers:
//   near: the nearest near-field layer around the tile (CoCs close to the dilated tile's nearest),
//         with its own radius: it spreads over what is behind it, in-focus pixels too (the
//         silhouette spread). Its opacity is the energy that covers the centre (the weights
//         times the area per tap), so a near object is also semi-transparent just inside its
//         silhouette, as a blurred edge is on both sides.
//   far: the rest, with the radius clamped to the centre's, so a blurred background never
//        spreads over sharper pixels in front of it; normalised. Where nothing behind the near
//        layer covers the centre, the taps' plain average fills the hole.
// A tile that is in focus throughout is copied.
#version 460
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 8, local_size_y = 8) in;

#include "lib/frame.glsl"
#include "lib/dof.glsl"
#include "lib/sampling.glsl"

layout(set = 1, binding = 1, rgba16f) uniform readonly image2D prefiltered;  // a: CoC
layout(set = 1, binding = 2, rg16f) uniform readonly image2D dilatedTiles;
layout(set = 1, binding = 3, rgba16f) uniform writeonly image2D farLayer;  // a: centre CoC
layout(set = 1, binding = 4, rgba16f) uniform writeonly image2D nearLayer;  // premultiplied

// Whether this pipeline serves an aperture of blades (frame.bladeCount 3 or more). The round
// aperture's is made without the polygon: with both behind a branch, a device that runs both
// sides under a mask paid for both (closeup focus pull, one thread: the step 5.6 -> 5.0 ms, with
// the near layer summed in every tile).
layout(constant_id = 0) const bool kBladed = false;

// A far tap's weight where it does not cover the centre: small against any covering tap's.
const float kHoleFill = 1e-4;

vec4 farSum = vec4(0.0);  // rgb * weight, weight
vec4 nearSum = vec4(0.0);
float centerRadius;
float centerInverseRadius;
float centerInverseArea;  // 1 / r^2; the pi cancels out of every weight
float nearestCoc;  // the dilated tile's
float inverseLayerDepth;  // 1 / how far behind the nearest CoC a tap is still near layer
float inverseRampWidth;  // 1 / the width of a disc's edge ramp (coverage)

// A tap at `distance` covers the centre where its disc (radius scaled by the aperture's shape in
// that direction) reaches it; the ramp is as wide as the tap spacing, so partial rings add up to
// the disc's area and the disc edge does not step from ring to ring. It is never wider than the
// disc: a nearly sharp tap covers its own pixel, not the ring around it (that would put an
// in-focus silhouette's colour into the blurred background around it, a halo). inverseRadius is
// 1 / radius (one division a tap serves both this and the tap's area).
float coverage(float radius, float inverseRadius, float distance) {
  return saturate((radius - distance) * maxOfPositive(inverseRampWidth, inverseRadius) + 0.5);
}

// Aperture blades: the distance to the edge of a regular polygon of unit circumradius, seen from
// its centre in direction `angle` (radians, y up); one vertex at the blade rotation.
float apertureBoundary(float angle) {
  float blades = frame.bladeCount;
  float sector = 2.0 * kPi / blades;
  float offset = fract((angle - frame.bladeRotation) / sector) - 0.5;
  return cos(kPi / blades) / cos(offset * sector);
}

// One tap at `angle` (radians, image space). The near layer is summed in every tile: where no
// near field is in reach every tap's nearness is 0.
void accumulate(vec4 tap, float distance, float angle) {
  float radius = halfResRadius(tap.a);
  float inverseRadius = 1.0 / radius;
  float inverseArea = inverseRadius * inverseRadius;
  // The tap's blur reaches this pixel along the opposite direction; in image space (y down) a
  // far-field blur is the aperture upright and a near-field one the aperture inverted.
  float farShape = kBladed ? apertureBoundary(kPi - angle) : 1.0;
  float near = nearness(tap.a) * saturate(2.0 - 2.0 * (tap.a - nearestCoc) * inverseLayerDepth);
  float farWeight = coverage(minOfPositive(radius, centerRadius) * farShape,
                             maxOfPositive(inverseRadius, centerInverseRadius) / farShape,
                             distance) *
                        maxOfPositive(inverseArea, centerInverseArea) + kHoleFill;
  farSum += vec4(tap.rgb, 1.0) * (farWeight * (1.0 - near));
  float nearShape = kBladed ? apertureBoundary(-angle) : 1.0;
  float nearCoverage = coverage(radius * nearShape, inverseRadius / nearShape, distance);
  nearSum += vec4(tap.rgb, 1.0) * (nearCoverage * inverseArea * near);
}

void gatherRings(ivec2 pixel, int rings, float spacing) {
  ivec2 last = halfImageSize() - 1;
  float turn = toUnitFloat(pcgHash(uint(pixel.x) * 7919u + uint(pixel.y) * 104729u));
  for (int ring = 1; ring <= rings; ++ring) {
    int count = 8 * ring;
    float step = 2.0 * kPi / float(count);
    vec2 rotation = vec2(cos(step), sin(step));
    // Odd and even rings are staggered by half a step, so taps do not line up radially, and the
    // kernel is turned per pixel: a small bright detail spread by a few taps shows as noise,
    // which the median removes, rather than as the kernel's pattern of rings.
    float angle = ((ring & 1) == 0 ? 0.5 : 0.0) * step + turn * step;
    vec2 direction = vec2(cos(angle), sin(angle));
    float radius = float(ring) * spacing;
    for (int i = 0; i < count; ++i) {
      ivec2 offset = ivec2(floor(direction * radius + 0.5));
      vec4 tap = imageLoad(prefiltered, clamp(pixel + offset, ivec2(0), last));
      // The rounded offset's own length: small kernels would blur more than they should with the
      // ring's radius, which rounds outwards.
      accumulate(tap, length(vec2(offset)), angle);
      direction = vec2(direction.x * rotation.x - direction.y * rotation.y,
                       direction.x * rotation.y + direction.y * rotation.x);
      angle += step;
    }
  }
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, halfImageSize()))) return;
  vec4 center = imageLoad(prefiltered, pixel);
  vec2 tile = imageLoad(dilatedTiles, tileOfHalfResPixel(pixel)).xy;
  float tileCoc = tile.x;
  if (tileCoc < kDofFocusZone) {
    imageStore(farLayer, pixel, center);
    imageStore(nearLayer, pixel, vec4(0.0));
    return;
  }
  int rings = gatherRings(tileCoc);
  float spacing = ringSpacing(tileCoc);
  inverseRampWidth = 1.0 / max(spacing, 1.0);
  centerRadius = halfResRadius(center.a);
  centerInverseRadius = 1.0 / centerRadius;
  centerInverseArea = centerInverseRadius * centerInverseRadius;
  nearestCoc = tile.y;
  inverseLayerDepth = 1.0 / max(2.0, 0.5 * abs(nearestCoc));
  accumulate(center, 0.0, 0.0);
  gatherRings(pixel, rings, spacing);

  // A polygon's area relative to its circumscribed circle's, for alpha = 1 / area.
  float blades = frame.bladeCount;
  float areaScale = kBladed ? blades / (2.0 * kPi) * sin(2.0 * kPi / blades) : 1.0;
  vec3 nearColor = nearSum.w > 0.0 ? nearSum.rgb / nearSum.w : vec3(0.0);
  // Area per tap over the polygon's: the near weights' sum becomes the covered fraction.
  float nearAlpha = saturate(nearSum.w * spacing * spacing / (4.0 * areaScale));
  // Deep inside a near object no far tap reaches: the near colour stands in for the far one.
  vec3 farColor = farSum.w > 0.0 ? farSum.rgb / farSum.w
                                 : (nearSum.w > 0.0 ? nearColor : center.rgb);
  imageStore(farLayer, pixel, vec4(farColor, center.a));
  imageStore(nearLayer, pixel, vec4(nearColor * nearAlpha, nearAlpha));
}
