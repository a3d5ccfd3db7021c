// Lets one header declare structs and small functions for both C++ (glm) and GLSL.
// C++ includes it as <shared/types.h>; GLSL through GL_GOOGLE_include_directive.
#ifndef HDOF_SHARED_TYPES_H
#define HDOF_SHARED_TYPES_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
#include <glm/gtc/packing.hpp>
namespace hdof::gpu {
using vec2 = glm::vec2;
using vec3 = glm::vec3;
using vec4 = glm::vec4;
using uvec2 = glm::uvec2;
using uvec4 = glm::uvec4;
using mat4 = glm::mat4;
using uint = uint32_t;
// GLSL's built-ins for the shared functions.
using glm::abs;
using glm::clamp;
using glm::dot;
using glm::max;
using glm::min;
using glm::normalize;
}  // namespace hdof::gpu
#define HDOF_NAMESPACE_BEGIN namespace hdof::gpu {
#define HDOF_NAMESPACE_END }
#define HDOF_FN inline
#define HDOF_CONST inline constexpr
#else
#define HDOF_NAMESPACE_BEGIN
#define HDOF_NAMESPACE_END
#define HDOF_FN
#define HDOF_CONST const
#endif

#endif
