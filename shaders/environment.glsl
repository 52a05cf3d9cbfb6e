// The environment cube a curved mirror, glass or glossy metal reads (viewer/environment_cubes.h):
// rgb radiance, alpha the distance (m) from the capture centre of what the cube sees there.
//
// Parallax correction after Szirmay-Kalos et al., "Approximate Ray-Tracing on the GPU with
// Distance Impostors" (Eurographics 2005): along the ray x + t r from the shaded point, the
// first point q that lies behind the captured surface (|q - centre| beyond the distance stored
// in q's direction) is where the ray meets the scene; the cube is read in q's direction. A
// search over kEnvironmentSteps points, spaced finer near x, then secant steps between the
// last point in front and the first behind. With u_environment_parallax = 0 (the shared cube)
// q's direction is r: the plain direction lookup.
uniform samplerCube u_environment;
uniform float u_environment_levels;
uniform vec3 u_environment_centre;    // world, m
uniform float u_environment_parallax;  // 1 or 0
uniform float u_environment_reach;     // m: the search covers at least this far (scene diagonal)

const int kEnvironmentSteps = 16;
const int kEnvironmentSecantSteps = 3;

// How far q = o + t r lies behind the captured surface in its direction (m; < 0: in front).
float behind_capture(vec3 o, vec3 r, float t) {
  vec3 q = o + t * r;
  float distance = length(q);
  return distance - textureLod(u_environment, q / max(distance, 1e-30), 0.0).a;
}

// The direction from the capture centre in which the ray from `x` along `r` meets the scene.
vec3 environment_hit_direction(vec3 x, vec3 r) {
  vec3 o = (x - u_environment_centre) * u_environment_parallax;
  // t(u) = scale u^2 / (1 - u)^2 for u = k / (steps + 1): from ~scale / steps^2 to
  // scale steps^2, with scale chosen so the last step reaches u_environment_reach.
  float scale = max(length(o), u_environment_reach / float(kEnvironmentSteps * kEnvironmentSteps));
  // No search for the shared cube: a loop whose count is 0 costs llvmpipe nothing, where a
  // skipped branch would still run. Point 0 is x itself, in front: its object is not in its
  // own cube.
  int steps = u_environment_parallax > 0.0 ? kEnvironmentSteps : -1;
  float t_front = 0.0, f_front = -1.0;
  float t_behind = -1.0, f_behind = 0.0;
  for (int k = 0; k <= steps; ++k) {
    float u = float(k) / float(kEnvironmentSteps + 1);
    float s = u / (1.0 - u);
    float t = scale * s * s;
    float f = behind_capture(o, r, t);
    if (k == 0) {
      f_front = min(f, -1e-6);
    } else if (f < 0.0) {
      t_front = t;
      f_front = f;
    } else {
      t_behind = t;
      f_behind = f;
      break;
    }
  }
  if (t_behind < 0.0) return r;  // nothing within reach: as far as the sky
  for (int i = 0; i < kEnvironmentSecantSteps; ++i) {
    float t = t_front + (t_behind - t_front) * f_front / (f_front - f_behind);
    float f = behind_capture(o, r, t);
    if (f < 0.0) {
      t_front = t;
      f_front = f;
    } else {
      t_behind = t;
      f_behind = f;
    }
  }
  float t = t_front + (t_behind - t_front) * f_front / (f_front - f_behind);
  vec3 q = o + t * r;
  return u_environment_parallax > 0.0 && dot(q, q) > 0.0 ? q : r;
}

vec3 environment(vec3 x, vec3 r, float roughness) {
#if HAS_ENVIRONMENT
  return textureLod(u_environment, environment_hit_direction(x, r), roughness * u_environment_levels)
      .rgb;
#else
  return u_ambient;
#endif
}
