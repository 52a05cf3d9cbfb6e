#include "fuzz/fuzz_targets.h"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "bake/io/mesh_files.h"
#include "bake/io/scene_load.h"
#include "bake/pipeline/bake_io.h"

namespace lb {

namespace {

namespace fs = std::filesystem;

// One temporary folder per process, so parallel fuzzers and ctest -j do not collide.
// Never destroyed, so the exit handler that removes it can still read it.
const fs::path& work_dir() {
  static const fs::path* dir = [] {
    auto* d =
        new fs::path(fs::temp_directory_path() / ("lightbake-fuzz-" + std::to_string(::getpid())));
    fs::remove_all(*d);
    fs::create_directories(*d);
    std::atexit([] {
      std::error_code ignored;
      fs::remove_all(work_dir(), ignored);
    });
    return d;
  }();
  return *dir;
}

std::string write_input(const std::string& name, std::string_view bytes) {
  const fs::path path = work_dir() / name;
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(bytes.data(), std::streamsize(bytes.size()));
  return path.string();
}

std::string_view as_text(const uint8_t* data, size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

int load_scene_file(const std::string& name, const uint8_t* data, size_t size) {
  try {
    load_scene(write_input(name, as_text(data, size)));
  } catch (const SceneError&) {
  }
  return 0;
}

int load_mesh_file(const std::string& name, const uint8_t* data, size_t size) {
  try {
    std::vector<std::string> warnings;
    read_mesh_file(write_input(name, as_text(data, size)), 30.0f, "fuzz", warnings);
  } catch (const SceneError&) {
  }
  return 0;
}

// fuzz/bake_scene.toml: the scene every fuzzed bake directory claims to belong to.
const Scene& bake_scene() {
  static const Scene scene = load_scene(LIGHTBAKE_FUZZ_BAKE_SCENE).scene;
  return scene;
}

}  // namespace

int fuzz_toml(const uint8_t* data, size_t size) {
  return load_scene_file("scene.toml", data, size);
}

int fuzz_gltf(const uint8_t* data, size_t size) {
  return load_scene_file("scene.gltf", data, size);
}

int fuzz_obj(const uint8_t* data, size_t size) {
  return load_mesh_file("mesh.obj", data, size);
}
int fuzz_ply(const uint8_t* data, size_t size) {
  return load_mesh_file("mesh.ply", data, size);
}
int fuzz_stl(const uint8_t* data, size_t size) {
  return load_mesh_file("mesh.stl", data, size);
}

int fuzz_bake_dir(const uint8_t* data, size_t size) {
  const Scene& scene = bake_scene();
  const fs::path directory = work_dir() / "bake";
  fs::remove_all(directory);
  fs::create_directories(directory);
  const std::string_view text = as_text(data, size);
  const std::string_view separator = kBakeFileSeparator;
  size_t start = 0;
  for (const char* name :
       {"manifest.json", "illumination.bin", "radiosity.bin", "illumination.exr"}) {
    if (start > text.size()) break;
    const size_t end = std::min(text.find(separator, start), text.size());
    write_input("bake/" + std::string(name), text.substr(start, end - start));
    start = end + separator.size();
  }
  try {
    load_bake(directory.string(), scene);
  } catch (const std::runtime_error&) {
  }
  return 0;
}

}  // namespace lb
