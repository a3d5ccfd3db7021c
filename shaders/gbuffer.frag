// G-buffer (stage 1), visibility step: which triangle covers the pixel centre. Shading happens once
// per pixel in gbuffer_resolve.comp, with the same code the ray tracer runs.
#version 460

layout(location = 0) flat in uint inTriangle;
layout(location = 0) out uint outTriangle;

void main() { outTriangle = inTriangle; }
