// SPDX-License-Identifier: MIT
#include "raster/gpu_scene_buffers.hpp"

#include <glm/vec4.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>

namespace vplrender {

vplkit::gl::buffer upload_surfels(const std::vector<vec3>& position, const std::vector<vec3>& normal,
                                  const std::vector<vec3>& albedo, const std::vector<vec3>* shading_normal) {
  std::vector<glm::vec4> s(3 * std::max<std::size_t>(position.size(), 1), glm::vec4(0.0f));
  const bool shading = shading_normal != nullptr && shading_normal->size() == position.size();
  for (std::size_t i = 0; i < position.size(); ++i) {
    const vec3 ns = shading ? (*shading_normal)[i] : vec3(0.0f);
    s[3 * i] = glm::vec4(position[i], ns.x);
    s[3 * i + 1] = glm::vec4(normal[i], ns.y);
    s[3 * i + 2] = glm::vec4(albedo[i], ns.z);
  }
  return vplkit::gl::buffer::from_vector(s);
}

vplkit::gl::buffer upload_voxel_words(const vplkit::voxel_grid_view<float>& grid) {
  std::vector<std::uint32_t> words(grid.words, grid.words + vplkit::voxel_word_count(grid.resolution));
  if (words.empty()) words.push_back(0u);
  return vplkit::gl::buffer::from_vector(words);
}

long long march_triangle_tests(const scene_voxels_view& v) {
  const vplkit::ivec3 r = v.grid.resolution;
  const std::size_t k = std::min<std::size_t>(v.occupied, std::size_t(r.x) + std::size_t(r.y) + std::size_t(r.z));
  std::vector<std::uint32_t> lengths(v.occupied);
  for (std::size_t i = 0; i < v.occupied; ++i) lengths[i] = v.offsets[i + 1] - v.offsets[i];
  std::partial_sort(lengths.begin(), lengths.begin() + std::ptrdiff_t(k), lengths.end(), std::greater<std::uint32_t>());
  long long sum = 0;
  for (std::size_t i = 0; i < k; ++i) sum += lengths[i];
  return sum;
}

namespace {

// A voxel_triangle<float> is four vec4 in the GLSL layout, a voxel_plane<float> one.
static_assert(sizeof(vplkit::voxel_triangle<float>) == 4 * sizeof(glm::vec4), "four vec4 per triangle");
static_assert(sizeof(vplkit::voxel_plane<float>) == sizeof(glm::vec4), "one vec4 per voxel plane");

std::size_t at_least_one(std::size_t n) { return n > 0 ? n : 1; }

vplkit::gl::buffer upload_uints(const std::uint32_t* p, std::size_t n) {
  std::vector<std::uint32_t> a(p, p + n);
  if (a.empty()) a.push_back(0u);  // a buffer is never empty
  return vplkit::gl::buffer::from_vector(a);
}

}  // namespace

std::size_t triangle_voxels_bytes(const scene_voxels_view& v) {
  const std::size_t words = vplkit::voxel_word_count(v.grid.resolution);
  return 4 * (at_least_one(words) + at_least_one(v.occupied + 1) + at_least_one(v.entry_count()) +
              at_least_one(vplkit::voxel_brick_word_count(v.grid.resolution))) +
         sizeof(vplkit::voxel_triangle<float>) * at_least_one(v.triangle_count) +
         sizeof(vplkit::voxel_plane<float>) * (v.occupied + 1);
}

gpu_triangle_voxels upload_triangle_voxels(const scene_voxels_view& v) {
  gpu_triangle_voxels g;
  g.rank = upload_uints(v.rank, vplkit::voxel_word_count(v.grid.resolution));
  g.offsets = upload_uints(v.offsets, v.occupied + 1);
  g.entries = upload_uints(v.entries, v.entry_count());
  // The triangles, then the planes: occupied + 1 vec4, as many as offsets has entries (see
  // gpu_triangle_voxels). Without the view's planes every voxel is "several": the near-surface
  // test then scans as before.
  const std::size_t plane_base = 4 * at_least_one(v.triangle_count);
  const vplkit::voxel_plane<float> several = vplkit::voxel_planes_several<float>();
  std::vector<glm::vec4> tris(plane_base + v.occupied + 1, glm::vec4(several.normal, several.offset));
  std::fill(tris.begin(), tris.begin() + static_cast<std::ptrdiff_t>(plane_base), glm::vec4(0.0f));
  if (v.triangle_count > 0)
    std::memcpy(tris.data(), v.triangles, v.triangle_count * sizeof(vplkit::voxel_triangle<float>));
  if (v.planes != nullptr && v.occupied > 0)
    std::memcpy(tris.data() + plane_base, v.planes, v.occupied * sizeof(vplkit::voxel_plane<float>));
  g.triangles = vplkit::gl::buffer::from_vector(tris);
  if (v.bricks != nullptr) {
    g.bricks = upload_uints(v.bricks, vplkit::voxel_brick_word_count(v.grid.resolution));
  } else {  // a view without its brick level: every brick occupied, so the marches step as before
    const std::vector<std::uint32_t> all(vplkit::voxel_brick_word_count(v.grid.resolution), ~0u);
    g.bricks = upload_uints(all.data(), all.size());
  }
  g.march_tests = march_triangle_tests(v);
  return g;
}

namespace {

// Three vec4 per surfel back into arrays (a G-buffer pixel's w: its shading normal).
void read_surfels(const vplkit::gl::buffer& b, std::size_t count, std::vector<vec3>& position, std::vector<vec3>& normal,
                  std::vector<vec3>& albedo, std::vector<vec3>* shading_normal) {
  const std::vector<glm::vec4> s = b.read<glm::vec4>(3 * count);
  position.resize(count);
  normal.resize(count);
  albedo.resize(count);
  if (shading_normal) shading_normal->resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    position[i] = vec3(s[3 * i]);
    normal[i] = vec3(s[3 * i + 1]);
    albedo[i] = vec3(s[3 * i + 2]);
    if (shading_normal) (*shading_normal)[i] = vec3(s[3 * i].w, s[3 * i + 1].w, s[3 * i + 2].w);
  }
}

}  // namespace

gbuffer_data read_back_gbuffer(const gpu_scene_buffers& b, int width, int height) {
  gbuffer_data g;
  g.width = width;
  g.height = height;
  read_surfels(b.gbuffer, static_cast<std::size_t>(width) * static_cast<std::size_t>(height), g.position, g.normal,
               g.albedo, &g.shading_normal);
  return g;
}

dprsm_data read_back_dprsm(const gpu_scene_buffers& b, int resolution, const vplkit::point_light<float>& light) {
  dprsm_data d;
  d.resolution = resolution;
  d.light = light;
  read_surfels(b.dprsm, 2 * static_cast<std::size_t>(resolution) * static_cast<std::size_t>(resolution), d.position,
               d.normal, d.albedo, nullptr);
  return d;
}

gpu_scene_buffers upload_scene_buffers(const gbuffer_data& g, const dprsm_data& d, const scene_voxels_view& grid) {
  gpu_scene_buffers b;
  b.gbuffer = upload_surfels(g.position, g.normal, g.albedo, &g.shading_normal);
  b.dprsm = upload_surfels(d.position, d.normal, d.albedo);
  b.voxels = upload_voxel_words(grid.grid);
  b.voxel_triangles = upload_triangle_voxels(grid);
  return b;
}

}  // namespace vplrender
