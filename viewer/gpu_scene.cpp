#include "viewer/gpu_scene.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include <tbb/parallel_for.h>

#include "bake/lightmap/lightmap.h"
#include "bake/lightmap/seam_stitch.h"
#include "bake/probes/dynamic_light.h"

namespace lb {

namespace {

// Interleaved vertex: position 3, normal 3, uv 2, lightmap uv 2, tangent 4, radiance 3.
constexpr int kFloatsPerVertex = 17;

void detect_plane(const Mesh& mesh, GpuMesh& gpu) {
  if (mesh.triangles.empty()) return;
  const vec3 n = triangle_normal(mesh, 0);
  if (glm::dot(n, n) < 0.5f) return;
  const float d = -glm::dot(n, mesh.positions[mesh.triangles[0].x]);
  const float tolerance = 1e-4f * std::max(gpu.bounds.diagonal(), 1e-3f);
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (glm::dot(triangle_normal(mesh, t), n) < 0.9999f) return;
  }
  for (const vec3& p : mesh.positions) {
    if (std::abs(glm::dot(n, p) + d) > tolerance) return;
  }
  gpu.planar = true;
  gpu.plane = glm::vec4(n, d);
}

GpuMesh upload_mesh(const Mesh& mesh, const MeshChunks& chunks, const MeshDetail& detail,
                    const std::vector<vec3>* radiance, const std::vector<uint32_t>* patches,
                    bool has_lightmap) {
  GpuMesh gpu;
  gpu.material = mesh.material;
  gpu.has_normals = mesh.normals.size() == mesh.positions.size();
  gpu.has_lightmap = has_lightmap && mesh.lightmap_uvs.size() == mesh.positions.size();
  gpu.has_vertex_radiance = radiance && radiance->size() == mesh.positions.size();
  const size_t count = mesh.positions.size();
  std::vector<float> data(count * kFloatsPerVertex, 0.0f);
  for (size_t v = 0; v < count; ++v) {
    float* out = &data[v * kFloatsPerVertex];
    const vec3 p = mesh.positions[v];
    gpu.bounds.extend(p);
    out[0] = p.x, out[1] = p.y, out[2] = p.z;
    if (gpu.has_normals)
      out[3] = mesh.normals[v].x, out[4] = mesh.normals[v].y, out[5] = mesh.normals[v].z;
    if (mesh.uvs.size() == count) out[6] = mesh.uvs[v].x, out[7] = mesh.uvs[v].y;
    if (gpu.has_lightmap) out[8] = mesh.lightmap_uvs[v].x, out[9] = mesh.lightmap_uvs[v].y;
    if (mesh.tangents.size() == count) {
      out[10] = mesh.tangents[v].x, out[11] = mesh.tangents[v].y;
      out[12] = mesh.tangents[v].z, out[13] = mesh.tangents[v].w;
    }
    if (gpu.has_vertex_radiance) {
      out[14] = (*radiance)[v].x, out[15] = (*radiance)[v].y, out[16] = (*radiance)[v].z;
    }
  }
  gpu.vertex_array = gl::make_vertex_array();
  gpu.vertices = gl::make_buffer();
  gpu.indices = gl::make_buffer();
  glBindVertexArray(gpu.vertex_array.get());
  glBindBuffer(GL_ARRAY_BUFFER, gpu.vertices.get());
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(data.size() * sizeof(float)), data.data(),
               GL_STATIC_DRAW);
  const int sizes[] = {3, 3, 2, 2, 4, 3};
  size_t offset = 0;
  for (GLuint attribute = 0; attribute < 6; ++attribute) {
    glEnableVertexAttribArray(attribute);
    glVertexAttribPointer(attribute, sizes[attribute], GL_FLOAT, GL_FALSE,
                          kFloatsPerVertex * sizeof(float),
                          reinterpret_cast<const void*>(offset * sizeof(float)));
    offset += size_t(sizes[attribute]);
  }
  const size_t full = mesh.triangles.size();
  std::vector<uvec3> triangles(full);
  for (size_t k = 0; k < full; ++k) triangles[k] = mesh.triangles[chunks.order[k]];
  triangles.insert(triangles.end(), detail.triangles.begin(), detail.triangles.end());
  gpu.chunks = chunks.chunks;
  gpu.chunk_levels = detail.chunk_levels;
  for (std::vector<DetailLevel>& levels : gpu.chunk_levels) {
    for (DetailLevel& level : levels) level.first_triangle += uint32_t(full);
  }
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, gpu.indices.get());
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(triangles.size() * sizeof(uvec3)),
               triangles.data(), GL_STATIC_DRAW);
  gpu.index_count = GLsizei(full * 3);
  detect_plane(mesh, gpu);
  glBindVertexArray(0);
  if (patches && patches->size() == mesh.triangles.size() && !patches->empty()) {
    gpu.has_patches = true;
    std::vector<uint32_t> ordered(full + detail.source.size());
    for (size_t k = 0; k < full; ++k) ordered[k] = (*patches)[chunks.order[k]];
    for (size_t k = 0; k < detail.source.size(); ++k)
      ordered[full + k] = (*patches)[detail.source[k]];
    gpu.triangle_patch =
        gl::make_buffer_texture(GL_R32UI, ordered.data(), ordered.size() * sizeof(uint32_t));
  }
  return gpu;
}

gl::Texture upload_texture(const Texture& texture) {
  gl::Texture result = gl::make_texture();
  glBindTexture(GL_TEXTURE_2D, result.get());
  static const GLenum formats[] = {GL_RED, GL_RG, GL_RGB, GL_RGBA};
  static const GLenum internal[] = {GL_R32F, GL_RG32F, GL_RGB32F, GL_RGBA32F};
  const int c = std::clamp(texture.channels, 1, 4) - 1;
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  // Rows go up top row first, so v = 0 is the image's top row: the same addressing as
  // lb::sample_texture (bake/surface.h) and glTF.
  glTexImage2D(GL_TEXTURE_2D, 0, GLint(internal[c]), texture.width, texture.height, 0, formats[c],
               GL_FLOAT, texture.texels.data());
  if (c == 0) {
    const GLint swizzle[] = {GL_RED, GL_RED, GL_RED, GL_ONE};
    glTexParameteriv(GL_TEXTURE_2D, GL_TEXTURE_SWIZZLE_RGBA, swizzle);
  }
  glGenerateMipmap(GL_TEXTURE_2D);
  // The texture's sampler, as lb::sample_texture reads it (mipmaps besides, against aliasing).
  const bool nearest = texture.filter == TextureFilter::nearest;
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER,
                  nearest ? GL_NEAREST_MIPMAP_LINEAR : GL_LINEAR_MIPMAP_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, nearest ? GL_NEAREST : GL_LINEAR);
  auto wrap = [](TextureWrap mode) {
    return GLint(mode == TextureWrap::clamp    ? GL_CLAMP_TO_EDGE
                 : mode == TextureWrap::mirror ? GL_MIRRORED_REPEAT
                                               : GL_REPEAT);
  };
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, wrap(texture.wrap_u));
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, wrap(texture.wrap_v));
  glBindTexture(GL_TEXTURE_2D, 0);
  return result;
}

// An atlas-sized map (the illumination atlas, the soft-light texels): texel (i, j) covers
// [i, i+1] x [j, j+1] / size in lightmap uv, row j = 0 at v = 0; bilinear, clamped at the
// atlas border.
// RGB, or RGBA when `alpha` is given (the L1 x map's alpha: the decode's s, sh_projection.h).
gl::Texture upload_lightmap(const IlluminationMaps& maps, const std::vector<vec3>& radiance,
                            const std::vector<float>* alpha = nullptr) {
  gl::Texture result = gl::make_texture();
  glBindTexture(GL_TEXTURE_2D, result.get());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  if (alpha) {
    std::vector<glm::vec4> rgba(radiance.size());
    for (size_t k = 0; k < rgba.size(); ++k)
      rgba[k] = glm::vec4(radiance[k], k < alpha->size() ? (*alpha)[k] : 0.0f);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, maps.width, maps.height, 0, GL_RGBA, GL_FLOAT,
                 rgba.data());
  } else {
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB32F, maps.width, maps.height, 0, GL_RGB, GL_FLOAT,
                 radiance.data());
  }
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glBindTexture(GL_TEXTURE_2D, 0);
  return result;
}

// The outline (CCW from the front) of two triangles that share an edge, if they do.
bool quad_outline(const Mesh& mesh, uint32_t t0, uint32_t t1, vec3 out[4]) {
  const uvec3 a = mesh.triangles[t0], b = mesh.triangles[t1];
  for (int r = 0; r < 3; ++r) {
    // a rotated to (x, y, z); b must hold z, y in that (reversed) order plus one more vertex.
    const uint32_t x = a[r], y = a[(r + 1) % 3], z = a[(r + 2) % 3];
    for (int s = 0; s < 3; ++s) {
      if (b[s] == z && b[(s + 1) % 3] == y) {
        const uint32_t d = b[(s + 2) % 3];
        out[0] = mesh.positions[x];
        out[1] = mesh.positions[y];
        out[2] = mesh.positions[d];
        out[3] = mesh.positions[z];
        return true;
      }
    }
  }
  return false;
}

// A native bake's caustic and soft-light maps with their seams stitched as the export stitches
// its map (bake/lightmap/seam_stitch.h; the stitch is linear, so stitching each term is
// stitching their sum), so the window shows the seams an engine will. A map read back from an
// export (no soft-light texels of its own) is drawn as the file holds it.
struct StitchedMaps {
  std::vector<vec3> caustic, soft;
  std::array<std::vector<vec3>, 3> soft_l1;  // the soft map's band, where the bake has one
};

StitchedMaps stitched_maps(const Scene& scene, const IlluminationMaps& maps,
                           const SoftTexelMap& soft) {
  const std::vector<SeamSample> seams = atlas_seams(scene, maps);
  StitchedMaps out{maps.radiance, soft.radiance, {}};
  const float weight = LightmapParams{}.seam_weight;
  stitch_seams(seams, out.caustic, weight);
  stitch_seams(seams, out.soft, weight);
  for (size_t a = 0; a < 3; ++a)
    if (soft.l1[a].size() == soft.radiance.size()) {
      out.soft_l1[a] = soft.l1[a];
      stitch_seams(seams, out.soft_l1[a], weight);
    }
  return out;
}

GpuLights upload_lights(const Scene& scene) {
  GpuLights gpu;
  gpu.lights = collect_lights(scene);
  std::vector<vec3> corners, outlines;
  for (const AreaLight& light : gpu.lights) {
    const Mesh& mesh = scene.meshes[size_t(light.mesh)];
    vec3 quad[4];
    const bool planar_pair = light.triangles.size() == 2 &&
                             glm::dot(triangle_normal(mesh, light.triangles[0]),
                                      triangle_normal(mesh, light.triangles[1])) > 0.99999f;
    if (planar_pair && quad_outline(mesh, light.triangles[0], light.triangles[1], quad)) {
      gpu.outline_start.push_back(int(outlines.size() / 4));
      outlines.insert(outlines.end(), quad, quad + 4);
    } else {
      gpu.outline_start.push_back(-1);
    }
    gpu.triangle_start.push_back(int(corners.size() / 3));
    gpu.triangle_count.push_back(int(light.triangles.size()));
    for (uint32_t t : light.triangles) {
      const uvec3 tri = mesh.triangles[t];
      for (int k = 0; k < 3; ++k) corners.push_back(mesh.positions[tri[k]]);
    }
  }
  gpu.triangles = gl::make_buffer_texture(GL_RGB32F, corners.data(), corners.size() * sizeof(vec3));
  gpu.outlines =
      gl::make_buffer_texture(GL_RGB32F, outlines.data(), outlines.size() * sizeof(vec3));
  return gpu;
}

}  // namespace

void GpuScene::add_dynamic_meshes(const Scene& scene, const BakeResult* bake) {
  if (scene.dynamic_meshes.empty()) return;
  bool from_file = true;
  for (const Mesh& mesh : scene.dynamic_meshes)
    from_file = from_file && mesh.probe_sh.size() == size_t(kShCoefficients);
  // From an export with its grid: blends of the file's grid at each vertex; from a bake: the
  // probes it reads baked anew at each vertex (bake/probes/dynamic_light.h). The centre's
  // blend goes along for the detail a bump turns the shading normal by. From an export
  // without a grid: the node's centre blend alone.
  const DynamicLight light = !scene.probe_grid.empty() ? light_dynamic_meshes_from_grid(scene)
                             : bake && !from_file       ? light_dynamic_meshes(scene, *bake)
                                                        : DynamicLight{};
  for (size_t d = 0; d < scene.dynamic_meshes.size(); ++d) {
    const Mesh& mesh = scene.dynamic_meshes[d];
    const MeshChunks chunks = make_mesh_chunks(mesh);
    const std::vector<MeshDetail> detail = make_scene_detail({mesh}, {chunks});
    const bool per_vertex = d < light.blends.size();
    meshes_.push_back(upload_mesh(mesh, chunks, detail[0],
                                  per_vertex ? &light.vertex_light[d] : nullptr, nullptr, false));
    if (per_vertex) {
      meshes_.back().probe_lit = true;
      meshes_.back().probe_sh = light.blends[d].sh;
    } else if (mesh.probe_sh.size() == size_t(kShCoefficients)) {  // an export without a grid
      meshes_.back().probe_lit = true;
      std::copy(mesh.probe_sh.begin(), mesh.probe_sh.end(), meshes_.back().probe_sh.begin());
    }
    geometry_bytes_ += mesh.positions.size() * kFloatsPerVertex * sizeof(float) +
                       (mesh.triangles.size() + detail[0].triangles.size()) * sizeof(uvec3);
    scene_.meshes.push_back(mesh);  // meshes_[m] draws scene_.meshes[m]
    if (!meshes_.back().bounds.empty()) {
      bounds_.extend(meshes_.back().bounds.min);
      bounds_.extend(meshes_.back().bounds.max);
    }
  }
  scene_.dynamic_meshes.clear();
}

GpuScene::GpuScene(const Scene& scene, const BakeResult* bake) {
  const IlluminationMaps* maps = bake ? &bake->illumination : nullptr;
  std::vector<std::vector<vec3>> vertex_radiance(scene.meshes.size());
  if (bake) {
    BakedScene baked = make_baked_scene(scene, *bake);
    scene_ = std::move(baked.scene);
    vertex_radiance = std::move(baked.vertex_radiance);
    baked_ = true;
  } else {
    scene_ = scene;
  }
  const bool atlas = maps && maps->width > 0 && maps->height > 0 &&
                     maps->radiance.size() == size_t(maps->width) * size_t(maps->height);
  if (atlas && bake->soft_texels.radiance.size() == maps->radiance.size()) {
    const StitchedMaps stitched = stitched_maps(scene, *maps, bake->soft_texels);
    lightmap_ = upload_lightmap(*maps, stitched.caustic);
    soft_light_ = upload_lightmap(*maps, stitched.soft);
    if (stitched.soft_l1[0].size() == maps->radiance.size() &&
        stitched.soft_l1[1].size() == maps->radiance.size() &&
        stitched.soft_l1[2].size() == maps->radiance.size())
      for (size_t a = 0; a < 3; ++a)
        soft_light_l1_[a] = upload_lightmap(*maps, stitched.soft_l1[a]);
  } else if (atlas) {
    lightmap_ = upload_lightmap(*maps, maps->radiance);
  }
  lightmap_holds_direct_ = atlas && maps->holds_direct_light;
  for (size_t a = 0; a < 3; ++a)
    if (atlas && maps->l1[a].size() == maps->radiance.size())
      lightmap_l1_[a] = upload_lightmap(*maps, maps->l1[a], a == 0 ? &maps->l1_share : nullptr);
  // Chunks and levels of detail on every core first (no GL there), then the uploads.
  std::vector<MeshChunks> chunks(scene_.meshes.size());
  tbb::parallel_for(size_t(0), scene_.meshes.size(),
                    [&](size_t m) { chunks[m] = make_mesh_chunks(scene_.meshes[m]); });
  std::vector<MeshDetail> detail = make_scene_detail(scene_.meshes, chunks);
  for (size_t m = 0; m < scene_.meshes.size(); ++m) {
    const std::vector<uint32_t>* patches = nullptr;
    if (bake && m < bake->radiosity.meshes.size())
      patches = &bake->radiosity.meshes[m].triangle_patch;
    const bool diffuse = scene_.materials[size_t(scene_.meshes[m].material)].is_diffuse();
    meshes_.push_back(upload_mesh(scene_.meshes[m], chunks[m], detail[m], &vertex_radiance[m],
                                  patches, atlas && diffuse));
    const size_t triangles = scene_.meshes[m].triangles.size() + detail[m].triangles.size();
    geometry_bytes_ += scene_.meshes[m].positions.size() * kFloatsPerVertex * sizeof(float) +
                       triangles * sizeof(uvec3) + (meshes_.back().has_patches ? triangles * 4 : 0);
    detail_triangles_ += detail[m].triangles.size();
    chunks[m] = MeshChunks();
    detail[m] = MeshDetail();
    if (!meshes_.back().bounds.empty()) {
      bounds_.extend(meshes_.back().bounds.min);
      bounds_.extend(meshes_.back().bounds.max);
    }
  }
  for (const Texture& texture : scene_.textures) textures_.push_back(upload_texture(texture));
  lights_ = upload_lights(scene_);  // the static scene's: moving objects light nothing
  add_dynamic_meshes(scene, bake);
  gl::check_errors("uploading the scene");
}

void DrawCounts::add(const DrawCounts& other) {
  chunks_drawn += other.chunks_drawn;
  chunks_total += other.chunks_total;
  triangles_drawn += other.triangles_drawn;
  triangles_total += other.triangles_total;
  draw_calls += other.draw_calls;
  chunks_simplified += other.chunks_simplified;
}

bool GpuScene::culled(size_t m, const Frustum& frustum, DrawCounts& counts) const {
  const GpuMesh& mesh = meshes_[m];
  if (!culling_ || frustum.may_see(mesh.bounds)) return false;
  count_skipped(m, counts);
  return true;
}

void GpuScene::count_skipped(size_t m, DrawCounts& counts) const {
  counts.chunks_total += int(meshes_[m].chunks.size());
  counts.triangles_total += size_t(meshes_[m].index_count / 3);
}

void GpuScene::draw_mesh(size_t m, const Frustum& frustum, DrawCounts& counts,
                         const DetailView& detail, GLint first_triangle_uniform,
                         const std::vector<glm::ivec2>* light_ranges,
                         GLint light_range_uniform, GLint detail_lift_uniform) const {
  const GpuMesh& mesh = meshes_[m];
  const std::vector<MeshChunk>& chunks = mesh.chunks;
  counts.chunks_total += int(chunks.size());
  counts.triangles_total += size_t(mesh.index_count / 3);
  // Whole-mesh test first: most meshes of a big level are one chunk or wholly outside.
  if (culling_ && !frustum.may_see(mesh.bounds)) return;
  const bool test_chunks = culling_ && chunks.size() > 1;
  bool bound = false;
  // Runs of visible chunks whose triangles (at the level each is drawn) are contiguous in the
  // index buffer and share one light list go in one call.
  uint32_t run_first = 0, run_count = 0;
  size_t run_chunk = 0;
  float run_lift = 0.0f;
  auto flush = [&] {
    if (run_count == 0) return;
    if (!bound) glBindVertexArray(mesh.vertex_array.get());
    bound = true;
    if (first_triangle_uniform >= 0) glUniform1i(first_triangle_uniform, GLint(run_first));
    if (light_ranges && light_range_uniform >= 0) {
      const glm::ivec2 range = (*light_ranges)[run_chunk];
      glUniform2i(light_range_uniform, range.x, range.y);
    }
    if (detail_lift_uniform >= 0) glUniform1f(detail_lift_uniform, run_lift);
    glDrawElements(GL_TRIANGLES, GLsizei(run_count * 3), GL_UNSIGNED_INT,
                   reinterpret_cast<const void*>(size_t(run_first) * sizeof(uvec3)));
    counts.triangles_drawn += run_count;
    ++counts.draw_calls;
    run_count = 0;
  };
  for (size_t c = 0; c < chunks.size(); ++c) {
    if (test_chunks && !frustum.may_see(chunks[c].bounds)) continue;
    uint32_t first = chunks[c].first_triangle, count = chunks[c].triangle_count;
    float lift = 0.0f;
    const int level = c < mesh.chunk_levels.size()
                          ? pick_detail_level(mesh.chunk_levels[c], chunks[c].bounds, detail)
                          : -1;
    if (level >= 0) {
      first = mesh.chunk_levels[c][size_t(level)].first_triangle;
      count = mesh.chunk_levels[c][size_t(level)].triangle_count;
      lift = mesh.chunk_levels[c][size_t(level)].error;
      ++counts.chunks_simplified;
    }
    ++counts.chunks_drawn;
    const bool joins = run_count > 0 && run_first + run_count == first && lift == run_lift &&
                       (!light_ranges || (*light_ranges)[c] == (*light_ranges)[run_chunk]);
    if (!joins) {
      flush();
      run_first = first;
      run_chunk = c;
      run_lift = lift;
    }
    run_count += count;
  }
  flush();
}

GLuint GpuScene::texture(int index) const {
  if (index < 0 || size_t(index) >= textures_.size()) return 0;
  return textures_[size_t(index)].get();
}

}  // namespace lb
