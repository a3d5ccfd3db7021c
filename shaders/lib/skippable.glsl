// SKIPPABLE_IF(condition) { ... }: `if (condition)` for code that most invocations skip. A CPU
// device (lavapipe) runs an if's body under a lane mask whatever its lanes' conditions, but leaves
// a loop that no lane enters: written as a loop that runs once or not at all, the body costs only
// where some lane takes it. The same on every device; the body must not `break` or `continue` a
// loop around it (it would leave this one instead).
#ifndef HDOF_LIB_SKIPPABLE_GLSL
#define HDOF_LIB_SKIPPABLE_GLSL

#define SKIPPABLE_IF(condition) for (bool enter_ = (condition); enter_; enter_ = false)

#endif
