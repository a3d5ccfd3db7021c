// Ray mask (stage 3), ray counts: rays where an edge's disc covers the pixel
// (ray_mask_columns.comp) or where the ray-traced output is noisy, at least 1 and at most the
// frame's samples per pixel: as many as the strongest edge asks for while the pixel is new to the
// mask, then as many as the variance of its rays asks for (settled, quiet pixels keep a ray or two
// a frame, enough for their history to go on; on a still view out of focus, a pixel counts as
// noisy as its noisiest settled neighbour). Rays by CoC: where every edge that reaches the pixel
// is blurred on both sides, what its rays see varies slowly across the image, and the spatial
// reconstruction fills in from the neighbours: the rays fall with the area of the sharper side's
// blur beyond kRayMaskDenseCoc, in motion (of the camera or the lens: a focus pull) and over a
// view's first frames; once camera and lens have rested kStillRasterFrames frames, a settled
// pixel's rays follow its variance alone, so that a resting view keeps converging as fast, and a
// pixel the composite trusts gets them all, and a quiet one that it trusts takes its rays in turns
// with its neighbours (kRestingTurns). Then the tile's pixels with rays are appended to the
// work list together (one atomic per workgroup and counter; a ballot gives each lane its slot
// among its subgroup's), so that the tracer's subgroups, which take consecutive entries, trace
// neighbouring pixels: measured 6% faster than one atomic per subgroup, whose tiles interleave in
// the list as the device's threads run them side by side.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_arithmetic : require
layout(local_size_x = 8, local_size_y = 8) in;

#include "lib/frame.glsl"
#include "lib/dof.glsl"
#include "shared/ray_work.h"

// The edges whose disc covers the pixel: the strongest (x; -1: none), their sharper sides' |CoC|.
layout(set = 1, binding = 1, rg16f) uniform readonly image2D covered;
// Any float format: the variance of one ray and the rays accumulated (hybrid_temporal.comp); a
// 1x1 zero image when there is no variance yet.
layout(set = 1, binding = 2) uniform sampler2D variance;
layout(set = 1, binding = 3, r8ui) uniform writeonly uimage2D rays;
HDOF_RAY_WORK_LIST(4, coherent);
layout(set = 1, binding = 5, rgba32f) uniform readonly image2D normalDepth;

layout(push_constant) uniform Push {
  uint everywhere;  // 1: every pixel gets the full rays
  // 1: on a resting view whose last frame's image stands (hybrid_dof.cpp), a pixel of one ray a
  // frame takes its rays in turns (kRestingTurns).
  uint inTurns;
} push;

// A resting pixel of a ray a frame that the composite shows as traced alone (kHybridTrustedRays)
// traces kRestingTurns rays once every kRestingTurns frames instead, by tiles (this workgroup's
// 8x8 pixels; one tile of each 2x2 a frame): the same rays, a quarter of such pixels listed. What
// a listed pixel costs beyond its rays is the trace's set-up and stores and the temporal, spatial
// and composite passes (on the closeup after a hundred frames at rest, single-thread, those three
// passes took about half as long: 48.5 -> 26 ms). Whole tiles keep the listed pixels together
// for the trace's subgroups: turns by pixel (one of each 2x2) scattered them, and the trace took
// 10% longer for the same rays.
// Between its turns a pixel keeps its history and its colour; trusted, that colour is its traced
// colour alone, which a turn's rays change by a fraction of its noise (the closeup at 96 frames
// differs by 2 levels at most). Pixels with a shorter history taking turns too drew the turns'
// pattern where the composite blends the traced colour in by its rays: a blurred near surface
// after 16-20 frames of the closeup, 0.2-0.5 dB below.
const uint kRestingTurns = 4u;

// The pixel's rays this frame, or its turn's; whether it is listed this frame.
uint rayCount(ivec2 pixel, out bool listed) {
  vec2 edges = imageLoad(covered, pixel).xy;
  bool nearEdge = edges.x >= 0.0;
  float strongest = max(edges.x, 0.0);
  float sharpest = edges.y;
  ivec2 last = textureSize(variance, 0) - 1;
  vec2 history = texelFetch(variance, min(pixel, last), 0).rg;
  float noise = history.x;
  // New to the mask: no rays accumulated (a cleared history), or too few for a variance.
  bool settled = history.y > 0.0 && noise < kRayMaskVarianceNew;
  // On a still view a settled pixel out of focus is as noisy as its noisiest settled neighbour:
  // beside a bright light's blur a pixel whose few rays have not met the light yet reads no
  // variance at all, and would keep one ray a frame while its traced colour, missing the light, is
  // handed over to. (In motion the history is short anyway: measured, the rays cost 5% of the
  // frame rate for no gain.)
  if (frame.stillFrames > 0u && settled &&
      abs(signedCoc(imageLoad(normalDepth, pixel).w)) >= kDofFocusZone) {
    for (int i = 0; i < 9; ++i) {
      ivec2 neighbour = clamp(pixel + ivec2(i % 3 - 1, i / 3 - 1), ivec2(0), last);
      float other = texelFetch(variance, neighbour, 0).x;
      if (other < kRayMaskVarianceNew) noise = max(noise, other);
    }
  }
  // New to the mask, or without any variance yet (a few rays that all saw the same colour say
  // little): as the edge asks; then as the variance of the pixel's rays asks.
  bool measured = settled && noise > 0.0;
  float need = measured ? saturate(noise / kRayMaskVarianceFull) : strongest;
  uint samples = clamp(frame.samplesPerPixel, 1u, 255u);  // what r8ui holds
  uint count = 0u;
  bool resting = frame.stillFrames >= kStillRasterFrames;
  float density = nearEdge && !(measured && resting)
                      ? min(1.0, pow(kRayMaskDenseCoc / max(sharpest, 1.0), 2.0))
                      : 1.0;
  if (nearEdge || noise >= kRayMaskVarianceOn)
    count = clamp(uint(ceil(need * density * float(samples))), 1u, samples);
  // Once camera and lens have rested kStillRasterFrames frames, the raster has all its samples and
  // the G-buffer no longer runs: a frame's time goes to rays, and a pixel of the mask that the
  // composite already shows as traced alone (kHybridTrustedRays) gets the full rays. Before that,
  // more rays would only hand a pixel that the variance gave few over to its traced colour
  // sooner, while it is still noisier than the post-process.
  // A pixel the mask leaves out gets a ray a frame: the post-process is not the lens's image
  // either (its blurs approximate, its in-focus edges have the raster's samples alone), and with
  // the rays a resting view goes on converging to the traced image instead of stopping there.
  bool trusted = history.y >= kHybridTrustedRays;
  if (push.everywhere != 0u || resting && trusted && count > 0u) count = samples;
  listed = true;
  if (resting && count == 0u) {
    count = 1u;
    if (push.inTurns != 0u && trusted) {
      count = min(kRestingTurns, samples);
      listed = (gl_WorkGroupID.x + 2u * gl_WorkGroupID.y) % count == frame.stillFrames % count;
    }
  }
  return count;
}

// The tile's entries and rays, and its first slot in the list.
shared uint groupListed, groupRays, groupFirst;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(frame.imageSize);
  bool inside = all(lessThan(pixel, size));
  bool listed = false;
  uint count = inside ? rayCount(pixel, listed) : 0u;
  if (inside) imageStore(rays, pixel, uvec4(count));
  if (!listed) count = 0u;
  if (gl_LocalInvocationIndex == 0u) {
    groupListed = 0u;
    groupRays = 0u;
  }
  barrier();
  uvec4 ballot = subgroupBallot(count > 0u);
  uint subgroupListed = subgroupBallotBitCount(ballot);
  uint rayTotal = subgroupAdd(count);
  uint subgroupFirst = 0u;
  if (subgroupElect() && subgroupListed > 0u) {
    subgroupFirst = atomicAdd(groupListed, subgroupListed);
    atomicAdd(groupRays, rayTotal);
  }
  subgroupFirst = subgroupBroadcastFirst(subgroupFirst);
  barrier();
  if (gl_LocalInvocationIndex == 0u && groupListed > 0u) {
    groupFirst = atomicAdd(workList.header.count, groupListed);
    atomicAdd(workList.header.rays, groupRays);
  }
  barrier();
  if (count > 0u) {
    uint slot = groupFirst + subgroupFirst + subgroupBallotExclusiveBitCount(ballot);
    workList.entries[slot] = uvec2(packRayWorkPixel(uint(pixel.x), uint(pixel.y)), count);
  }
}
