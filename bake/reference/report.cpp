#include "bake/reference/report.h"

#include <nlohmann/json.hpp>

#include "bake/json_text.h"

namespace lb::reference {

std::string report_json(const ReportInfo& info, const ReferenceParams& params, const Film& film,
                        const ReferenceStats& stats) {
  using nlohmann::json;
  const NoiseEstimate noise = film.noise();
  const ReferenceRays& r = stats.rays;
  json report;
  report["generator"] = "lightbake";  // lets a later run know it may replace this file
  report["scene"] = info.scene_path;
  report["output"] = info.output_path;
  report["camera"] = info.camera;
  report["width"] = params.width;
  report["height"] = params.height;
  if (!params.window.empty())  // the noise and the means below are over the window's pixels
    report["window"] = {{"x0", params.window.x},
                        {"y0", params.window.y},
                        {"x1", params.window.x + params.window.width},
                        {"y1", params.window.y + params.window.height}};
  report["terms"] = params.terms == Terms::all ? "all" : "direct";
  report["seed"] = params.seed;
  report["samples_per_pixel"] = film.passes();  // one eye path per pixel per pass
  report["passes"] = film.passes();
  report["spp_requested"] = params.spp;
  report["time_limit_seconds"] = params.time_limit_seconds;
  report["light_paths_per_pixel_per_pass"] = params.light_paths_per_pixel;
  double mean = 0.0;
  const std::vector<vec3> image = film.average();  // the window's pixels
  for (const vec3& v : image) mean += (double(v.x) + double(v.y) + double(v.z)) / 3.0;
  report["image_mean_radiance"] = image.empty() ? 0.0 : mean / double(image.size());  // W/(sr m^2)
  report["cpu_seconds"] = stats.cpu_seconds;  // user + system
  report["wall_seconds"] = stats.wall_seconds;
  report["rays"] = {{"camera", r.camera},          {"bounce", r.bounce},
                    {"shadow", r.shadow},          {"light", r.light},
                    {"connection", r.connection},  {"total", r.total()},
                    {"eye_paths", r.eye_paths},    {"cut_at_max_depth", r.cut_at_max_depth},
                    {"light_paths", r.light_paths}};
  report["lost_samples"] = film.lost_samples;  // pixel values not finite or beyond film.h's bound
  report["rays_per_cpu_second"] =
      stats.cpu_seconds > 0 ? double(r.total()) / stats.cpu_seconds : 0.0;
  report["noise"] = {{"pixel_relative_standard_error", noise.pixel_relative_standard_error},
                     {"mean_relative_standard_error", noise.mean_relative_standard_error},
                     {"method", "even/odd pass halves per pixel; spread of per-pass image means"}};
  return json_text(report, 2) + "\n";
}

}  // namespace lb::reference
