// Mathematical constants, shared by C++ and GLSL.
#ifndef HDOF_SHARED_MATH_H
#define HDOF_SHARED_MATH_H
#include "types.h"

HDOF_NAMESPACE_BEGIN

HDOF_CONST float kPi = 3.14159265358979f;

HDOF_NAMESPACE_END

#endif
