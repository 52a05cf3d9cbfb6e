#pragma once
// Offscreen rendering of one view (the `lightbake snapshot` command and the image tests).

#include <string>

#include "bake/bake_result.h"
#include "bake/io/image_io.h"
#include "viewer/render_settings.h"
#include "viewer/shader_program.h"
#include "viewer/view_camera.h"

namespace lb {

struct SnapshotOptions {
  std::string camera;  // a scene camera's name or index; empty: the first, else fit-to-scene
  int width = 640;
  int height = 480;
  RenderSettings settings;
  ShadowSettings shadows;
  std::string shader_directory = default_shader_directory();
};

// The camera `name_or_index` of the scene; throws std::invalid_argument naming the choices.
ViewCamera choose_camera(const Scene& scene, const std::string& name_or_index);

// Linear radiance (RGB, top row first) rendered with OSMesa on the calling thread.
Image render_snapshot(const Scene& scene, const BakeResult* bake, const SnapshotOptions& options);

}  // namespace lb
