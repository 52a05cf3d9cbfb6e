#pragma once
// A thin-lens camera (Cook 1986): rays leave a disk of radius `aperture_radius` and meet at
// the plane of focus, so objects off that plane blur. A zero aperture is a pinhole.

#include "bake/accel.h"
#include "bake/scene.h"

namespace lb {

class ThinLensCamera {
 public:
  ThinLensCamera(const Camera& camera, int width, int height);

  // `film` in [0,width)x[0,height) pixels, row 0 at the top; `lens` in [0,1)^2 (mapped to the
  // disk through the concentric square-to-disk map). The direction is unit length.
  Ray generate(vec2 film, vec2 lens) const;
  // The same ray written into `ray` in place (no temporary to copy into a ray buffer).
  void generate(vec2 film, vec2 lens, Ray& ray) const;

  // The inverse of generate() for light tracing: the ray from lens point `lens` (as above) to
  // the world point `point`. False if it leaves the film. Otherwise `film` is where generate()
  // would start that ray, `lens_point` its origin, and `importance` converts area to pixels:
  // a pixel's mean radiance over its film area is
  //     (1 / N) sum over points x of L(x -> lens) * cos_x / |x - lens|^2 * importance,
  // importance = 1 / (pixel area on the image plane at distance 1 * cos^3 theta), theta the
  // ray's angle to the view axis (the change of variables from film area to surface area;
  // the same at any lens point, since the plane of focus maps to the film by a fixed scale).
  struct Connection {
    vec2 film{0.0f};
    vec3 lens_point{0.0f};
    float importance = 0.0f;  // 1/sr per unit film-area fraction, see above
  };
  bool connect(vec3 point, vec2 lens, Connection& out) const;
  bool is_pinhole() const { return aperture_radius_ <= 0.0f; }

 private:
  vec3 position_;
  vec3 right_, up_, forward_;  // orthonormal, right-handed view frame
  float half_width_ = 1.0f;    // of the image plane at distance 1
  float half_height_ = 1.0f;
  float aperture_radius_ = 0.0f;
  float focus_distance_ = 1.0f;
  int width_ = 1, height_ = 1;
};

}  // namespace lb
