// SPDX-License-Identifier: MIT
#include "render/gpu/gpu_dprsm_planes.hpp"

#include "render/gpu/gpu_allocating.hpp"

#include <vplkit/paraboloid/texel_grid.hpp>
#include <vplkit/vpl/dprsm_planes_params.h>

#include <cstddef>

namespace vplrender {

namespace {

namespace gl = vplkit::gl;

void build_into(const gl::buffer& dprsm, gl::buffer& out, int resolution, const vplkit::point_light<float>& light) {
  const std::size_t texels = static_cast<std::size_t>(vplkit::texel_count(resolution));
  const std::size_t bytes = sizeof(vplkit::dprsm_plane<float>) * (texels > 0 ? texels : 1);
  if (out.size_bytes() != bytes)
    out = gpu_allocating(bytes, "the DPRSM plane records", [&] { return gl::buffer::filled(bytes, 0); });
  vplkit::gpu::dprsm_planes_params p{};
  p.light = vplkit::gpu::make_light_params(light);
  p.resolution = resolution;
  const gl::buffer params = gl::buffer::from_bytes(&p, sizeof p);
  dprsm.bind(VPLKIT_DPRSM_PLANES_BINDING_DPRSM);
  out.bind(VPLKIT_DPRSM_PLANES_BINDING_PLANES);
  glBindBufferBase(GL_UNIFORM_BUFFER, VPLKIT_DPRSM_PLANES_BINDING_PARAMS, params.id());
  // dispatch_linear ends with the storage barrier the estimate kernels' reads need.
  gl::dispatch_linear(gl::cached_kernel("vplkit/vpl/dprsm_planes.comp"),
                      gl::groups_for(texels, VPLKIT_DPRSM_PLANES_LOCAL_SIZE));
}

}  // namespace

void build_dprsm_planes_gpu(gpu_scene_buffers& scene, int resolution, const vplkit::point_light<float>& light) {
  scene.dprsm_planes.resolution = 0;
  build_into(scene.dprsm, scene.dprsm_planes.records, resolution, light);
  scene.dprsm_planes.resolution = resolution;
  scene.dprsm_planes.light_position = light.position;
}

const gl::buffer& dprsm_planes_for(const gpu_scene_buffers& scene, int resolution,
                                   const vplkit::point_light<float>& light, gl::buffer& scratch) {
  const gpu_dprsm_planes& p = scene.dprsm_planes;
  if (p.resolution == resolution && p.resolution > 0 && p.light_position == light.position) return p.records;
  build_into(scene.dprsm, scratch, resolution, light);
  return scratch;
}

}  // namespace vplrender
