// SPDX-License-Identifier: MIT
#pragma once
// The DPRSM's plane records on the GPU (glsl/vplkit/vpl/dprsm_planes.comp; the C++ side is
// vplkit::build_dprsm_planes): one vec4 per texel, (unit normal, signed height over the light),
// that the estimate kernels' patch-sampled VPLs read through VPLKIT_DPRSM_PLANE_ACCESSOR
// (estimate_io.glsl): one 16-byte load per neighbour of the hidden test instead of three and a
// normalisation. Built by the frame pipeline once the DPRSM is written (stage "dprsm planes (gpu)"),
// so every estimator run of the frame reads the same records.
#include "raster/gpu_scene_buffers.hpp"

#include <headless_gl/compute.hpp>

#include <vplkit/vpl/dprsm_view.hpp>

namespace vplrender {

// Builds scene.dprsm_planes from scene.dprsm (2 R^2 surfels) for `light` (needs the current GL
// context; one dispatch, no read-back).
void build_dprsm_planes_gpu(gpu_scene_buffers& scene, int resolution, const vplkit::point_light<float>& light);

// The records of scene's DPRSM for (resolution, light): scene.dprsm_planes when they were built
// for them, else built into `scratch` (a frame made from arrays by hand), which is returned.
const vplkit::gl::buffer& dprsm_planes_for(const gpu_scene_buffers& scene, int resolution,
                                           const vplkit::point_light<float>& light, vplkit::gl::buffer& scratch);

}  // namespace vplrender
