#include "app/bake_summary.h"

#include <cstdio>

#include "bake/work_limits.h"

namespace lb::app {

void print_bake_summary(const Scene& scene, const BakeResult& bake, const std::string& directory) {
  const IlluminationStats& i = bake.illumination.stats;
  const RadiosityStats& r = bake.radiosity.stats;
  std::printf(
      "illumination  %dx%d atlas at %.4g texels/m, %llu feeler + %llu dense rays (%llu casts), "
      "zones %llu/%llu traced, %.3f s\n",
      bake.illumination.width, bake.illumination.height,
      double(texel_density(bake.illumination.texel_size)), (unsigned long long)i.feeler_rays,
      (unsigned long long)i.illumination_rays, (unsigned long long)i.ray_casts,
      (unsigned long long)i.zones_traced, (unsigned long long)i.zones_total, i.seconds);
  std::printf("              caustic power (%.4g, %.4g, %.4g) W of (%.4g, %.4g, %.4g) W sent\n",
              i.power_deposited.x, i.power_deposited.y, i.power_deposited.z, i.power_sent.x,
              i.power_sent.y, i.power_sent.z);
  // The caustic pilot's choices (IlluminationParams::pilot_texels): finer texels and why; the
  // first few by name (a level refines hundreds of floors; the manifest lists every one).
  constexpr int kPilotLines = 8;
  int refined = 0;
  for (size_t m = 0; m < i.pilot_texel_size.size() && m < scene.meshes.size(); ++m) {
    if (i.pilot_texel_size[m] <= 0.0f) continue;
    if (refined++ < kPilotLines)
      std::printf(
          "              '%s': %.3g cm texels for its caustic (%.3g deposits/m^2 at peak)\n",
          scene.meshes[m].name.c_str(), 100.0 * double(i.pilot_texel_size[m]),
          double(i.pilot_peak_density[m]));
  }
  if (refined > kPilotLines)
    std::printf(
        "              and %d more meshes with finer caustic texels (manifest: "
        "illumination.stats.pilot_texel_size)\n",
        refined - kPilotLines);
  std::printf(
      "radiosity     %zu patches, %llu shots, %llu light + %llu patch rays "
      "(%llu casts), %.3f s (setup %.3f s)\n",
      r.patch_count, (unsigned long long)r.shots, (unsigned long long)r.light_rays,
      (unsigned long long)r.rays, (unsigned long long)r.ray_casts, r.seconds, r.setup_seconds);
  std::printf("              residual %.3g of emitted (%s), emitted (%.4g, %.4g, %.4g) W\n",
              r.residual_fraction, r.converged ? "converged" : "NOT converged: work cap hit",
              r.power_emitted.x, r.power_emitted.y, r.power_emitted.z);
  std::printf("memory        %s at most, for %zu triangles and %d x %d texels\n",
              format_bytes(double(peak_resident_bytes())).c_str(), triangle_count(scene),
              bake.illumination.width, bake.illumination.height);
  std::printf("saved         %s\n", directory.c_str());
}

}  // namespace lb::app
