// vplkit GLSL pack: the exhaustive VPL sum L(x) = sum_t L_t(x) V(x, y_t) (DESIGN 3.2), the estimand
// of every CDF method, and the per-sample pieces every VPL-sampling estimator shares; mirrors
// include/vplkit/estimators/vpl_sum.hpp (T = float).
//
// Visibility: a vplkit_visibility value (visibility/visibility_callables.glsl) stands for the C++
// Visibility callable: V = 1, the two-sided or one-sided voxel test, or the user's hook.
//
// ACCESSORS used (defined by the including shader):
//   vec3 vplkit_load_dprsm_position(int texel), vplkit_load_dprsm_normal(int texel),
//   vplkit_load_dprsm_albedo(int texel)  (vpl/dprsm_view.glsl);
//   uint vplkit_load_voxel_word(uint word_index)  (visibility/voxel_grid.glsl).
//
// Where the GPU differs from the CPU:
//  - exhaustive_vpl_sum accumulates in double on the CPU. GLSL is float only here (Vulkan needs an
//    optional feature for doubles), so the GPU sums with Neumaier's compensated summation, every
//    step `precise` (no reassociation may remove the compensation): the sum of the float terms is
//    then accurate to about 2 float ulps whatever the number of terms, the double sum's accuracy
//    in practice. What remains is each term's own float error (docs/glsl/estimators.md).
//  - vplkit_estimator_finite_or_zero decides "finite" on the bits: Mesa rewrites
//    `a <= c && b <= c` into `max(a, b) <= c`, and max() drops a NaN operand.
#ifndef VPLKIT_ESTIMATORS_VPL_SUM_GLSL
#define VPLKIT_ESTIMATORS_VPL_SUM_GLSL

#include "vplkit/core/gather_point.glsl"
#include "vplkit/visibility/visibility_callables.glsl"
#include "vplkit/vpl/dprsm_view.glsl"
#include "vplkit/vpl/vpl.glsl"

// v when every component is finite, else 0: the last guard of every estimator's per-sample value.
vec3 vplkit_estimator_finite_or_zero(vec3 v) {
  bvec3 bad = equal(floatBitsToUint(v) & 0x7F800000u, uvec3(0x7F800000u));  // NaN or +-inf
  return any(bad) ? vec3(0.0) : v;
}

// L_t(x) V(x, y_t) for texel t: 0 for an index outside the view, a texel without flux, or a
// back-facing pair; visibility is queried only when the unoccluded contribution is non-zero.
vec3 vplkit_vpl_visible_contribution(vplkit_gather_point gp, vplkit_dprsm_view view, int t,
                                     vplkit_visibility visibility, float dmin) {
  if (t < 0 || t >= vplkit_dprsm_view_texel_count(view)) return vec3(0.0);
  vplkit_vpl v = vplkit_dprsm_view_vpl_at(view, t);
  vec3 c = vplkit_vpl_contribution(gp.position, gp.normal, gp.albedo, v, dmin);
  if (!(c.x > 0.0 || c.y > 0.0 || c.z > 0.0)) return vec3(0.0);
  return vplkit_visibility_test(visibility, gp.position, gp.normal, v.position, v.normal) ? c : vec3(0.0);
}

// GLSL-only: sum_t L_t(x) V(x, y_t) over the texels first .. first + count - 1 (clipped to the
// view), compensated as below. For splitting the exhaustive sum over invocations: llvmpipe (Mesa
// 22.3, measured) runs at most 65535 loop iterations per invocation, all loops together, and
// silently exits every loop after that; one voxel visibility test marches up to nx + ny + nz
// voxels, so the whole sum with voxel visibility exceeds that budget from about R = 16 on. Sum the
// partial results of texel ranges (in double, or compensated) instead.
vec3 vplkit_exhaustive_vpl_sum_range(vplkit_gather_point gp, vplkit_dprsm_view view,
                                     vplkit_visibility visibility, float dmin, int first, int count) {
  if (!vplkit_gather_point_valid(gp)) return vec3(0.0);
  precise vec3 sum = vec3(0.0);
  precise vec3 comp = vec3(0.0);  // Neumaier: the low-order parts lost by the additions
  int n = vplkit_dprsm_view_texel_count(view);
  int begin = first < 0 ? 0 : first;
  int end = count > n - begin ? n : begin + count;
  for (int t = begin; t < end; ++t) {
    vec3 c = vplkit_vpl_visible_contribution(gp, view, t, visibility, dmin);
    precise vec3 s = sum + c;
    precise vec3 big = mix(c, sum, greaterThanEqual(abs(sum), abs(c)));    // the larger term
    precise vec3 small = mix(sum, c, greaterThanEqual(abs(sum), abs(c)));  // the smaller one
    comp += (big - s) + small;
    sum = s;
  }
  precise vec3 total = sum + comp;
  return total;
}

// sum_t L_t(x) V(x, y_t) over all 2 R^2 texels; 0 for an invalid (background) gather point.
// Compensated float summation (see the header) where the C++ sums in double. See
// vplkit_exhaustive_vpl_sum_range for llvmpipe's loop budget.
vec3 vplkit_exhaustive_vpl_sum(vplkit_gather_point gp, vplkit_dprsm_view view,
                               vplkit_visibility visibility, float dmin) {
  return vplkit_exhaustive_vpl_sum_range(gp, view, visibility, dmin, 0, vplkit_dprsm_view_texel_count(view));
}

#endif  // VPLKIT_ESTIMATORS_VPL_SUM_GLSL
