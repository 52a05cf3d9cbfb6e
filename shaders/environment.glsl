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

// How far q = o + t r (o from the centre) lies beyond the surface `cube` holds in q's
// direction (m; < 0: nearer the centre).
float beyond_surface(samplerCube cube, vec3 o, vec3 r, float t) {
  vec3 q = o + t * r;
  float distance = length(q);
  return distance - textureLod(cube, q / max(distance, 1e-30), 0.0).a;
}

// Secant steps between t_a, on `side` of the surface (beyond_surface * side > 0), and t_b,
// across it: the t where the ray crosses.
float refine_crossing(samplerCube cube, vec3 o, vec3 r, float t_a, float f_a, float t_b, float f_b,
                      float side) {
  for (int i = 0; i < kEnvironmentSecantSteps; ++i) {
    float t = t_a + (t_b - t_a) * f_a / (f_a - f_b);
    float f = beyond_surface(cube, o, r, t);
    if (f * side > 0.0) {
      t_a = t;
      f_a = f;
    } else {
      t_b = t;
      f_b = f;
    }
  }
  return t_a + (t_b - t_a) * f_a / (f_a - f_b);
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
    float f = beyond_surface(u_environment, o, r, t);
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
  float t = refine_crossing(u_environment, o, r, t_front, f_front, t_behind, f_behind, -1.0);
  vec3 q = o + t * r;
  return u_environment_parallax > 0.0 && dot(q, q) > 0.0 ? q : r;
}

vec3 environment(vec3 x, vec3 r, float roughness) {
#if HAS_ENVIRONMENT
  vec3 direction = environment_hit_direction(x, r);
  return textureLod(u_environment, direction, roughness * u_environment_levels).rgb;
#else
  return u_ambient;
#endif
}

// ---- glass: the exit of a refracted ray ----
// A glass object's second cube holds the object alone as seen from the same centre: rgb the
// surface normal as 0.5 n + 0.5 (the mesh's, out of the glass), alpha its distance (m; 0 where
// there is none). From the entry point the ray runs inside the glass until it crosses that
// surface (the sign of |q - centre| - distance changes from what it was just inside), where it
// refracts out; a ray that meets no surface within the object's size keeps the entry's ray.
uniform samplerCube u_environment_self;
uniform float u_environment_glass;  // 1: glass with its own cubes, 0 otherwise
uniform float u_environment_size;   // m: the object's bounding-box diagonal

// Where the ray from `x` (world) along `r` first crosses the object's surface (the sign of
// beyond_surface changes from what it is one small step on): the point and the surface normal
// there, turned along the ray. False when it meets none within the object's size.
bool glass_crossing(vec3 x, vec3 r, out vec3 crossing, out vec3 normal) {
  crossing = x;
  normal = r;
  vec3 o = x - u_environment_centre;
  int steps = u_environment_glass > 0.0 ? kEnvironmentSteps : 0;
  // t = size (k / steps)^2: ~size / 256 first, finer than the thinnest wall near the entry.
  float t_inside = 0.0, f_inside = 0.0, t_out = -1.0, f_out = 0.0, side = 0.0;
  for (int k = 1; k <= steps; ++k) {
    float u = float(k) / float(kEnvironmentSteps);
    float t = u_environment_size * u * u;
    float f = beyond_surface(u_environment_self, o, r, t);
    if (k == 1) side = f < 0.0 ? -1.0 : 1.0;
    if (f * side > 0.0) {
      t_inside = t;
      f_inside = f;
    } else {
      t_out = t;
      f_out = f;
      break;
    }
  }
  if (t_out < 0.0) return false;
  float t = refine_crossing(u_environment_self, o, r, t_inside, f_inside, t_out, f_out, side);
  vec3 q = o + t * r;
  normal = normalize(textureLod(u_environment_self, q, 0.0).rgb * 2.0 - 1.0);
  if (dot(normal, r) < 0.0) normal = -normal;
  crossing = u_environment_centre + q;
  return true;
}
