// The hybrid's debug views (render/modes.h names them; shaders/debug_view.comp draws them),
// shared by C++ and GLSL.
#ifndef HDOF_SHARED_DEBUG_VIEW_H
#define HDOF_SHARED_DEBUG_VIEW_H
#include "types.h"

HDOF_NAMESPACE_BEGIN

HDOF_CONST uint kDebugViewFinal = 0;     // the composite, no debug view
HDOF_CONST uint kDebugViewMask = 1;      // rays per pixel over the cap
HDOF_CONST uint kDebugViewHitRatio = 2;  // the accumulated near-hit ratio
HDOF_CONST uint kDebugViewCoc = 3;       // signed CoC: near blue, far red, focus zone black
HDOF_CONST uint kDebugViewNear = 4;      // the reconstructed near layer
HDOF_CONST uint kDebugViewFar = 5;       // the reconstructed far layer
HDOF_CONST uint kDebugViewFocusZone = 6;  // the composite, the in-focus zone tinted green

HDOF_NAMESPACE_END

#endif
