// Exposure and tone mapping, the same formula as lb::tonemap_value in bake/io/image_io.h so
// that viewer PNGs and CLI/HQ PNGs agree:
//   x = radiance * 2^exposure;  display = curve(x);  encoded = srgb_oetf(display)
// curves: 0 clamp, 1 reinhard x/(1+x), 2 aces (Narkowicz 2015 fit), per channel.
#ifndef LB_TONEMAP_GLSL
#define LB_TONEMAP_GLSL

float tone_curve(float x, int curve) {
  if (curve == 0) return clamp(x, 0.0, 1.0);
  if (curve == 1) { x = max(x, 0.0); return x / (1.0 + x); }
  x = max(x, 0.0);
  return clamp(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

float srgb_oetf(float v) {
  v = clamp(v, 0.0, 1.0);
  return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055;
}

vec3 tonemap(vec3 radiance, float exposure, int curve) {
  vec3 x = radiance * exp2(exposure);
  return vec3(srgb_oetf(tone_curve(x.r, curve)), srgb_oetf(tone_curve(x.g, curve)),
              srgb_oetf(tone_curve(x.b, curve)));
}

#endif
