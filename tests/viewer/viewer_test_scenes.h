#pragma once
// Scenes and reference computations shared by the viewer tests.

#include <string>

#include "bake/accel.h"
#include "bake/bake_result.h"
#include "bake/io/image_io.h"
#include "bake/scene.h"
#include "viewer/view_camera.h"

namespace lb::test {

// A Figure 6-like room built in code: 4 x 3 x 4 m, one 0.6 m ceiling light, a table on four
// thin legs (sharp leg shadows) and a block; one camera. `light_size` scales the light.
Scene make_table_room(float light_size = 0.6f);

// A closed box, |x|, |y|, |z| <= half_size, whose inside emits 1 W/(sr m^2) and reflects
// nothing: a uniform field, in which any lossless specular surface shows exactly 1 and any
// other its directional albedo.
void add_uniform_field(Scene& scene, float half_size);

// The world-space ray through the centre of pixel (x, y) (top row first), exactly as the
// rasteriser samples it: glm::lookAt + glm::perspective conventions.
Ray camera_ray(const ViewCamera& camera, int width, int height, int x, int y);

// Ray-traced R * E/pi of the direct light, per pixel: the same camera ray, the hit point,
// and n x n stratified shadow rays to every light (visibility included when `shadows`).
Image ray_traced_direct(const Scene& scene, const ViewCamera& camera, int width, int height, int n,
                        bool shadows);

// lb::write_comparison into the test output directory; prints where the files went.
void write_comparison_files(const std::string& name, const Image& image, const Image& reference);

// A bake made by hand with known values: every diffuse mesh keeps its geometry and gets a
// constant vertex radiosity `radiosity`, and a 4 x 4 illumination atlas of constant `caustic`
// with all lightmap uvs at its centre; triangle t of each mesh is patch 1000 * mesh + t.
BakeResult make_constant_bake(const Scene& scene, vec3 radiosity, vec3 caustic);

}  // namespace lb::test
