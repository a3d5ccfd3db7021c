// Ray mask (stage 3), dispatch arguments: one kRayWorkGroupSize-wide workgroup per
// kRayWorkGroupSize entries of the work list, for the vkCmdDispatchIndirect of the steps that run
// over the list (stages 4 to 6).
#version 460
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 1) in;

#include "shared/ray_work.h"

HDOF_RAY_WORK_LIST(1, );

void main() {
  workList.header.groupsX = (workList.header.count + kRayWorkGroupSize - 1u) / kRayWorkGroupSize;
  workList.header.groupsY = 1u;
  workList.header.groupsZ = 1u;
}
