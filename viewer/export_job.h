#pragma once
// The viewer's Export button: writes the shown bake as glTF 2.0 (bake/export/gltf_export.h) on a
// background thread, baking first when the window has no bake yet, with the progress, Cancel
// and error line of BakeJob. The output rules are the CLI's (app/output_path.h), except that a
// missing folder is refused rather than created (a typo in a text field should not make one).

#include <mutex>
#include <optional>
#include <string>

#include "bake/export/export_settings.h"
#include "bake/export/gltf_export.h"
#include "bake/pipeline/bake.h"
#include "viewer/background_job.h"

namespace lb {

// "NAME.glb" beside the scene file; "NAME_export.glb" when that is the scene file itself.
std::string default_export_path(const std::string& scene_path);

// Empty when `path` may be written: .glb or .gltf, an existing folder, and neither it nor its
// .lightmap.exr an existing file that lightbake did not write (or not a file at all);
// otherwise the one-line reason, starting with the path.
std::string export_path_problem(const std::string& path);

class ExportJob {
 public:
  // Checks the path (export_path_problem; the error() when refused, and false), then writes a
  // copy of `scene` with a copy of `bake`, or with a bake made with `params` when `bake` is
  // null, and its moving objects' light probes (bake_export_probes), as `lightbake export`
  // does. Cancel stops the bake; the writing itself (under 2 s) is not interrupted, and both
  // files appear whole or not at all (export_gltf writes through temporary files).
  // `settings`: what the file holds, checked and resolved as `lightbake export` does
  // (export_settings.h; a refusal is the error() and false, before any bake).
  bool start(const std::string& path, const Scene& scene, const BakeResult* bake,
             const BakeParams& params, const ExportSettings& settings = {});
  void cancel() { job_.cancel(); }
  bool running() const { return job_.running(); }
  double fraction() const { return job_.fraction(); }
  std::string stage() const { return job_.stage(); }
  std::string error() const { return job_.error(); }  // refusal, bake or write failure
  // The finished export's summary, once.
  std::optional<GltfExportInfo> take_result();

 private:
  std::mutex mutex_;
  std::optional<GltfExportInfo> result_;
  BackgroundJob job_;  // last: joined before the result above is destroyed
};

}  // namespace lb
