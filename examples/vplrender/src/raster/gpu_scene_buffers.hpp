#pragma once
// The frame's scene buffers on the GPU, in the one layout every kernel of the GPU backend reads
// (the pack's builder kernels, the fallback weights, estimate.comp): made once per frame by the
// pipeline (render/pipeline.hpp) and bound by every GPU stage, so nothing is uploaded twice. A
// richer visibility structure adds its buffers here and to upload_scene_buffers.
#include "raster/gpu_bvh.hpp"
#include "raster/render_data.hpp"

#include <headless_gl/compute.hpp>

#include <vplkit/visibility/voxel_grid.hpp>

#include <vector>

namespace vplrender {

struct gpu_scene_buffers {
  vplkit::gl::buffer gbuffer;  // surfels of gbuffer_data, index y * W + x (row 0 = top)
  vplkit::gl::buffer dprsm;    // surfels of dprsm_data, index face * R^2 + y * R + x
  vplkit::gl::buffer voxels;   // the voxel grid's occupancy words (voxel_grid::words order)
  gpu_bvh bvh;                 // --visibility exact: the scene's BVH (empty unless prepared with exact rays)
};

// A G-buffer pixel or a DPRSM texel as the kernels read it: struct { vec4 position; vec4 normal;
// vec4 albedo; } in std430 (xyz used); a G-buffer pixel's shading normal in the three w
// (vplkit_unpack_gather_point), w = 0 without one. At least one entry, so an empty array still
// binds.
// Bytes upload_surfels() asks for: three vec4 per surfel (at least one surfel).
inline std::size_t surfel_bytes(std::size_t count) { return 3 * 16 * (count > 0 ? count : 1); }
vplkit::gl::buffer upload_surfels(const std::vector<vec3>& position, const std::vector<vec3>& normal,
                                  const std::vector<vec3>& albedo, const std::vector<vec3>* shading_normal = nullptr);

// The occupancy words (at least one).
vplkit::gl::buffer upload_voxel_words(const vplkit::voxel_grid_view<float>& grid);

// All of them from the CPU copies (needs the current GL context).
gpu_scene_buffers upload_scene_buffers(const gbuffer_data& g, const dprsm_data& d,
                                       const vplkit::voxel_grid_view<float>& grid);

}  // namespace vplrender
