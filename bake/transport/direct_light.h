#pragma once
// Direct light with ONE shadow ray per diffuse hit (Shirley 1990, section 3.3).
//
// The paper: estimate every light's contribution at the hit with Eq. 2 (the point form
// L cos1 cos2 A / (pi d^2) at the light's centre), choose one light with probability in
// proportion to that estimate, send one shadow ray to a random point on it, and if the ray is
// not blocked return the SUM of all lights' estimates, else zero.
//
// What we return instead (unbiased, also near a light where the point form is wrong):
// choose light j with probability p_j, a point y uniformly on it (pdf 1/A_j), and return
//     f_j(y) * A_j / p_j          if the segment x-y is unblocked, else 0,
// with f_j(y) = L_j cos_x cos_y / (pi |x-y|^2), i.e. in the E/pi convention of bake_result.h
// (multiply by the reflectance R to get outgoing radiance). Its mean is exactly
// sum_j (1/pi) \int_{A_j} L_j V cos_x cos_y / d^2 dA for any p_j > 0 wherever f_j can be > 0.
//
// Relation to the paper: with p_j = w_j / W (w_j the Eq. 2 estimate, W their sum) the value is
//     W * (f_j(y) A_j / w_j),
// the paper's "sum over all lights" W times a correction that is ~1 for a small or distant
// light (where Eq. 2 is accurate) and fixes the value near a large light (where it is not).
// To stay unbiased where Eq. 2 says zero but part of a light is still visible (a big light
// whose centre is below the horizon), p_j mixes in a small uniform share over every light
// that can reach the point at all:  p_j = (1 - a) w_j / W + a / M,  a = kUniformShare.
// Lights that cannot reach the point (behind it, or it behind them) get p_j = 0 and f_j = 0.
// When no light can reach the point, no shadow ray is sent (the paper's dark ceiling).
//
// Lamps (point, spot, directional; bake/light_sources.h) are lights j >= lights().size(), after
// the area lights. For a lamp Eq. 2 is exact: w_j = I(dir) window cos_x / (pi d^2) (E cos_x / pi
// for a directional lamp), and f_j / p_j is that value over p_j with its one shadow ray (to the
// lamp's point, or to infinity). The sky is not sampled here: it is soft light, baked by pass 2.

#include <cstdint>
#include <vector>

#include "bake/accel.h"
#include "bake/light_sources.h"
#include "bake/lights.h"
#include "bake/scene.h"

namespace lb {

// The receiver: a point on a diffuse surface, normals on the side the light must arrive from.
struct ReceiverPoint {
  vec3 position{0.0f};
  vec3 geometric_normal{0.0f};  // unit; light from below this plane is ignored
  vec3 shading_normal{0.0f};    // unit (bump-mapped); the cosine uses it
};

struct DirectEstimate {
  vec3 value{0.0f};         // E/pi, W/(sr m^2)
  int light = -1;           // the light the shadow ray went to, -1 if none was sent
  bool shadow_ray = false;  // whether a shadow ray was traced
};

// The same estimate before its shadow ray is traced, so a caller can trace many at once:
// the estimate is `value` if the shadow ray is unblocked, else 0. Without a shadow ray
// (`shadow_ray` false) the estimate is 0.
struct DeferredEstimate {
  vec3 value{0.0f};  // E/pi, W/(sr m^2), if unblocked
  int light = -1;
  bool shadow_ray = false;
};

class DirectLight {
 public:
  // Share of the selection probability spread uniformly over the lights that can reach a point.
  static constexpr float kUniformShare = 0.1f;
  // A reused choice is searched block by block (see Choice): entries per block, and the most
  // blocks searched that way (more lights: a binary search).
  static constexpr size_t kChoiceBlock = 8;
  static constexpr size_t kChoiceMaxBlocks = 64;

  DirectLight(const Scene& scene, const Accel& accel);

  // The accelerator its shadow rays are traced through: a caller tracing a DeferredEstimate's
  // ray uses this one, which may hold more than the scene's (moving objects' shadows, probes).
  const Accel& accel() const { return accel_; }
  // The area lights, lights 0 .. lights().size() - 1.
  const std::vector<AreaLight>& lights() const { return sources_.area_lights(); }
  // Every light the estimator chooses from: the area lights, then the lamps.
  size_t light_count() const { return lights().size() + lamps_.size(); }
  // The scene's sky (nullptr if none), for rays that leave the scene.
  const SkyLight* sky() const { return sources_.sky(); }
  // Light j's index among the scene's LightSources (area lights first, then lamps).
  size_t source_of(size_t light) const {
    return light < lights().size() ? light : lamps_[light - lights().size()];
  }

  // Eq. 2 of the paper at the light's centre, luminance-weighted, in E/pi units; 0 when the
  // light cannot reach the point. The d^2 is clamped below by A/4 so it stays finite.
  float eq2_estimate(const ReceiverPoint& x, size_t light) const;
  // Whether any part of the light can send light to x (conservative).
  bool can_reach(const ReceiverPoint& x, size_t light) const;
  // The probability of choosing each light at x (sums to 1, or all 0 when none can reach x).
  std::vector<float> selection_probabilities(const ReceiverPoint& x) const;

  // The paper's one-shadow-ray estimate; `u_select` chooses the light, `u_point` the point on it
  // (both stratified by the caller).
  DirectEstimate one_shadow_ray(const ReceiverPoint& x, float u_select, vec2 u_point) const;

  // The same estimator with the light choice computed once at an anchor point and reused at
  // nearby hits (the HQ renderer reuses it over the samples of one pixel that hit the same
  // surface): the Eq. 2 sweep then costs O(lights) per pixel, not per viewing ray. To stay
  // unbiased at ANY hit, not just the anchor, the uniform share goes to every light:
  //     p_j = (1 - a) w_j(anchor) / W(anchor) + a / N       (p_j = 1/N if W(anchor) = 0)
  // so p_j > 0 everywhere; a light that cannot reach the hit returns 0 without a shadow ray.
  struct Choice {
    // Cumulative p_j over all lights (last = 1), then 2.0 up to a multiple of kChoiceBlock
    // entries, so a search reads whole blocks; `coarse` holds every block's last entry.
    std::vector<float> cdf;
    std::vector<float> coarse;
    size_t lights = 0;
    vec3 anchor{0.0f};
    vec3 normal{0.0f};
    uint32_t mesh = 0;
    bool valid = false;
  };
  void prepare_choice(const ReceiverPoint& anchor, uint32_t mesh, Choice& choice) const;
  // Whether `choice` may serve x (same mesh, normals within ~25 degrees); any choice gives an
  // unbiased estimate, this only keeps the variance near the per-hit one.
  static bool choice_fits(const Choice& choice, const ReceiverPoint& x, uint32_t mesh);
  DirectEstimate one_shadow_ray(const ReceiverPoint& x, const Choice& choice, float u_select,
                                vec2 u_point) const;

  // The two estimators above with the visibility test left to the caller (see
  // DeferredEstimate): the shadow ray is written into `shadow_ray` (in place, so a caller can
  // point it into its ray buffer). one_shadow_ray is exactly these plus Accel::occluded.
  DeferredEstimate sample_one_light(const ReceiverPoint& x, float u_select, vec2 u_point,
                                    Ray& shadow_ray) const;
  // `chosen`, if given, is chosen_light(choice, u_select), found earlier.
  DeferredEstimate sample_one_light(const ReceiverPoint& x, const Choice& choice, float u_select,
                                    vec2 u_point, Ray& shadow_ray,
                                    size_t chosen = kNotChosen) const;
  static constexpr size_t kNotChosen = ~size_t(0);
  // The light a prepared `choice` gives u_select, and a prefetch of what that light's shadow
  // ray reads. The choice is known before a hit is shaded, so a caller can find the light
  // then and let its loads (which miss L1 when it is one of many) run beside the shading.
  size_t chosen_light(const Choice& choice, float u_select) const;
  void prefetch_light(size_t light) const {
    if (light >= records_.size()) return;
    const char* record = reinterpret_cast<const char*>(&records_[light]);
    __builtin_prefetch(record);
    __builtin_prefetch(record + 64);
  }

  // The reference: one shadow ray to every light, point `u_points[j]` on light j (light_count()
  // points; a lamp ignores its point).
  // Returns the sum of f_j(y_j) A_j V_j; counts the shadow rays in `shadow_rays`.
  vec3 every_light(const ReceiverPoint& x, const vec2* u_points, uint64_t& shadow_rays) const;

  // f_j(y) A_j V(x, y) for a given light sample, without the selection probability.
  vec3 contribution(const ReceiverPoint& x, size_t light, vec2 u_point, bool& traced) const;

 private:
  // Fills weights_[j] with the Eq. 2 estimate of light j at x, or -1 where the light cannot
  // reach x; returns the sum of the estimates and the number of reachable lights. One pass over
  // structure-of-arrays data, no square roots for planar lights, so it vectorises: the paper's
  // "estimate every light" stays cheap beside one ray even for 100 lights.
  double eq2_weights(const ReceiverPoint& x, float* weights, int& reachable) const;
  // f_j(y) A_j for a point y on light j and the shadow ray x -> y; false (and nothing to
  // trace) when y cannot light x.
  bool unoccluded_contribution(const ReceiverPoint& x, size_t light, vec2 u_point, vec3& f_over_pdf,
                               Ray& shadow_ray) const;
  DirectEstimate traced(const DeferredEstimate& deferred, const Ray& shadow_ray) const;
  // Light j (a lamp, j >= lights().size()) seen from x: its irradiance and direction (pdf 0
  // when it cannot light x); `weight` its luminance-weighted E/pi, Eq. 2's exact value for it.
  LightTowards lamp_towards(const ReceiverPoint& x, size_t light, float& weight) const;

  const Scene& scene_;
  const Accel& accel_;
  LightSources sources_;       // its area lights are lights(), indices 0 .. lights().size() - 1
  std::vector<size_t> lamps_;  // the lamps' indices in sources_ (those that emit)
  // Per light, structure of arrays.
  std::vector<float> cx_, cy_, cz_;   // centroid
  std::vector<float> nx_, ny_, nz_;   // mean normal
  std::vector<float> radius_;         // bounding sphere about the centroid
  std::vector<float> lum_area_;       // luminance(L) * A / pi
  std::vector<float> min_d2_;         // A / 4: Eq. 2's d^2 is clamped below by this
  std::vector<float> planar_;         // 1 if all triangles face the normal in one plane, else 0
  std::vector<uint32_t> non_planar_;  // indices of the lights with planar_ == 0
  std::vector<uint32_t> two_sided_;   // planar two-sided lights: Eq. 2 with |cos_y|
  // The area lights' triangles packed light after light, for AreaLight::sample's point with
  // one or two cache lines per light: a shadow ray's light is random among them, and reaching
  // through Scene's meshes missed the cache (100 lights: the sample cost twice one light's).
  struct SampleTriangle {
    vec3 p0, p1, p2, normal;
  };
  std::vector<float> sample_cdf_;                 // each light's triangle_cdf, concatenated
  std::vector<SampleTriangle> sample_triangles_;  // parallel to sample_cdf_
  std::vector<uint32_t> sample_first_;            // light j's entries: [first[j], first[j + 1])
  // What a shadow ray to area light j reads, in two adjacent cache lines found from j alone:
  // through sample_first_, the CDF, the triangle and the AreaLight it was a chain of dependent
  // loads, each missing L1 once the light is random among 100 (perf: a 100-light render's
  // light point cost 1.2x one light's). Lights of more than two triangles keep their first two
  // here and read all of theirs from the arrays above.
  struct alignas(64) LightRecord {
    SampleTriangle triangles[2];
    float cdf[2];  // their triangle_cdf entries
    vec3 radiance{0.0f};
    float area = 0.0f;
    uint32_t count = 0;  // triangles
    bool two_sided = false;
  };
  std::vector<LightRecord> records_;
};

}  // namespace lb
