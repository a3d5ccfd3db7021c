// Catmull-Rom resampling at a sub-pixel position, for a history reprojected from the previous
// frame: the 4x4 texels around the position, of which the corners are left out (their weights are
// under 0.4% each). A bilinear fetch blurs such a history a little every frame, and a nearest one
// moves it by up to half a pixel.
#ifndef HDOF_LIB_CATMULL_ROM_GLSL
#define HDOF_LIB_CATMULL_ROM_GLSL

// Tap (i, j), i and j from 0 to 3, is texel first + (i, j) and weighs x[i] * y[j].
struct CatmullRomTaps {
  ivec2 first;
  vec4 x, y;
};

CatmullRomTaps catmullRomTaps(vec2 position) {
  vec2 p = position - 0.5;
  vec2 base = floor(p);
  vec2 f = p - base;
  vec2 w0 = f * (-0.5 + f * (1.0 - 0.5 * f));
  vec2 w1 = 1.0 + f * f * (-2.5 + 1.5 * f);
  vec2 w2 = f * (0.5 + f * (2.0 - 1.5 * f));
  vec2 w3 = f * f * (-0.5 + 0.5 * f);
  return CatmullRomTaps(ivec2(base) - 1, vec4(w0.x, w1.x, w2.x, w3.x),
                        vec4(w0.y, w1.y, w2.y, w3.y));
}

// Whether tap (i, j) is read: all but the corners.
bool catmullRomTapRead(int i, int j) { return !((i == 0 || i == 3) && (j == 0 || j == 3)); }

#endif
