#include "gpu/timestamps.h"

namespace hdof::gpu {

GpuTimer::GpuTimer(const Context& context, uint32_t maxPasses)
    : context_(&context), capacity_(maxPasses), enabled_(context.timestampsSupported()) {
  if (!enabled_) return;
  VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  info.queryType = VK_QUERY_TYPE_TIMESTAMP;
  info.queryCount = maxPasses * 3;  // begin and end per pass, then one scratch each (begin())
  VkQueryPool pool = VK_NULL_HANDLE;
  VK_CHECK(vkCreateQueryPool(context.device(), &info, nullptr, &pool));
  pool_ = QueryPool(context.device(), pool);
}

void GpuTimer::reset(VkCommandBuffer cmd, bool timed) {
  names_.clear();
  timed_ = timed;
  if (enabled_ && timed_) vkCmdResetQueryPool(cmd, pool_, 0, capacity_ * 3);
}

void GpuTimer::begin(VkCommandBuffer cmd, const std::string& pass) {
  if (!timed_) return;
  if (names_.size() >= capacity_) throw std::logic_error("GpuTimer: too many passes");
  names_.push_back(pass);
  if (!enabled_) return;
  vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, pool_,
                      static_cast<uint32_t>(names_.size() - 1) * 2);
  // Lavapipe defers a timestamp while a framebuffer is bound until its next flush, which a
  // synchronous compute dispatch does not cause: the begin stamp would land after the pass. A
  // second (scratch) timestamp flushes it first; elsewhere it is one more cheap timestamp.
  vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, pool_,
                      capacity_ * 2 + static_cast<uint32_t>(names_.size() - 1));
}

void GpuTimer::end(VkCommandBuffer cmd) {
  if (enabled_ && timed_)
    vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, pool_,
                        static_cast<uint32_t>(names_.size() - 1) * 2 + 1);
}

std::vector<std::pair<std::string, double>> GpuTimer::results() const {
  std::vector<std::pair<std::string, double>> out;
  if (names_.empty()) return out;
  std::vector<uint64_t> ticks(names_.size() * 2, 0);
  if (enabled_)
    VK_CHECK(vkGetQueryPoolResults(context_->device(), pool_, 0,
                                   static_cast<uint32_t>(ticks.size()),
                                   ticks.size() * sizeof(uint64_t), ticks.data(), sizeof(uint64_t),
                                   VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
  double msPerTick = context_->timestampPeriodNs() * 1e-6;
  for (size_t i = 0; i < names_.size(); ++i)
    out.emplace_back(names_[i], static_cast<double>(ticks[2 * i + 1] - ticks[2 * i]) * msPerTick);
  return out;
}

}  // namespace hdof::gpu
