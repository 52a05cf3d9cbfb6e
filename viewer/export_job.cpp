#include "viewer/export_job.h"

#include <filesystem>
#include <stdexcept>
#include <system_error>

#include "bake/io/image_io.h"
#include "bake/probes/dynamic_light.h"

namespace lb {

namespace fs = std::filesystem;

std::string default_export_path(const std::string& scene_path) {
  const fs::path scene(scene_path);
  fs::path out = scene.parent_path() / (scene.stem().string() + ".glb");
  if (out == scene) out = scene.parent_path() / (scene.stem().string() + "_export.glb");
  return out.string();
}

namespace {

// The rule of app/output_path.h's prepare_output_file, without --force: an existing file is
// replaced only when lightbake wrote it (a glTF by its asset.generator, an image by its stamp).
std::string existing_file_problem(const std::string& path, bool gltf) {
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (!fs::exists(status)) return "";
  if (!fs::is_regular_file(status)) return path + ": exists and is not a file; choose another name";
  const bool ours = gltf ? is_lightbake_gltf(path) : is_lightbake_image(path);
  return ours ? "" : path + ": exists and was not written by lightbake; choose another name";
}

}  // namespace

std::string export_path_problem(const std::string& path) {
  const std::string extension = fs::path(path).extension().string();
  if (extension != ".glb" && extension != ".gltf")
    return path + ": the output must be a .glb or .gltf file";
  const fs::path folder = fs::absolute(path).parent_path();
  std::error_code error;
  if (!fs::is_directory(folder, error))
    return path + ": folder '" + folder.string() + "' does not exist";
  std::string problem = existing_file_problem(path, true);
  if (problem.empty()) problem = existing_file_problem(lightmap_exr_path(path), false);
  return problem;
}

bool ExportJob::start(const std::string& path, const Scene& scene, const BakeResult* bake,
                      const BakeParams& params, const ExportSettings& settings) {
  job_.stop();
  {
    std::lock_guard lock(mutex_);
    result_.reset();
  }
  if (const std::string problem = export_path_problem(path); !problem.empty()) {
    job_.fail(problem, "refused");
    return false;
  }
  GltfExportOptions resolved;
  try {
    resolved = resolve_export_settings(settings);
  } catch (const std::invalid_argument& e) {
    job_.fail(e.what(), "refused");
    return false;
  }
  std::optional<BakeResult> given;
  if (bake) given = *bake;
  job_.start(
      [this, path, scene, given = std::move(given), params,
       options = std::move(resolved)](const Progress& job) mutable {
        // The bake, when there is one to make, is the long part: 0..0.9 of the bar.
        Progress progress = job;
        progress.report = [this](std::string_view stage, double fraction) {
          job_.report("baking: " + std::string(stage), 0.9 * fraction);
        };
        if (!given) {  // a directional export bakes the bands too, as `lightbake export`
          BakeParams asked = params;
          if (options.directional) asked.illumination.directional = true;
          given = bake_scene(scene, asked, progress);
        }
        progress.throw_if_cancelled();
        // Moving objects: the probe grid and each object's blend of it, as `lightbake export`
        // writes them (docs/light-probes.md); 0.9..0.99 of the bar.
        ExportProbes probes;
        if (!scene.dynamic_meshes.empty()) {
          progress.report = [this](std::string_view stage, double fraction) {
            job_.report("light probes: " + std::string(stage), 0.9 + 0.09 * fraction);
          };
          probes = bake_export_probes(scene, *given, {}, progress);
          progress.throw_if_cancelled();
          options.light_probes = &probes.grid;
          options.dynamic_sh = &probes.blends;
        }
        job_.report("writing " + fs::path(path).filename().string(), 0.99);
        const GltfExportInfo info = export_gltf(path, scene, *given, options);
        {
          std::lock_guard lock(mutex_);
          result_ = info;
        }
        job_.report("done", 1.0);
      },
      "cancelled; nothing written");
  return true;
}

std::optional<GltfExportInfo> ExportJob::take_result() {
  std::lock_guard lock(mutex_);
  std::optional<GltfExportInfo> result = std::move(result_);
  result_.reset();
  return result;
}

}  // namespace lb
