// G-buffer (stage 1), visibility step: which triangle covers each sample. Shading happens in
// gbuffer_resolve.comp, with the same code the ray tracer runs. The number is written as a float
// (exact below 2^24; the cleared images hold -1): a multisampled image of an integer format is not
// a render target on every device.
#version 460

layout(location = 0) flat in uint inTriangle;
layout(location = 0) out float outTriangle;

void main() { outTriangle = float(inTriangle); }
