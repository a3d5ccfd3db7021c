// Post-process DoF (stage 2), CoC and downsample: the signed CoC of every pixel beside its colour
// (full resolution, for the tiles and the composite), and colour and CoC at half resolution. The
// CoC of a 2x2 block is its nearest, so near silhouettes grow rather than shrink; colours are
// weighted by how close their CoC is to it, so in-focus colour does not bleed into the blur of a
// near object. A background pixel beside a sharper, nearer one (an in-focus silhouette) takes its
// |CoC| when smaller: the raster averages its samples over the pixel, so its colour holds some of
// the silhouette's, while its depth is one sample's; blurred as background it would spread the
// silhouette's colour around it (a halo). The background's blur stops a pixel short instead.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
layout(local_size_x = 8, local_size_y = 8) in;

#include "lib/frame.glsl"
#include "lib/dof.glsl"

layout(set = 1, binding = 1, rgba16f) uniform readonly image2D color;
layout(set = 1, binding = 2, rgba32f) uniform readonly image2D normalDepth;
layout(set = 1, binding = 3, rgba16f) uniform writeonly image2D colorCoc;  // a: CoC
layout(set = 1, binding = 4, rgba16f) uniform writeonly image2D halfColorCoc;  // a: CoC

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, imageSize(halfColorCoc)))) return;
  ivec2 size = ivec2(frame.imageSize);
  // The CoCs of the 4x4 pixels around the block (its 2x2 and the pixels beside them; the
  // corners are not read).
  float around[16];
  [[unroll]] for (int j = 0; j < 16; ++j) {
    ivec2 inBlock = ivec2(j % 4, j / 4) - 1;
    if ((inBlock.x == -1 || inBlock.x == 2) && (inBlock.y == -1 || inBlock.y == 2)) continue;
    ivec2 source = clamp(pixel * 2 + inBlock, ivec2(0), size - 1);
    around[j] = signedCoc(imageLoad(normalDepth, source).w);
  }
  vec3 colors[4];
  float cocs[4];
  float nearest = kDofMaxCoc;
  [[unroll]] for (int i = 0; i < 4; ++i) {
    ivec2 offset = ivec2(i & 1, i >> 1);
    ivec2 source = pixel * 2 + offset;
    bool inside = all(lessThan(source, size));
    source = min(source, size - 1);
    colors[i] = imageLoad(color, source).rgb;
    int j = (offset.y + 1) * 4 + offset.x + 1;
    float coc = around[j];
    float sharpest = abs(coc);
    [[unroll]] for (int k = 0; k < 4; ++k) {
      int beside = j + (k == 0 ? -1 : k == 1 ? 1 : k == 2 ? -4 : 4);
      if (around[beside] < coc) sharpest = min(sharpest, abs(around[beside]));
    }
    cocs[i] = sign(coc) * sharpest;
    if (inside) imageStore(colorCoc, source, vec4(colors[i], cocs[i]));
    nearest = min(nearest, cocs[i]);
  }
  vec4 sum = vec4(0.0);
  [[unroll]] for (int i = 0; i < 4; ++i)
    sum += vec4(colors[i], 1.0) * cocSimilarity(cocs[i], nearest);
  imageStore(halfColorCoc, pixel, vec4(sum.rgb / sum.w, nearest));
}
