#include "render/steps.h"

#include <vector>

namespace hdof {

StepRecorder::StepRecorder(VkCommandBuffer cmd, gpu::GpuTimer& timer,
                           const gpu::Buffer& frameUniforms, const GpuScene& scene)
    : cmd_(cmd), timer_(timer), frameUniforms_(frameUniforms), scene_(scene) {}

void StepRecorder::begin(const char* name) {
  gpu::memoryBarrier(cmd_, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                     VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT |
                         VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT,
                     VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                         VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT |
                         VK_ACCESS_INDIRECT_COMMAND_READ_BIT);
  timer_.begin(cmd_, name);
}

void StepRecorder::dispatch(const gpu::ComputeProgram& program,
                            std::initializer_list<gpu::Bind> binds, const gpu::Grid& grid,
                            gpu::PushConstants push, const char* name) {
  std::vector<gpu::Bind> all(binds);
  if (program.interface().find("Frame")) all.emplace_back("Frame", frameUniforms_);
  step(name ? name : program.name().c_str(), [&](VkCommandBuffer cmd) {
    if (program.readsScene()) scene_.bind(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, program.layout());
    program.record(cmd, all, grid, push);
  });
}

}  // namespace hdof
