// SPDX-License-Identifier: MIT
#pragma once
// The frame's scene buffers on the GPU, in the one layout every kernel of the GPU backend reads
// (the pack's builder kernels, the fallback weights, the estimate kernels): made once per frame by the
// pipeline (render/pipeline.hpp) and bound by every GPU stage, so nothing is uploaded twice. A
// richer visibility structure adds its buffers here and to upload_scene_buffers.
#include "raster/gpu_bvh.hpp"
#include "raster/gpu_scene_shading.hpp"
#include "raster/render_data.hpp"
#include "raster/voxels.hpp"

#include <headless_gl/compute.hpp>

#include <vplkit/visibility/triangle_voxel_grid.hpp>

#include <vector>

namespace vplrender {

// The triangle voxel grid beside the occupancy words: the four arrays of
// glsl/vplkit/visibility/triangle_voxel_grid.glsl (rank, offsets, entries, triangles as four vec4
// each) and the brick level the marches skip empty space with (glsl/vplkit/visibility/
// voxel_bricks.glsl), each at least one element, and the loop bound of one march over them.
struct gpu_triangle_voxels {
  // triangles: the four vec4 of each triangle, then the grid's planes (vplkit/visibility/
  // triangle_voxel_grid.hpp: per occupied voxel the plane its triangles share, or the "several"
  // mark), occupied + 1 vec4 (the last one unused), so a kernel finds them at triangles.length() -
  // offsets.length() without a binding or a parameter of their own (shaders/estimate_visibility.glsl).
  vplkit::gl::buffer rank, offsets, entries, triangles, bricks;
  long long march_tests = 0;  // march_triangle_tests of the grid
  std::size_t size_bytes() const {
    return rank.size_bytes() + offsets.size_bytes() + entries.size_bytes() + triangles.size_bytes() +
           bricks.size_bytes();
  }
};

// The DPRSM's plane records (glsl/vplkit/vpl/dprsm_plane.glsl, one vec4 per texel) and what they
// were built for: render/gpu/gpu_dprsm_planes.hpp builds them once the DPRSM is written.
struct gpu_dprsm_planes {
  vplkit::gl::buffer records;
  int resolution = 0;           // R of the DPRSM they were built from; 0: not built
  vec3 light_position{0.0f};    // ... and its light
};

// The estimate kernels' per-pixel buffers (render/gpu/gpu_backend.cpp): the estimates, the state
// between split dispatches, the RIS reservoirs. Kept from one render to the next, so the frames
// of a --frames run allocate them once; a render whose image size differs reallocates them.
struct gpu_pixel_buffers {
  vplkit::gl::buffer out, state, reservoirs;
  // --method ris-mis --candidate-pool: the presampled candidates (not per pixel: pools x entries).
  vplkit::gl::buffer ris_pool;
  // The clamp compensation's pixel list (render/gpu: --clamp-compensation-pass compacted).
  vplkit::gl::buffer clamp_list;
  int allocations = 0;  // buffers made so far (a render that reuses all of them makes none)
  std::size_t size_bytes() const {
    return out.size_bytes() + state.size_bytes() + reservoirs.size_bytes() + ris_pool.size_bytes() +
           clamp_list.size_bytes();
  }
};

struct gpu_scene_buffers {
  vplkit::gl::buffer gbuffer;  // surfels of gbuffer_data, index y * W + x (row 0 = top)
  vplkit::gl::buffer dprsm;    // surfels of dprsm_data, index face * R^2 + y * R + x
  gpu_dprsm_planes dprsm_planes;  // the DPRSM's plane records for its light
  vplkit::gl::buffer voxels;   // the voxel grid's occupancy words (voxel_grid::words order)
  gpu_triangle_voxels voxel_triangles;  // --visibility voxels: the lists of the occupied voxels
  gpu_bvh bvh;                 // --visibility exact: the scene's BVH (empty unless prepared with exact rays)
  gpu_scene_shading shading;   // --method exact: the hits' normals and albedos (empty unless prepared with exact rays)
  // Scratch of the estimator runs on these buffers; mutable: a frame hands its buffers out const.
  mutable gpu_pixel_buffers pixels;
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

// The triangle tests one voxel march may make: it visits each voxel at most once and at most
// nx + ny + nz of them, so the sum of the nx + ny + nz longest lists bounds them.
long long march_triangle_tests(const scene_voxels_view& v);

// The four arrays of the triangle voxel grid (needs the current GL context).
gpu_triangle_voxels upload_triangle_voxels(const scene_voxels_view& v);
// Bytes upload_triangle_voxels asks for.
std::size_t triangle_voxels_bytes(const scene_voxels_view& v);

// A GPU frame's G-buffer (W H surfels) and DPRSM (2 R^2 surfels, `light` its light) read back into
// arrays: for a CPU-side consumer of a GPU frame (needs the current GL context).
gbuffer_data read_back_gbuffer(const gpu_scene_buffers& b, int width, int height);
dprsm_data read_back_dprsm(const gpu_scene_buffers& b, int resolution, const vplkit::point_light<float>& light);

// All of them from the CPU copies (needs the current GL context).
gpu_scene_buffers upload_scene_buffers(const gbuffer_data& g, const dprsm_data& d, const scene_voxels_view& grid);

}  // namespace vplrender
