#pragma once
// The paper's Table 1: rays by kind (viewing, shadow, illumination, radiosity) with their
// proportions, printed and written into the render's JSON report.

#include <cstdint>
#include <string>
#include <vector>

#include "bake/bake_result.h"
#include "bake/hq/hq_render.h"

namespace lb {

struct RayTable {
  uint64_t viewing = 0;
  uint64_t shadow = 0;
  uint64_t illumination = 0;  // the bake's pass 1: every ray cast (feelers, dense rays, bounces)
  uint64_t radiosity = 0;     // the bake's pass 2: every ray cast
  uint64_t gather = 0;        // HQ's final gather: its rays, bounces and shadow rays
  uint64_t total() const { return viewing + shadow + illumination + radiosity + gather; }
  double fraction(uint64_t part) const { return total() ? double(part) / double(total()) : 0.0; }
};

// `bake` may be null (a render of an unbaked scene).
RayTable make_ray_table(const HqRayCounts& render, const BakeResult* bake);

// "fig.  total rays  view rays  shad. rays  illum. rays  radios. rays" and one row, as Table 1
// (and "gather rays" after them when the render gathered).
std::string format_ray_table(const RayTable& table, const std::string& label);

struct RenderReportInfo {
  std::string scene_path;
  std::string bake_dir;  // empty: baked in this run
  std::string output_path;
  std::string camera;
  HqParams params;
  int passes = 1;
  double bake_seconds = 0.0;
};

// The render's JSON report (pretty-printed): settings, seconds per pass, ray table.
std::string render_report_json(const RenderReportInfo& info, const HqStats& stats,
                               const RayTable& table);

}  // namespace lb
