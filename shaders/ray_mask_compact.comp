// Ray mask (stage 3), compaction: appends every pixel with rays to the work list and adds up their
// rays. One atomic per subgroup and counter: a ballot gives each lane its slot among the subgroup's
// entries.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_arithmetic : require
layout(local_size_x = 8, local_size_y = 8) in;

#include "lib/frame.glsl"
#include "shared/ray_work.h"

HDOF_RAY_WORK_LIST(1, coherent);
layout(set = 1, binding = 2, r8ui) uniform readonly uimage2D rays;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  bool inside = all(lessThan(pixel, ivec2(frame.imageSize)));
  uint count = inside ? imageLoad(rays, pixel).r : 0u;
  uvec4 ballot = subgroupBallot(count > 0u);
  uint listed = subgroupBallotBitCount(ballot);
  if (listed == 0u) return;
  uint rays = subgroupAdd(count);
  uint first = 0u;
  if (subgroupElect()) {
    first = atomicAdd(workList.header.count, listed);
    atomicAdd(workList.header.rays, rays);
  }
  first = subgroupBroadcastFirst(first);
  if (count > 0u) {
    uint slot = first + subgroupBallotExclusiveBitCount(ballot);
    workList.entries[slot] = uvec2(packRayWorkPixel(uint(pixel.x), uint(pixel.y)), count);
  }
}
