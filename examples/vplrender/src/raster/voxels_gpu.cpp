#include "raster/voxels_gpu.hpp"

#include "raster/voxels.hpp"

#include <vplkit/visibility/voxelize.hpp>
#include <vplkit/visibility/voxelize_params.h>

#include <glm/vec4.hpp>

#include <chrono>

namespace vplrender {

gpu_voxelization voxelize_gpu(const scene& s, int resolution) {
  const voxel_mesh m = make_voxel_mesh(s);
  const vplkit::voxel_bounds<float> b = vplkit::fit_voxel_bounds(m.positions.data(), m.positions.size());
  const glm::ivec3 res(resolution);
  const std::size_t words = vplkit::voxel_word_count(res);
  const vplkit::gl::program& prog = vplkit::gl::cached_kernel("vplkit/visibility/voxelize.comp");
  std::vector<glm::vec4> pos;
  pos.reserve(m.positions.size());
  for (const vec3& p : m.positions) pos.emplace_back(p, 1.0f);
  auto positions = vplkit::gl::buffer::from_vector(pos);
  auto indices = vplkit::gl::buffer::from_vector(m.indices);
  auto grid = vplkit::gl::buffer::filled(words * sizeof(std::uint32_t), 0);
  vplkit::gpu::voxelize_params pr{};
  pr.bounds_min = glm::vec4(b.min, 0.0f);
  pr.bounds_max = glm::vec4(b.max, 0.0f);
  pr.resolution = glm::ivec4(res, 0);
  const std::uint32_t tris = static_cast<std::uint32_t>(m.indices.size() / 3);
  pr.triangle_count = tris;
  pr.margin_voxels = static_cast<float>(vplkit::voxelize_default_margin);
  const vplkit::gl::buffer params = vplkit::gl::buffer::from_bytes(&pr, sizeof pr);
  glBindBufferBase(GL_UNIFORM_BUFFER, VPLKIT_VOXELIZE_BINDING_PARAMS, params.id());
  positions.bind(VPLKIT_VOXELIZE_BINDING_POSITIONS);
  indices.bind(VPLKIT_VOXELIZE_BINDING_INDICES);
  grid.bind(VPLKIT_VOXELIZE_BINDING_WORDS);
  vplkit::gl::timer_query tq;
  tq.begin();
  // One work group per triangle (voxelize.comp's dispatch rule), spread over y past the x limit.
  vplkit::gl::dispatch_linear(prog, tris);
  tq.end();
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::uint32_t> w = grid.read<std::uint32_t>(words);
  const double readback_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  gpu_voxelization out{vplkit::voxel_grid<float>(b.min, b.max, res, std::move(w)), std::move(grid), tq.milliseconds(),
                       readback_ms};
  return out;
}

}  // namespace vplrender
