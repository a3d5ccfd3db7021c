// What a frame shows: the render modes of the pipeline and the hybrid's debug views, with the
// names the CLI, the wire protocol and the browser client use.
#pragma once

#include <shared/debug_view.h>

#include <optional>
#include <string>
#include <vector>

namespace hdof {

enum class RenderMode { Pinhole, PostProcess, Hybrid, RayTrace, Reference };

const char* modeName(RenderMode mode);
std::optional<RenderMode> parseMode(const std::string& name);
std::string modeNames();  // "pinhole|postprocess|hybrid|raytrace|reference"

enum class DebugView : uint32_t {
  Final = gpu::kDebugViewFinal,
  Mask = gpu::kDebugViewMask,
  HitRatio = gpu::kDebugViewHitRatio,
  Coc = gpu::kDebugViewCoc,
  Near = gpu::kDebugViewNear,
  Far = gpu::kDebugViewFar,
  FocusZone = gpu::kDebugViewFocusZone,
};

const char* debugViewName(DebugView view);
std::optional<DebugView> parseDebugView(const std::string& name);
std::vector<std::string> debugViewList();  // "final", "mask", ... in order
std::string debugViewNames();              // "final|mask|..."

}  // namespace hdof
