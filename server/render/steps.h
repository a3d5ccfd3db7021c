// Records a frame's steps in order: each step waits for the writes of the steps before it (one
// global barrier between compute, transfer and indirect-argument use), is timed under its name,
// and, for a compute program, gets the frame uniforms (the shaders' `Frame` block) and, when it
// reads the scene, the scene's set bound. Multi-step effects are lists of these calls.
#pragma once

#include "gpu/program.h"
#include "gpu/timestamps.h"
#include "scene/gpu_scene.h"

#include <initializer_list>

namespace hdof {

class StepRecorder {
 public:
  StepRecorder(VkCommandBuffer cmd, gpu::GpuTimer& timer, const gpu::Buffer& frameUniforms,
               const GpuScene& scene);

  VkCommandBuffer cmd() const { return cmd_; }
  const GpuScene& scene() const { return scene_; }
  const gpu::Buffer& frameUniforms() const { return frameUniforms_; }

  // One dispatch of program, timed as `name` (default: the program's name).
  void dispatch(const gpu::ComputeProgram& program, std::initializer_list<gpu::Bind> binds,
                const gpu::Grid& grid, gpu::PushConstants push = {}, const char* name = nullptr);

  // Any other commands as one timed step.
  template <typename Record>
  void step(const char* name, Record&& record) {
    begin(name);
    record(cmd_);
    timer_.end(cmd_);
  }

 private:
  void begin(const char* name);

  VkCommandBuffer cmd_;
  gpu::GpuTimer& timer_;
  const gpu::Buffer& frameUniforms_;
  const GpuScene& scene_;
};

}  // namespace hdof
