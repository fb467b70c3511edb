// SPDX-License-Identifier: MIT
// vplkit GLSL pack: the exhaustive VPL sum L(x) = sum_t L_t(x) V(x, y_t) (docs/math.md section 2),
// the estimand of every CDF method, and the per-sample pieces every VPL-sampling estimator shares;
// mirrors include/vplkit/estimators/vpl_sum.hpp (T = float), its patch form (m x m stratified
// jittered points per texel from a seeded stream at fixed counters, docs/math.md section 11)
// included.
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
#include "vplkit/sampling/rng.glsl"
#include "vplkit/visibility/visibility_callables.glsl"
#include "vplkit/vpl/dprsm_patch.glsl"
#include "vplkit/vpl/dprsm_view.glsl"
#include "vplkit/vpl/vpl.glsl"

// v when every component is finite, else 0: the last guard of every estimator's per-sample value.
vec3 vplkit_estimator_finite_or_zero(vec3 v) {
  return vplkit_is_finite(v) ? v : vec3(0.0);
}

// A drawn sample's pmf as the estimators use it: 0 unless it is a finite normal number (decided
// on the bits, so that neither a flushing GPU nor a folded comparison changes it); mirrors
// estimator_pmf (docs/math.md, "GPU arithmetic model").
float vplkit_estimator_pmf(float p) {
  uint b = floatBitsToUint(p);
  return (b >= 0x00800000u && b < 0x7F800000u) ? p : 0.0;
}

// L_t(x) V(x, y_t) for texel t: 0 for an index outside the view, a texel without flux, or a
// back-facing pair; visibility is queried only when the unoccluded contribution is non-zero.
vec3 vplkit_vpl_visible_contribution(vplkit_gather_point gp, vplkit_dprsm_view view, int t,
                                     vplkit_visibility visibility, float dmin) {
  if (t < 0 || t >= vplkit_dprsm_view_texel_count(view)) return vec3(0.0);
  vplkit_vpl v = vplkit_dprsm_view_vpl_at(view, t);
  vec3 c = vplkit_vpl_contribution(gp, v, dmin);
  if (!(c.x > 0.0 || c.y > 0.0 || c.z > 0.0)) return vec3(0.0);
  return vplkit_visibility_test(visibility, gp.position, gp.normal, v.position, v.normal) ? c : vec3(0.0);
}

// L(y) V(x, y) for the point y of texel t's patch that xi selects (vplkit_dprsm_patch_vpl): the
// per-sample term of every patch-sampled VPL estimator.
vec3 vplkit_vpl_patch_visible_contribution(vplkit_gather_point gp, vplkit_dprsm_view view, int t, vec2 xi,
                                           vplkit_visibility visibility, float dmin, float depth_tolerance) {
  if (t < 0 || t >= vplkit_dprsm_view_texel_count(view)) return vec3(0.0);
  vplkit_dprsm_patch_sample s = vplkit_dprsm_patch_vpl(view, t, xi, depth_tolerance);
  vec3 c = vplkit_vpl_contribution(gp, s.point, dmin);
  if (!(c.x > 0.0 || c.y > 0.0 || c.z > 0.0)) return vec3(0.0);
  return vplkit_visibility_test(visibility, gp.position, gp.normal, s.point.position, s.point.normal) ? c
                                                                                                      : vec3(0.0);
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

// state += c, Neumaier-compensated: every step `precise`, so no reassociation removes the
// compensation.
void vplkit_vpl_sum_state_add(inout vplkit_vpl_sum_state state, vec3 c) {
  precise vec3 sum = state.sum;
  precise vec3 comp = state.compensation;
  precise vec3 s = sum + c;
  precise vec3 big = mix(c, sum, greaterThanEqual(abs(sum), abs(c)));    // the larger term
  precise vec3 small = mix(sum, c, greaterThanEqual(abs(sum), abs(c)));  // the smaller one
  comp += (big - s) + small;
  state.sum = s;
  state.compensation = comp;
}

// Adds L_t(x) V(x, y_t) of the texels [begin, end) (clipped to the view) to the state, in texel
// order; nothing for an invalid (background) gather point. Also the way to split the sum over
// dispatches under llvmpipe's loop budget (docs/glsl.md).
void vplkit_exhaustive_vpl_sum_range(vplkit_gather_point gp, vplkit_dprsm_view view,
                                     inout vplkit_vpl_sum_state state, int begin, int end,
                                     vplkit_visibility visibility, float dmin) {
  if (!vplkit_gather_point_valid(gp)) return;
  int n = vplkit_dprsm_view_texel_count(view);
  int first = begin < 0 ? 0 : begin;
  int last = end < n ? end : n;
  for (int t = first; t < last; ++t)
    vplkit_vpl_sum_state_add(state, vplkit_vpl_visible_contribution(gp, view, t, visibility, dmin));
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

// ---- patch form: texel t's stratum (i, j) of m x m takes u0, u1 from `stream` at the counters
// stream.counter + 2 (t m^2 + j m + i) and + 1 (random access: any split of the texels gives the
// same numbers); xi = ((i + u0) / m, (j + u1) / m).
vec2 vplkit_exhaustive_vpl_patch_jitter(vplkit_counter_rng stream, int t, int strata, int i, int j) {
  uint m = uint(strata);
  vplkit_counter_rng r = vplkit_counter_rng(stream.key, stream.counter + 2u * (uint(t) * m * m + uint(j) * m + uint(i)));
  float u0 = vplkit_rng_next_unit(r);
  float u1 = vplkit_rng_next_unit(r);
  return vec2((float(i) + u0) / float(strata), (float(j) + u1) / float(strata));
}

// Adds sum_k L(y_tk) V(x, y_tk) over the m^2 strata of the texels [begin, end) (clipped), texel by
// texel, strata row by row; nothing for an invalid gather point or strata <= 0.
void vplkit_exhaustive_vpl_patch_sum_range(vplkit_gather_point gp, vplkit_dprsm_view view,
                                           inout vplkit_vpl_sum_state state, int begin, int end,
                                           vplkit_counter_rng stream, int strata, vplkit_visibility visibility,
                                           float dmin, float depth_tolerance) {
  if (!vplkit_gather_point_valid(gp) || strata <= 0) return;
  int n = vplkit_dprsm_view_texel_count(view);
  int first = begin < 0 ? 0 : begin;
  int last = end < n ? end : n;
  for (int t = first; t < last; ++t) {
    if (!vplkit_vpl_has_flux(vplkit_dprsm_view_vpl_at(view, t))) continue;
    for (int j = 0; j < strata; ++j)
      for (int i = 0; i < strata; ++i)
        vplkit_vpl_sum_state_add(state, vplkit_vpl_patch_visible_contribution(
                                            gp, view, t, vplkit_exhaustive_vpl_patch_jitter(stream, t, strata, i, j),
                                            visibility, dmin, depth_tolerance));
  }
}

// The compensated total divided by m^2; 0 for strata <= 0.
vec3 vplkit_exhaustive_vpl_patch_sum_finish(vplkit_vpl_sum_state state, int strata) {
  if (strata <= 0) return vec3(0.0);
  precise vec3 total = state.sum + state.compensation;
  return total / (float(strata) * float(strata));
}

vec3 vplkit_exhaustive_vpl_patch_sum(vplkit_gather_point gp, vplkit_dprsm_view view, vplkit_counter_rng stream,
                                     int strata, vplkit_visibility visibility, float dmin, float depth_tolerance) {
  if (!vplkit_gather_point_valid(gp) || strata <= 0) return vec3(0.0);
  vplkit_vpl_sum_state state = vplkit_make_vpl_sum_state();
  vplkit_exhaustive_vpl_patch_sum_range(gp, view, state, 0, vplkit_dprsm_view_texel_count(view), stream, strata,
                                        visibility, dmin, depth_tolerance);
  return vplkit_exhaustive_vpl_patch_sum_finish(state, strata);
}

#endif  // VPLKIT_ESTIMATORS_VPL_SUM_GLSL
