#pragma once
// The reference render's JSON report: what was rendered, how long it took, rays by kind and
// the image's own noise estimate.

#include <string>

#include "bake/reference/reference.h"

namespace lb::reference {

struct ReportInfo {
  std::string scene_path;
  std::string output_path;
  std::string camera;
};

std::string report_json(const ReportInfo& info, const ReferenceParams& params, const Film& film,
                        const ReferenceStats& stats);

}  // namespace lb::reference
