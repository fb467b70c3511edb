// vplkit GLSL pack: the exhaustive VPL sum L(x) = sum_t L_t(x) V(x, y_t) (docs/math.md section 2),
// the estimand of every CDF method, and the per-sample pieces every VPL-sampling estimator shares;
// mirrors include/vplkit/estimators/vpl_sum.hpp (T = float).
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
//  - vplkit_estimator_finite_or_zero decides "finite" on the bits: compilers may fold NaN
//    comparisons (docs/glsl.md, "NaN, FMA and compiler rewrites").
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

// The exhaustive sum's running total: a Neumaier-compensated float pair where the C++
// vpl_sum_state keeps a double (see the header).
struct vplkit_vpl_sum_state {
  vec3 sum;
  vec3 compensation;  // the low-order parts lost by the additions
};

vplkit_vpl_sum_state vplkit_make_vpl_sum_state() {
  return vplkit_vpl_sum_state(vec3(0.0), vec3(0.0));
}

// Adds L_t(x) V(x, y_t) of the texels [begin, end) (clipped to the view) to the state, in texel
// order; nothing for an invalid (background) gather point. Also the way to split the sum over
// dispatches under llvmpipe's loop budget (docs/glsl.md).
void vplkit_exhaustive_vpl_sum_range(vplkit_gather_point gp, vplkit_dprsm_view view,
                                     inout vplkit_vpl_sum_state state, int begin, int end,
                                     vplkit_visibility visibility, float dmin) {
  if (!vplkit_gather_point_valid(gp)) return;
  precise vec3 sum = state.sum;
  precise vec3 comp = state.compensation;
  int n = vplkit_dprsm_view_texel_count(view);
  int first = begin < 0 ? 0 : begin;
  int last = end < n ? end : n;
  for (int t = first; t < last; ++t) {
    vec3 c = vplkit_vpl_visible_contribution(gp, view, t, visibility, dmin);
    precise vec3 s = sum + c;
    precise vec3 big = mix(c, sum, greaterThanEqual(abs(sum), abs(c)));    // the larger term
    precise vec3 small = mix(sum, c, greaterThanEqual(abs(sum), abs(c)));  // the smaller one
    comp += (big - s) + small;
    sum = s;
  }
  state.sum = sum;
  state.compensation = comp;
}

// The compensated total.
vec3 vplkit_exhaustive_vpl_sum_finish(vplkit_vpl_sum_state state) {
  precise vec3 total = state.sum + state.compensation;
  return total;
}

// sum_t L_t(x) V(x, y_t) over all 2 R^2 texels; 0 for an invalid (background) gather point.
vec3 vplkit_exhaustive_vpl_sum(vplkit_gather_point gp, vplkit_dprsm_view view,
                               vplkit_visibility visibility, float dmin) {
  if (!vplkit_gather_point_valid(gp)) return vec3(0.0);
  vplkit_vpl_sum_state state = vplkit_make_vpl_sum_state();
  vplkit_exhaustive_vpl_sum_range(gp, view, state, 0, vplkit_dprsm_view_texel_count(view), visibility, dmin);
  return vplkit_exhaustive_vpl_sum_finish(state);
}

#endif  // VPLKIT_ESTIMATORS_VPL_SUM_GLSL
