#include "raster/gpu_scene_buffers.hpp"

#include <glm/vec4.hpp>

#include <algorithm>
#include <cstdint>

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

gpu_scene_buffers upload_scene_buffers(const gbuffer_data& g, const dprsm_data& d,
                                       const vplkit::voxel_grid_view<float>& grid) {
  gpu_scene_buffers b;
  b.gbuffer = upload_surfels(g.position, g.normal, g.albedo, &g.shading_normal);
  b.dprsm = upload_surfels(d.position, d.normal, d.albedo);
  b.voxels = upload_voxel_words(grid);
  return b;
}

}  // namespace vplrender
