#pragma once
// Limits on what a scene file may ask for, checked before the work or memory is spent.
// Each is far beyond any scene the baker can finish, and far below what crashes the process
// or exhausts a workstation's memory. Errors quote the limit; docs/scene_format.md and
// docs/gltf.md list them.

#include <cstddef>
#include <cstdint>

namespace lb::limits {

// Fuzzing builds (LIGHTBAKE_FUZZ) divide the count limits by this: under ASan the loaders run
// ~100x slower (262,000 empty glTF node visits: 0.03 s in Release, 9.7 s under ASan), and an
// input just under a limit must still finish within libFuzzer's 20 s timeout.
#ifdef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
inline constexpr uint64_t kFuzzDivisor = 10;
#else
inline constexpr uint64_t kFuzzDivisor = 1;
#endif

// JSON nesting ([ and {) in a glTF. Real files nest < 20 deep; tinygltf converts JSON
// recursively and overflows an 8 MB stack near 100,000 levels.
inline constexpr int kMaxJsonDepth = 512;

// Mesh instances a scene may place (glTF node DAG, TOML definitions). Each instance is copied
// into world space as its own mesh: 786,000 one-triangle instances took 2.8 s and 465 MB to
// load (25 s under ASan), so 200,000 keeps loading under a second and ~120 MB.
inline constexpr uint64_t kMaxInstances = 200'000 / kFuzzDivisor;

// glTF nodes visited while expanding the hierarchy (a DAG can reach 2^30 visits with 31 nodes).
inline constexpr uint64_t kMaxNodeVisits = 1'000'000 / kFuzzDivisor;

// Triangles after instancing: a bake holds ~330 bytes each at its peak (mesh, BVH, atlas,
// patches; the generated level at 1M-3M triangles, docs/farm.md "Memory"), so 50M is ~16 GB,
// about the most a 24 GB machine can bake; a bake the machine cannot hold is refused by its
// memory estimate (bake/work_limits.h) before this limit is reached.
inline constexpr uint64_t kMaxTriangles = 50'000'000 / kFuzzDivisor;

// Instances nested inside instances (TOML `define`). A chain this deep is legal; deeper is
// refused as too deep, not as a cycle.
inline constexpr int kMaxInstanceDepth = 64;

// Vertex coordinates: |x| above this makes a triangle's area (x^2 ~ 1e36) approach float's
// 3.4e38 and every ray offset meaningless. 1e18 m is 100 light years.
inline constexpr double kMaxCoordinate = 1e18;

// Texels in one decoded texture (width * height * channels, 4 bytes each as float): 2^30 is
// a 16k x 16k RGBA image, 4 GB decoded.
inline constexpr uint64_t kMaxTextureValues = uint64_t(1) << 30;

// Bytes of one line of a text mesh file (OBJ). A real line is under 200 bytes, a face of
// kMaxPolygonVertices corners with full v/vt/vn triples ~0.2 MB (a longer face is refused by
// its corner count, which needs its line read); a file with no line breaks (a sparse or binary
// file named .obj) was read whole into one string: 3 GB of zeros took 2-9 GB and minutes
// before "no triangles".
inline constexpr size_t kMaxTextLineBytes = 16 << 20;

// Vertices of one polygon in a mesh file (OBJ `f` with this many corners is a data error, and
// OpenMesh's face insertion is quadratic in the corner count).
inline constexpr size_t kMaxPolygonVertices = 10'000;

}  // namespace lb::limits
