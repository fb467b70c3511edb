// SPDX-License-Identifier: MIT
#pragma once
// The DPRSM view as the renderer's small kernels take it in loose uniforms
// (shaders/vpl_fallback_weights.comp, shaders/frame_facts.comp): u_dprsm_res, u_light_pos,
// u_light_int, u_frame_pos, u_axis_x, u_axis_y, u_axis_z, which they pass to vplkit_dprsm_view.
#include <headless_gl/compute.hpp>

#include <vplkit/vpl/dprsm_view.hpp>

namespace vplrender {

// Sets them on `p` (made current here).
inline void set_dprsm_view_uniforms(const vplkit::gl::program& p, int resolution, const vplkit::point_light<float>& L) {
  p.use();
  glUniform1i(p.uniform_location("u_dprsm_res"), resolution);
  glUniform3f(p.uniform_location("u_light_pos"), L.position.x, L.position.y, L.position.z);
  glUniform3f(p.uniform_location("u_light_int"), L.intensity.x, L.intensity.y, L.intensity.z);
  glUniform3f(p.uniform_location("u_frame_pos"), L.frame.position.x, L.frame.position.y, L.frame.position.z);
  glUniform3f(p.uniform_location("u_axis_x"), L.frame.axis_x.x, L.frame.axis_x.y, L.frame.axis_x.z);
  glUniform3f(p.uniform_location("u_axis_y"), L.frame.axis_y.x, L.frame.axis_y.y, L.frame.axis_y.z);
  glUniform3f(p.uniform_location("u_axis_z"), L.frame.axis_z.x, L.frame.axis_z.y, L.frame.axis_z.z);
}

}  // namespace vplrender
