// MikkTSpace tangents (bake/tangent_space.h) against hand-derived frames: a planar quad and a
// cube (exact), mirrored UVs (w = -1), and a UV sphere against each triangle's own dP/du.

#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/constants.hpp>

#include "bake/tangent_space.h"
#include "test_helpers.h"

namespace lb {
namespace {

void expect_tangent(vec4 actual, vec3 direction, float w, const std::string& what) {
  EXPECT_NEAR(actual.x, direction.x, 1e-6f) << what;
  EXPECT_NEAR(actual.y, direction.y, 1e-6f) << what;
  EXPECT_NEAR(actual.z, direction.z, 1e-6f) << what;
  EXPECT_EQ(actual.w, w) << what;
}

// A quad in the xy plane facing +z whose UVs follow the image: u right (+x), v down (-y).
Mesh image_quad() {
  Mesh quad = test::make_quad(vec3(0), vec3(2, 0, 0), vec3(0, 1, 0), 0);
  quad.uvs = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
  return quad;
}

TEST(MikkTSpace, PlanarQuadWithImageUvsHasTangentAlongUAndRightHandedFrame) {
  Mesh quad = image_quad();
  generate_mikktspace_tangents(quad);
  ASSERT_EQ(quad.tangents.size(), 4u);  // nothing to split
  ASSERT_EQ(quad.positions.size(), 4u);
  // T = dP/du = +x; the map's +Y (up the image, -dP/dv = +y) = cross(N, T): w = +1.
  for (vec4 t : quad.tangents) expect_tangent(t, vec3(1, 0, 0), 1.0f, "image quad");
}

TEST(MikkTSpace, RotatedUvsTurnTheTangent) {
  Mesh quad = image_quad();
  // u along +y, v along +x: T = +y; -dP/dv = -x = cross(+z, +y), so w = +1.
  quad.uvs = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
  generate_mikktspace_tangents(quad);
  for (vec4 t : quad.tangents) expect_tangent(t, vec3(0, 1, 0), 1.0f, "rotated uvs");
}

TEST(MikkTSpace, MirroredUvsGiveNegativeHandedness) {
  Mesh quad = image_quad();
  for (vec2& uv : quad.uvs) uv.x = 1.0f - uv.x;  // u runs to -x: the UV triangle is mirrored
  generate_mikktspace_tangents(quad);
  for (vec4 t : quad.tangents) expect_tangent(t, vec3(-1, 0, 0), -1.0f, "mirrored u");
  Mesh flipped_v = image_quad();
  for (vec2& uv : flipped_v.uvs) uv.y = 1.0f - uv.y;  // v up the quad: mirrored the other way
  generate_mikktspace_tangents(flipped_v);
  for (vec4 t : flipped_v.tangents) expect_tangent(t, vec3(1, 0, 0), -1.0f, "mirrored v");
}

TEST(MikkTSpace, CubeFacesGetTheirOwnEdgeDirections) {
  // make_box: 24 vertices, u along each face's first edge, v along its second, so -dP/dv is
  // -edge_v while cross(N, T) = +edge_v: every face is mirrored, w = -1.
  Mesh cube = test::make_box(vec3(-1, -2, -3), vec3(1, 2, 3), 0, false);
  const Mesh before = cube;
  generate_mikktspace_tangents(cube);
  ASSERT_EQ(cube.positions.size(), 24u);  // faces do not share vertices: no split
  for (size_t face = 0; face < 6; ++face) {
    const vec3 edge_u = before.positions[face * 4 + 1] - before.positions[face * 4];
    for (size_t k = 0; k < 4; ++k)
      expect_tangent(cube.tangents[face * 4 + k], glm::normalize(edge_u), -1.0f,
                     "face " + std::to_string(face) + " corner " + std::to_string(k));
  }
}

TEST(MikkTSpace, MirrorSeamSharedByValueKeepsBothSidesAndSplitsASharedVertex) {
  // Two quads side by side, the right one mirrored in u about their shared edge x = 2 (u = 1
  // there on both sides), stored with separate vertices of equal attributes.
  Mesh both = image_quad();
  Mesh right = image_quad();
  for (vec3& p : right.positions) p.x += 2.0f;
  for (vec2& uv : right.uvs) uv.x = 1.0f - uv.x;
  for (vec3 p : right.positions) both.positions.push_back(p);
  for (vec3 n : right.normals) both.normals.push_back(n);
  for (vec2 uv : right.uvs) both.uvs.push_back(uv);
  for (uvec3 t : right.triangles) both.triangles.push_back(t + uvec3(4));
  Mesh shared = both;
  generate_mikktspace_tangents(both);
  for (size_t v = 0; v < 4; ++v) expect_tangent(both.tangents[v], vec3(1, 0, 0), 1.0f, "left");
  for (size_t v = 4; v < 8; ++v) expect_tangent(both.tangents[v], vec3(-1, 0, 0), -1.0f, "right");
  // The right quad's corner at (2, 0, 0) now uses the left quad's vertex 1 (same position,
  // normal and uv): one vertex with both orientations is split in two.
  shared.triangles[2] = {1, 5, 6};
  generate_mikktspace_tangents(shared);
  ASSERT_EQ(shared.positions.size(), 9u);
  expect_tangent(shared.tangents[1], vec3(1, 0, 0), 1.0f, "vertex 1, left side");
  expect_tangent(shared.tangents[8], vec3(-1, 0, 0), -1.0f, "vertex 1's copy, right side");
  EXPECT_EQ(shared.triangles[2], uvec3(8, 5, 6));
}

TEST(MikkTSpace, TriangleSoupWeldsByValueLikeTheIndexedMesh) {
  // Unindexed output (three vertices per triangle) must give the indexed mesh's tangents:
  // corners are grouped by equal position, normal and uv, not by index.
  Mesh sphere = test::make_sphere(vec3(0), 1.0f, 8, 16, 0, false);
  Mesh soup;
  for (uvec3 t : sphere.triangles) {
    for (int k = 0; k < 3; ++k) {
      soup.positions.push_back(sphere.positions[t[k]]);
      soup.normals.push_back(sphere.normals[t[k]]);
      soup.uvs.push_back(sphere.uvs[t[k]]);
    }
    const uint32_t base = uint32_t(soup.positions.size() - 3);
    soup.triangles.push_back({base, base + 1, base + 2});
  }
  generate_mikktspace_tangents(sphere);
  generate_mikktspace_tangents(soup);
  float max_difference = 0.0f;
  for (size_t t = 0; t < sphere.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const vec4 a = sphere.tangents[sphere.triangles[t][k]], b = soup.tangents[t * 3 + size_t(k)];
      max_difference = std::max(max_difference, glm::length(vec3(a) - vec3(b)));
      EXPECT_EQ(a.w, b.w);
    }
  EXPECT_LT(max_difference, 1e-6f);
}

TEST(MikkTSpace, UvSphereFollowsEachTrianglesProjectedDpDu) {
  // 16 rings x 32 segments: u = longitude / 2 pi, v = colatitude / pi (v runs south).
  Mesh sphere = test::make_sphere(vec3(0), 1.0f, 16, 32, 0, false);
  const Mesh before = sphere;
  generate_mikktspace_tangents(sphere);
  ASSERT_EQ(sphere.positions.size(), before.positions.size());  // no seam mirrors: no split
  double max_angle_deg = 0.0, max_analytic_deg = 0.0;
  for (size_t t = 0; t < before.triangles.size(); ++t) {
    const auto d = uv_derivatives(before, t);
    ASSERT_TRUE(d);
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = before.triangles[t][k];
      const vec3 n = before.normals[v];
      const vec3 reference = glm::normalize(d->dp_du - n * glm::dot(n, d->dp_du));
      const vec4 tangent = sphere.tangents[v];
      EXPECT_NEAR(glm::dot(vec3(tangent), n), 0.0f, 1e-5f);
      EXPECT_NEAR(glm::length(vec3(tangent)), 1.0f, 1e-5f);
      const double angle =
          glm::degrees(std::acos(std::min(1.0f, glm::dot(vec3(tangent), reference))));
      max_angle_deg = std::max(max_angle_deg, angle);
      // Handedness from the UV winding: sign of (N x T) . (-dP/dv).
      const float w = glm::dot(glm::cross(n, vec3(tangent)), -d->dp_dv) > 0.0f ? 1.0f : -1.0f;
      EXPECT_EQ(tangent.w, w) << "triangle " << t;
      // The smooth surface's tangent, east along the parallel: (-sin phi, 0, cos phi).
      // Away from the seam (whose vertices see triangles on one side only) and the poles.
      const vec2 uv = before.uvs[v];
      if (uv.x > 0.0f && uv.x < 1.0f && uv.y > 0.0f && uv.y < 1.0f) {
        const vec3 east = glm::normalize(vec3(-n.z, 0.0f, n.x));
        max_analytic_deg = std::max(
            max_analytic_deg,
            double(glm::degrees(std::acos(std::min(1.0f, glm::dot(vec3(tangent), east))))));
      }
    }
  }
  // A triangle's dP/du runs along its chord of the parallel, half a segment (360/32/2 = 5.625
  // degrees) off the tangent at its ends: the vertex tangent is within that of every corner's
  // (measured 5.518). Inside the grid, the angle-weighted sum cancels the tilts: the analytic
  // tangent within 0.1 degree (measured 0.034); seam vertices see one side only.
  EXPECT_LT(max_angle_deg, 5.625) << max_angle_deg;
  EXPECT_LT(max_analytic_deg, 0.1) << max_analytic_deg;
  std::printf(
      "sphere: max angle to a triangle's projected dP/du %.3f deg, to the analytic "
      "east tangent %.4f deg\n",
      max_angle_deg, max_analytic_deg);
}

}  // namespace
}  // namespace lb
