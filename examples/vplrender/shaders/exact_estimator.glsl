// SPDX-License-Identifier: MIT
// vplrender: --method exact on the GPU, render/cpu/exact_estimator.cpp line for line (its header
// is the contract: one-bounce diffuse indirect light by cosine gathering around the gather point's
// geometric normal, each first hit y lit by the point light's direct light through an exact shadow
// ray, no VPLs), with the pack's BVH for Embree and ray_scene.glsl for ray_scene's shading. The
// offset that moves ray origins off their surfaces is the host's ray_scene value (a uniform), so
// both backends move the same points by the same amounts.
//
// ACCESSORS: those of vplkit/visibility/bvh_layout.glsl and of ray_scene.glsl.
#ifndef VPLRENDER_EXACT_ESTIMATOR_GLSL
#define VPLRENDER_EXACT_ESTIMATOR_GLSL

#include "ray_scene.glsl"
#include "vplkit/core/gather_point.glsl"
#include "vplkit/core/unit_or_zero.glsl"
#include "vplkit/estimators/estimator_state.glsl"
#include "vplkit/estimators/vpl_sum.glsl"
#include "vplkit/sampling/cosine_hemisphere.glsl"
#include "vplkit/sampling/orthonormal_basis.glsl"
#include "vplkit/sampling/rng.glsl"
#include "vplkit/visibility/bvh_traverse.glsl"
#include "vplkit/visibility/bvh_visibility.glsl"
#include "vplkit/vpl/dprsm_view.glsl"
#include "vplkit/vpl/vpl.glsl"

// The ray_scene values the estimator needs: the BVH and surface_offset().
struct vr_exact_scene {
  vplkit_bvh bvh;
  float offset;
};

// exact_sample: one direction's value rho_x L_o(y) cos_s / cos_g, 0 at or below either horizon.
vec3 vr_exact_sample(vr_exact_scene rs, vplkit_point_light light, vplkit_gather_point gp, vec3 n_g, vec3 dir) {
  float cos_g = dot(n_g, dir);
  float cos_s = dot(vplkit_unit_or_zero(vplkit_gather_point_shading_normal(gp)), dir);
  if (!(cos_g > 0.0) || !(cos_s > 0.0)) return vec3(0.0);
  float offset = rs.offset;
  vplkit_bvh_hit h = vplkit_bvh_closest_hit(rs.bvh, vplkit_bvh_offset_point(gp.position, n_g, offset), dir);
  if (!h.hit) return vec3(0.0);
  // A hit on x's own plane (x on a crease): the lifted origin crossed a surface x sees edge-on.
  if (vplkit_vpl_point_on_plane(gp.position, h.position, h.normal)) return vec3(0.0);
  // y's lit side is the one facing the light; seen from the other side it reflects nothing.
  vec3 y = h.position;
  vec3 n_gy = h.normal;
  if (dot(n_gy, light.position - y) < 0.0) n_gy = -n_gy;
  // x's side, not the lifted origin's; precise: a junction puts x within rounding of y's plane.
  precise vec3 to_x = gp.position - y;
  precise float side = dot(n_gy, to_x);
  if (!(side > 0.0)) return vec3(0.0);
  vec3 n_sy = vr_shading_normal(h);
  if (dot(n_sy, n_gy) < 0.0) n_sy = -n_sy;
  vec3 l_o = vplkit_reflected_radiance(light.position, light.intensity, y, n_sy, vr_albedo_at(h));
  if (!(l_o.x > 0.0 || l_o.y > 0.0 || l_o.z > 0.0)) return vec3(0.0);
  vec3 o = vplkit_bvh_offset_point(y, n_gy, offset);
  precise vec3 to_light = light.position - o;
  if (vplkit_bvh_occluded(rs.bvh, o, to_light, 0.0, 1.0)) return vec3(0.0);
  return vplkit_estimator_finite_or_zero(gp.albedo * l_o * (cos_s / cos_g));
}

// estimate_exact's loop over directions [begin, end) (the kernel splits n_dirs over passes; the
// draws and sums are those of the one loop whatever the split).
void vr_estimate_exact_range(vr_exact_scene rs, vplkit_point_light light, vplkit_gather_point gp,
                             inout vplkit_estimator_state state, int begin, int end) {
  if (!vplkit_gather_point_valid(gp)) return;
  vec3 n_g = vplkit_unit_or_zero(gp.normal);
  vplkit_orthonormal_basis frame = vplkit_make_orthonormal_basis(n_g);
  for (int k = begin; k < end; ++k) {
    float u0 = vplkit_rng_next_unit(state.rng);
    float u1 = vplkit_rng_next_unit(state.rng);
    vec3 local = vplkit_sample_cosine_hemisphere(vec2(u0, u1));
    state.sum += vr_exact_sample(rs, light, gp, n_g, vplkit_to_world(frame, local));
  }
}

vec3 vr_estimate_exact_finish(vplkit_estimator_state state, int n_dirs) {
  return n_dirs > 0 ? state.sum / float(n_dirs) : vec3(0.0);
}

#endif  // VPLRENDER_EXACT_ESTIMATOR_GLSL
