// Hybrid stage 5, before the temporal pass: pixels the ray mask left out this frame drop their
// history. Their moments and variance are zeroed, so that the spatial pass, the next frame's
// temporal pass and the next frame's ray mask find no rays there, and so are their noise test's
// terms, which the composite reads around the pixels it composites; hybrid_temporal.comp and
// hybrid_spatial.comp write the listed ones. A pass rather than an image clear: some GPUs clear a
// storage image through their raster units (at 1920x1080 on an H100, where the raster is slow, a
// clear of two images took 0.79 ms, this pass 0.02). Lavapipe's clear is a fill, faster than this
// pass (640x360, one thread: 0.7 against 2.3 ms, under 1% of a hybrid frame).
#version 460
layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 1, binding = 0, r8ui) uniform readonly uimage2D rays;
layout(set = 1, binding = 1, rgba32f) uniform writeonly image2D moments;
layout(set = 1, binding = 2) uniform writeonly image2D variance;  // rg16f
layout(set = 1, binding = 3) uniform writeonly image2D difference;  // rg16f

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, imageSize(rays))) || imageLoad(rays, pixel).r != 0u) return;
  imageStore(moments, pixel, vec4(0.0));
  imageStore(variance, pixel, vec4(0.0));
  imageStore(difference, pixel, vec4(0.0));
}
