// Patches: refinement keeps the surface and is conforming, grouping hits the target size and
// never crosses a crease, vertex averaging never bleeds across one.

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "bake/radiosity/patches.h"
#include "scenes.h"
#include "test_helpers.h"

namespace lb {
namespace {

Mesh make_grid(int n, float size, int material) {
  Mesh mesh;
  mesh.material = material;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      mesh.positions.push_back({size * float(i) / float(n), 0.0f, size * float(j) / float(n)});
      mesh.normals.push_back({0, 1, 0});
      mesh.uvs.push_back({float(i) / float(n), float(j) / float(n)});
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const uint32_t a = uint32_t(j * (n + 1) + i), b = a + 1, c = a + uint32_t(n) + 2,
                     d = a + uint32_t(n) + 1;
      mesh.triangles.push_back({a, d, c});  // front = +y
      mesh.triangles.push_back({a, c, b});
    }
  return mesh;
}

TEST(Patches, RefinementKeepsAreaAndInterpolatesAttributes) {
  Mesh quad = test::make_quad({0, 0, 0}, {3, 0, 0}, {0, 2, 0}, 0);
  quad.lightmap_uvs = {{0.1f, 0.1f}, {0.4f, 0.1f}, {0.4f, 0.3f}, {0.1f, 0.3f}};
  quad.tangents.assign(4, vec4(1, 0, 0, 1));
  const float max_edge = 0.25f;
  const Mesh refined = refine_mesh(quad, max_edge);
  EXPECT_GT(refined.triangles.size(), 150u);
  EXPECT_NEAR(mesh_area(refined), 6.0f, 6.0f * 1e-5f);
  ASSERT_EQ(refined.uvs.size(), refined.positions.size());
  ASSERT_EQ(refined.lightmap_uvs.size(), refined.positions.size());
  ASSERT_EQ(refined.tangents.size(), refined.positions.size());
  for (size_t v = 0; v < refined.positions.size(); ++v) {
    const vec3 p = refined.positions[v];
    // The quad's attributes are linear in position: midpoints must keep that exactly.
    EXPECT_NEAR(refined.uvs[v].x, p.x / 3.0f, 1e-6f);
    EXPECT_NEAR(refined.uvs[v].y, p.y / 2.0f, 1e-6f);
    EXPECT_NEAR(refined.lightmap_uvs[v].x, 0.1f + 0.1f * p.x, 1e-6f);
    EXPECT_NEAR(refined.lightmap_uvs[v].y, 0.1f + 0.1f * p.y, 1e-6f);
    EXPECT_NEAR(glm::length(refined.normals[v]), 1.0f, 1e-6f);
    EXPECT_EQ(refined.tangents[v], vec4(1, 0, 0, 1));
  }
  for (const uvec3& t : refined.triangles)
    for (int k = 0; k < 3; ++k)
      EXPECT_LE(glm::length(refined.positions[t[k]] - refined.positions[t[(k + 1) % 3]]),
                max_edge * (1.0f + 1e-6f));
  for (size_t t = 0; t < refined.triangles.size(); ++t)
    EXPECT_GT(glm::dot(triangle_normal(refined, t), vec3(0, 0, 1)), 0.999f);  // orientation kept
}

TEST(Patches, RefinedClosedSurfacesHaveNoCracks) {
  // The box's six faces have separate vertices (seams at every edge) and different sizes, so
  // conformity must come from the geometric split rule, not from shared vertices.
  Scene scene = test::make_room();
  const Patches patches = build_patches(scene, 0.3f, true);
  for (int m : {0, 1}) {
    const Mesh& refined = patches.meshes[size_t(m)].mesh;
    EXPECT_NEAR(mesh_area(refined), mesh_area(scene.meshes[size_t(m)]),
                1e-5f * mesh_area(scene.meshes[size_t(m)]));
    int bad = 0;
    for (const auto& [edge, count] : test::edge_uses(refined)) bad += count != 2;
    EXPECT_EQ(bad, 0) << "mesh " << m << ": edges not shared by exactly two triangles";
  }
  const Scene sphere = test::make_emitting_sphere(0.5f, 1.0f, 20.0f, 12, 24);
  const Patches sp = build_patches(sphere, 0.2f, true);
  Mesh whole = sp.meshes[0].mesh;  // sphere body and cap together must close up
  const Mesh& cap = sp.meshes[1].mesh;
  const uint32_t base = uint32_t(whole.positions.size());
  whole.positions.insert(whole.positions.end(), cap.positions.begin(), cap.positions.end());
  for (uvec3 t : cap.triangles) whole.triangles.push_back(t + uvec3(base));
  int bad = 0;
  for (const auto& [edge, count] : test::edge_uses(whole)) bad += count != 2;
  EXPECT_EQ(bad, 0);
}

TEST(Patches, CountNearTargetAndCreasesNotCrossed) {
  const Scene scene = test::make_room();
  for (float h : {0.5f, 0.2f}) {
    const Patches patches = build_patches(scene, h, true);
    double area = 0.0;
    for (const Mesh& mesh : scene.meshes) area += mesh_area(mesh);
    const double target = area / double(h * h);
    EXPECT_GT(double(patches.patches.size()), 0.6 * target) << "h " << h;
    EXPECT_LT(double(patches.patches.size()), 1.5 * target) << "h " << h;
    for (const Patch& patch : patches.patches) {
      const Mesh& mesh = patches.meshes[patch.mesh].mesh;
      for (uint32_t t : patch.triangles)  // box faces are flat: a patch is on exactly one face
        ASSERT_GT(glm::dot(triangle_normal(mesh, t), patch.normal), 0.9999f);
      EXPECT_LT(patch.area, 2.5 * double(h * h));
    }
  }
}

TEST(Patches, TinyTrianglesAreGrouped) {
  Scene scene;
  const int material = test::add_material(scene, Material{});
  scene.meshes.push_back(make_grid(64, 2.0f, material));  // 8192 triangles of 0.0005 m^2
  const Patches patches = build_patches(scene, 0.5f, true);
  EXPECT_EQ(patches.meshes[0].mesh.triangles.size(), 8192u);  // nothing to split
  EXPECT_GE(patches.patches.size(), 10u);
  EXPECT_LE(patches.patches.size(), 24u);  // target 4 m^2 / 0.25 m^2 = 16
}

TEST(Patches, AutomaticSizeIsAboutSixteenBySixteenPerWall) {
  const Scene scene = test::make_room();
  EXPECT_NEAR(automatic_patch_size(scene), std::sqrt(16.0f / 256.0f), 1e-5f);
  const Patches patches = build_patches(scene, 0.0f, true);
  size_t on_floor = 0;  // the floor is the 4 x 4 m face with normal +y of the room
  for (const Patch& patch : patches.patches) on_floor += patch.mesh == 0 && patch.normal.y > 0.99f;
  // Target 16 m^2 / 0.0625 m^2 = 256, plus the pieces cut along the block's footprint.
  EXPECT_GE(on_floor, 192u);
  EXPECT_LE(on_floor, 320u);
}

TEST(Patches, AutomaticSizeIsCappedAtHalfAMetre) {
  // A 40 x 40 m floor: 16 x 16 a face would give sqrt(1600 / 256) = 2.5 m patches.
  Scene scene;
  const int material = test::add_material(scene, Material{});
  scene.meshes.push_back(make_grid(4, 40.0f, material));
  EXPECT_EQ(automatic_patch_size(scene), kMaxAutomaticPatchSize);
  EXPECT_EQ(kMaxAutomaticPatchSize, 0.5f);
  // 1600 m^2 / 0.25 m^2 = 6400 patches; measured 6784 (grouping leaves some under h^2).
  const size_t count = build_patches(scene, 0.0f, true).patches.size();
  EXPECT_GE(count, 5600u);
  EXPECT_LE(count, 7200u);
}

TEST(Patches, VertexAveragingDoesNotBleedAcrossCreases) {
  Scene scene;
  const int material = test::add_material(scene, Material{});
  // A box with welded corners (shared vertices across creases): the crease split must
  // separate them.
  Mesh box;
  box.material = material;
  const Mesh faces = test::make_box({0, 0, 0}, {1, 1, 1}, material, false);
  std::map<std::array<float, 3>, uint32_t> index;
  for (uvec3 t : faces.triangles) {
    uvec3 welded;
    for (int k = 0; k < 3; ++k) {
      const vec3 p = faces.positions[t[k]];
      auto [it, inserted] = index.try_emplace({p.x, p.y, p.z}, uint32_t(box.positions.size()));
      if (inserted) box.positions.push_back(p);
      welded[k] = it->second;
    }
    box.triangles.push_back(welded);
  }
  ASSERT_EQ(box.positions.size(), 8u);
  scene.meshes.push_back(box);
  const Patches patches = build_patches(scene, 0.25f, true);
  // Radiance = the patch's face (by normal) -> 1..6; vertices must show their own face's.
  auto face_value = [](vec3 n) {
    for (int axis = 0; axis < 3; ++axis)
      if (std::abs(n[axis]) > 0.9f) return float(2 * axis + (n[axis] > 0) + 1);
    return 0.0f;
  };
  std::vector<vec3> patch_radiance;
  for (const Patch& patch : patches.patches)
    patch_radiance.push_back(vec3(face_value(patch.normal)));
  const PatchMesh& pm = patches.meshes[0];
  const std::vector<vec3> radiance =
      vertex_radiance_from_patches(pm, patches.patches, patch_radiance);
  for (size_t t = 0; t < pm.mesh.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      ASSERT_EQ(radiance[pm.mesh.triangles[t][k]].x, face_value(triangle_normal(pm.mesh, t)));
}

}  // namespace
}  // namespace lb
