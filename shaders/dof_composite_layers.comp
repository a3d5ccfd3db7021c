// Post-process DoF (stage 2), composite of the tiles without full-resolution blurs (their list,
// see lib/dof_composite.glsl): the sharp colour where the CoC is nothing, the far
// layer as |CoC| grows, the near layer over everything.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require

#include "lib/dof_composite.glsl"

void main() {
  ivec2 quad = listedQuad(kDofListLayers);
  ivec2 size = ivec2(frame.imageSize);
  CompositeQuad q = loadQuad(quad, true);
  [[unroll]] for (int i = 0; i < 4; ++i) {
    ivec2 pixel = q.first + ivec2(i & 1, i >> 1);
    if (any(greaterThanEqual(pixel, size))) continue;
    vec4 far, near;
    halfResLayers(q, i, far, near);
    storeComposite(pixel, overFarLayer(q.sharp[i], far), near);
  }
}
