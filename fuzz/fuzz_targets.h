#pragma once
// Fuzz entry points, one per input format. Each takes the bytes of one input, loads it the way
// the command line would, and returns 0; a rejected input is a SceneError (or, for a bake
// directory, std::runtime_error) and is fine. Anything else (a crash, a sanitizer report, an
// exception of another type, a hang) is a finding.
//
// The same functions back the libFuzzer executables (fuzz_main.cpp, -DLIGHTBAKE_FUZZ=ON with
// clang) and the corpus replay test (replay_test.cpp, every build). docs/fuzzing.md.

#include <cstddef>
#include <cstdint>

namespace lb {

int fuzz_toml(const uint8_t* data, size_t size);  // a .toml scene
int fuzz_gltf(const uint8_t* data, size_t size);  // a .gltf or .glb (chosen by its magic)
int fuzz_obj(const uint8_t* data, size_t size);   // a mesh file, as a TOML object reads it
int fuzz_ply(const uint8_t* data, size_t size);
int fuzz_stl(const uint8_t* data, size_t size);
// A bake directory for a fixed two-quad scene: the input is manifest.json, illumination.bin,
// radiosity.bin and illumination.exr, separated by kBakeFileSeparator (missing parts: absent).
int fuzz_bake_dir(const uint8_t* data, size_t size);
inline constexpr const char* kBakeFileSeparator = "\n--lightbake-fuzz-file--\n";

}  // namespace lb
