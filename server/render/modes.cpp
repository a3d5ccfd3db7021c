#include "render/modes.h"

namespace hdof {
namespace {

template <typename T>
struct Named {
  T value;
  const char* name;
};

constexpr Named<RenderMode> kModes[] = {{RenderMode::Pinhole, "pinhole"},
                                        {RenderMode::PostProcess, "postprocess"},
                                        {RenderMode::Hybrid, "hybrid"},
                                        {RenderMode::RayTrace, "raytrace"},
                                        {RenderMode::Reference, "reference"}};

constexpr Named<DebugView> kViews[] = {{DebugView::Final, "final"},       {DebugView::Mask, "mask"},
                                       {DebugView::HitRatio, "hitratio"}, {DebugView::Coc, "coc"},
                                       {DebugView::Near, "near"},         {DebugView::Far, "far"},
                                       {DebugView::FocusZone, "focus_zone"}};

template <typename T, size_t N>
const char* nameOf(const Named<T> (&table)[N], T value) {
  for (const auto& entry : table)
    if (entry.value == value) return entry.name;
  return "?";
}

template <typename T, size_t N>
std::optional<T> parse(const Named<T> (&table)[N], const std::string& name) {
  for (const auto& entry : table)
    if (name == entry.name) return entry.value;
  return std::nullopt;
}

template <typename T, size_t N>
std::string joined(const Named<T> (&table)[N]) {
  std::string names;
  for (const auto& entry : table) {
    if (!names.empty()) names += '|';
    names += entry.name;
  }
  return names;
}

}  // namespace

const char* modeName(RenderMode mode) { return nameOf(kModes, mode); }
std::optional<RenderMode> parseMode(const std::string& name) { return parse(kModes, name); }
std::string modeNames() { return joined(kModes); }

const char* debugViewName(DebugView view) { return nameOf(kViews, view); }
std::optional<DebugView> parseDebugView(const std::string& name) { return parse(kViews, name); }
std::string debugViewNames() { return joined(kViews); }

std::vector<std::string> debugViewList() {
  std::vector<std::string> names;
  for (const auto& entry : kViews) names.push_back(entry.name);
  return names;
}

}  // namespace hdof
