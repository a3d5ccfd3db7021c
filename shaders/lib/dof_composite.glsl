// Post-process DoF (stage 2), what the composite's passes share (dof_composite.comp for the
// tiles with full-resolution blurs, dof_composite_layers.comp for the others): their images, the
// tile lists they take their tiles from, and the half-resolution layers upsampled to a pixel.
// Each invocation does a 2x2 quad of pixels, whose bilinear footprints share the 3x3
// half-resolution pixels around it: 9 loads per layer instead of 16. A workgroup's 8x8 quads are
// one tile of kDofTileSize pixels.
#ifndef HDOF_LIB_DOF_COMPOSITE_GLSL
#define HDOF_LIB_DOF_COMPOSITE_GLSL
#include "lib/frame.glsl"
#include "lib/dof.glsl"
#include "lib/skippable.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 1, binding = 1, rgba16f) uniform readonly image2D colorCoc;  // sharp colour, CoC
layout(set = 1, binding = 3, rgba16f) uniform readonly image2D farLayer;  // a: CoC
layout(set = 1, binding = 4, rgba16f) uniform readonly image2D nearLayer;  // premultiplied
layout(set = 1, binding = 5, rg16f) uniform readonly image2D dilatedTiles;
layout(set = 1, binding = 6, rgba16f) uniform writeonly image2D result;
layout(set = 1, binding = 7, std430) readonly buffer TileLists {
  DofTileLists header;
  uint entries[];
} lists;

// A quad's pixels (clamped to the image) and the half-resolution layers around it.
struct CompositeQuad {
  ivec2 first;  // its top-left pixel
  vec3 sharp[4];
  float coc[4];
  float blur[4];  // halfResAmount of the CoC
  bool anyBlur;   // some pixel shows the half-resolution far layer
  bool withNear;  // the tile's dilated nearest CoC is in the near field: the near layer counts
  vec4 far[9];
  vec4 near[9];
};

// This invocation's quad, in its workgroup's tile of `list` (dof_tile_lists.comp).
ivec2 listedQuad(uint list) {
  ivec2 count = tileCount();
  uint entry = lists.entries[list * uint(count.x * count.y) + gl_WorkGroupID.x];
  ivec2 tile = ivec2(entry & 0xffffu, entry >> 16u);
  return tile * int(kDofTileSize / 2u) + ivec2(gl_LocalInvocationID.xy);
}

// layers: whether the half-resolution layers may show in the quad's tile (false: neither is
// loaded).
CompositeQuad loadQuad(ivec2 quad, bool layers) {
  CompositeQuad q;
  q.first = quad * 2;
  ivec2 size = ivec2(frame.imageSize);
  q.anyBlur = false;
  [[unroll]] for (int i = 0; i < 4; ++i) {
    ivec2 pixel = min(q.first + ivec2(i & 1, i >> 1), size - 1);
    vec4 texel = imageLoad(colorCoc, pixel);
    q.sharp[i] = texel.rgb;
    q.coc[i] = texel.a;
    q.blur[i] = halfResAmount(q.coc[i]);
    q.anyBlur = q.anyBlur || layers && q.blur[i] > 0.0;
  }
  q.withNear = layers && imageLoad(dilatedTiles, q.first / int(kDofTileSize)).y <= -kDofFocusZone;
  SKIPPABLE_IF(q.anyBlur || q.withNear) {
    ivec2 halfLast = halfImageSize() - 1;
    [[unroll]] for (int j = 0; j < 9; ++j) {
      ivec2 source = clamp(quad + ivec2(j % 3 - 1, j / 3 - 1), ivec2(0), halfLast);
      q.far[j] = imageLoad(farLayer, source);
      if (q.withNear) q.near[j] = imageLoad(nearLayer, source);
    }
  }
  return q;
}

// The half-resolution layers at pixel i of the quad: far, its colour and how much of the pixel it
// is (a); near, premultiplied. A pixel centre lies a quarter of a half-resolution pixel inside the
// 2x2 half-resolution pixels from offset to offset + 1 of the 3x3: bilinear weights 3/4 and 1/4.
void halfResLayers(CompositeQuad q, int i, out vec4 far, out vec4 near) {
  ivec2 offset = ivec2(i & 1, i >> 1);
  vec4 farSum = vec4(0.0);
  near = vec4(0.0);
  [[unroll]] for (int k = 0; k < 4; ++k) {
    ivec2 corner = ivec2(k & 1, k >> 1);
    int j = (offset.y + corner.y) * 3 + offset.x + corner.x;
    vec2 axes = mix(vec2(0.75), vec2(0.25), equal(corner, offset));
    float bilinear = axes.x * axes.y;
    if (q.anyBlur) {
      // Far colour only from half-resolution pixels of a similar CoC, so it neither brings
      // sharp colour into the blur nor blur across a depth edge.
      float weight = bilinear * cocSimilarity(q.far[j].a, q.coc[i]);
      farSum += vec4(q.far[j].rgb, 1.0) * weight;
    }
    if (q.withNear) near += q.near[j] * bilinear;
  }
  // Where no half-resolution pixel nearby has this pixel's CoC (a thin gap between in-focus
  // objects, which the downsample's nearest CoC closes), the sharp colour stands in.
  float amount = q.blur[i] * saturate(farSum.w * 4.0);
  far = vec4(amount > 0.0 ? farSum.rgb / farSum.w : vec3(0.0), amount);
}

// The far layer over what lies behind it (the sharp colour or its small blur).
vec3 overFarLayer(vec3 behind, vec4 far) {
  return far.a > 0.0 ? mix(behind, far.rgb, far.a) : behind;
}

// The near layer over everything, with its opacity (over in-focus pixels too: the blurred
// silhouette of a near object spreads).
void storeComposite(ivec2 pixel, vec3 background, vec4 near) {
  imageStore(result, pixel, vec4(background * (1.0 - near.a) + near.rgb, 1.0));
}

#endif
