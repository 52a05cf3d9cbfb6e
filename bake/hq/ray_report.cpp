#include "bake/hq/ray_report.h"

#include <cstdio>
#include <nlohmann/json.hpp>

#include "bake/json_text.h"

namespace lb {

RayTable make_ray_table(const HqRayCounts& render, const BakeResult* bake) {
  RayTable table;
  table.viewing = render.viewing;
  table.shadow = render.shadow;
  table.gather = render.gather + render.gather_shadow;
  if (bake) {
    const IlluminationStats& illumination = bake->illumination.stats;
    // ray_casts counts every rtcIntersect of the pass; older bakes may only have the totals.
    table.illumination = illumination.ray_casts
                             ? illumination.ray_casts
                             : illumination.feeler_rays + illumination.illumination_rays;
    const RadiosityStats& radiosity = bake->radiosity.stats;
    table.radiosity = radiosity.ray_casts ? radiosity.ray_casts : radiosity.rays;
  }
  return table;
}

std::string format_ray_table(const RayTable& table, const std::string& label) {
  char row[256];
  const bool gather = table.gather > 0;
  std::string text = "fig.      total rays   view rays  shad. rays  illum. rays  radios. rays";
  text += gather ? "  gather rays\n" : "\n";
  std::snprintf(row, sizeof row, "%-6s %14llu %10.1f%% %10.1f%% %11.2f%% %12.2f%%", label.c_str(),
                static_cast<unsigned long long>(table.total()),
                100.0 * table.fraction(table.viewing), 100.0 * table.fraction(table.shadow),
                100.0 * table.fraction(table.illumination),
                100.0 * table.fraction(table.radiosity));
  text += row;
  if (gather) {
    std::snprintf(row, sizeof row, " %11.1f%%", 100.0 * table.fraction(table.gather));
    text += row;
  }
  return text + "\n";
}

std::string render_report_json(const RenderReportInfo& info, const HqStats& stats,
                               const RayTable& table) {
  nlohmann::json report;
  report["generator"] = "lightbake";  // lets a later run know it may replace this file
  report["scene"] = info.scene_path;
  report["bake_dir"] = info.bake_dir;
  report["output"] = info.output_path;
  report["camera"] = info.camera;
  report["width"] = info.params.width;
  report["height"] = info.params.height;
  report["samples_per_side"] = info.params.samples_per_side;
  report["passes"] = info.passes;
  report["samples_per_pixel"] =
      info.passes * info.params.samples_per_side * info.params.samples_per_side;
  report["seed"] = info.params.seed;
  report["max_depth"] = info.params.max_depth;
  // 0: the soft term interpolated from the vertex radiosity; N: N gather rays per diffuse hit.
  report["final_gather"] = info.params.final_gather;
  report["bake_seconds"] = info.bake_seconds;
  report["pass_seconds"] = stats.pass_seconds;
  double render_seconds = 0.0;
  for (double s : stats.pass_seconds) render_seconds += s;
  report["render_seconds"] = render_seconds;
  const auto kind = [&](uint64_t count) {
    return nlohmann::json{{"count", count}, {"fraction", table.fraction(count)}};
  };
  report["rays"] = {
      {"total", table.total()},
      {"viewing", kind(table.viewing)},
      {"shadow", kind(table.shadow)},
      {"illumination", kind(table.illumination)},
      {"radiosity", kind(table.radiosity)},
      {"gather", kind(table.gather)},
      {"shadow_per_viewing", table.viewing ? double(table.shadow) / double(table.viewing) : 0.0}};
  report["rays_per_second"] =
      render_seconds > 0.0 ? double(table.viewing + table.shadow + table.gather) / render_seconds
                           : 0.0;
  return json_text(report, 2) + "\n";
}

}  // namespace lb
