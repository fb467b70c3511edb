// SPDX-License-Identifier: MIT
// vplkit GLSL pack: point-to-point visibility through the voxel grid (docs/math.md section 7, the
// paper's Alg. 6; mirrors include/vplkit/visibility/voxel_visible.hpp, T = float).
// L = vplkit_voxel_length (the largest voxel edge) is the unit of every offset and tolerance.
//
//   vplkit_voxel_visible (the paper's one-sided test):
//     o = vplkit_surface_ray_origin(x, n_x), dist = |y - o|; visible <=> no occupied voxel is
//     entered within [0, dist - psi], psi = tolerance_voxels * L (points closer than psi: visible).
//   vplkit_voxel_visible_two_sided: both ends lifted off their surfaces, o -> o_y. Prefer it
//     wherever y has a normal (every VPL does): see docs/api/visibility.md for the measurements.
// Defaults (C++ default arguments -> overloads without those parameters): offset 1.75 voxels,
// psi 2 voxels (one-sided) and 0 voxels (two-sided).
//
// ACCESSOR: uint vplkit_load_voxel_word(uint word_index) (see voxel_grid.glsl).
//
// Parity: the segment length is sqrt of the written-out, `precise` dot (GLSL length() may be
// computed differently), the offsets are unfused; with correctly rounded division and sqrt the
// answer is the C++ float answer bit for bit. Elsewhere a pair can flip only when an occupied
// voxel's entry distance lies within a few ulp of dist - psi.
#ifndef VPLKIT_VISIBILITY_VOXEL_VISIBLE_GLSL
#define VPLKIT_VISIBILITY_VOXEL_VISIBLE_GLSL

#include "vplkit/visibility/dda.glsl"
#include "vplkit/visibility/voxel_grid.glsl"

const float vplkit_voxel_surface_offset_default = 1.75;
const float vplkit_voxel_visible_default_tolerance = 2.0;
const float vplkit_voxel_visible_two_sided_default_tolerance = 0.0;

// Ray origin for rays leaving the surface at x with normal n_x (any length): x moved
// offset_voxels * L along n_x. A zero or non-finite normal leaves x where it is. Also the origin of
// the GBG gathering rays (then trace with vplkit_dda_trace_hit_point).
vec3 vplkit_surface_ray_origin(vplkit_voxel_grid g, vec3 x, vec3 n_x, float offset_voxels) {
  vec3 n = vec3(0.0);
  if (!vplkit_dda_unit_direction(n_x, n)) return x;
  precise vec3 o = x + (offset_voxels * vplkit_voxel_length(g)) * n;
  return o;
}

vec3 vplkit_surface_ray_origin(vplkit_voxel_grid g, vec3 x, vec3 n_x) {
  return vplkit_surface_ray_origin(g, x, n_x, vplkit_voxel_surface_offset_default);
}

// Is there no occupied voxel on the segment o -> target before |target - o| - psi? The shared core
// of both tests (o already lifted off its surface).
bool vplkit_voxel_segment_clear(vplkit_voxel_grid g, vec3 o, vec3 target, float tolerance_voxels) {
  precise vec3 to_target = target - o;
  precise float t_max = sqrt(vplkit_voxel_dot(to_target, to_target)) - tolerance_voxels * vplkit_voxel_length(g);
  if (!(t_max > 0.0)) return true;
  return !vplkit_dda_first_hit(g, o, to_target, t_max).hit;
}

// The paper's test: is y visible from the surface point x (normal n_x)? Non-finite x or y: not
// visible (no contribution rather than a NaN one).
bool vplkit_voxel_visible(vplkit_voxel_grid g, vec3 x, vec3 n_x, vec3 y, float offset_voxels,
                          float tolerance_voxels) {
  if (!vplkit_voxel_vec3_finite(x) || !vplkit_voxel_vec3_finite(y)) return false;
  return vplkit_voxel_segment_clear(g, vplkit_surface_ray_origin(g, x, n_x, offset_voxels), y, tolerance_voxels);
}

bool vplkit_voxel_visible(vplkit_voxel_grid g, vec3 x, vec3 n_x, vec3 y) {
  return vplkit_voxel_visible(g, x, n_x, y, vplkit_voxel_surface_offset_default,
                              vplkit_voxel_visible_default_tolerance);
}

// Both ends lifted: are the surface points x (normal n_x) and y (normal n_y) mutually visible?
bool vplkit_voxel_visible_two_sided(vplkit_voxel_grid g, vec3 x, vec3 n_x, vec3 y, vec3 n_y,
                                    float offset_voxels, float tolerance_voxels) {
  if (!vplkit_voxel_vec3_finite(x) || !vplkit_voxel_vec3_finite(y)) return false;
  return vplkit_voxel_segment_clear(g, vplkit_surface_ray_origin(g, x, n_x, offset_voxels),
                                    vplkit_surface_ray_origin(g, y, n_y, offset_voxels), tolerance_voxels);
}

bool vplkit_voxel_visible_two_sided(vplkit_voxel_grid g, vec3 x, vec3 n_x, vec3 y, vec3 n_y) {
  return vplkit_voxel_visible_two_sided(g, x, n_x, y, n_y, vplkit_voxel_surface_offset_default,
                                        vplkit_voxel_visible_two_sided_default_tolerance);
}

#endif  // VPLKIT_VISIBILITY_VOXEL_VISIBLE_GLSL
