// vplkit GLSL pack: VPL sampling by inverse transform (DESIGN 3.3):
// L^(x) = (1/N) sum_k L_{t_k}(x) V / p(t_k), t_k ~ p; mirrors
// include/vplkit/estimators/vpl_sampling_estimator.hpp (T = float).
//
// DISTRIBUTION HOOKS. The C++ estimators are templates over the distribution (discrete_cdf,
// alias_table, defensive_mixture, flat_face_roulette, ...); GLSL has no templates, so the
// estimators name a distribution by a uint id and the including shader defines two functions that
// sample it and evaluate its pmf (the same two prototypes are declared in vpl_sampling_estimator.glsl,
// local_estimator.glsl and mis_estimator.glsl; define them once):
//   vplkit_discrete_sample vplkit_estimator_distribution_sample(uint distribution, float u);
//     C++ distribution.sample(u): {index over the flat DPRSM index face * R * R + y * R + x, pmf}
//   float vplkit_estimator_distribution_pmf(uint distribution, uint index);
//     C++ distribution.pmf(index)
// Typically one line each over the distribution pack, e.g. for defensive mixtures (eps = 0 is the
// plain discrete CDF, bit for bit) held in the shader:
//   vplkit_discrete_sample vplkit_estimator_distribution_sample(uint d, float u) {
//     return vplkit_defensive_mixture_sample(my_mixture(d), u); }
//   float vplkit_estimator_distribution_pmf(uint d, uint i) {
//     return vplkit_defensive_mixture_pmf(my_mixture(d), i); }
// (vplkit_discrete_cdf_*, vplkit_alias_table_*, vplkit_flat_face_roulette_* work the same way.)
// A draw with pmf 0 (empty distribution) or an index outside the view adds 0 and is never divided.
//
// Random numbers, as in the C++: for k = 0 .. N-1, one u = vplkit_rng_next_unit(rng) passed to the
// sample hook. An invalid gather point or N <= 0 returns 0 and consumes none. Visibility: a
// vplkit_visibility value (visibility/visibility_callables.glsl) stands for the C++ callable.
//
// ACCESSORS used: those of vpl/dprsm_view.glsl and visibility/voxel_grid.glsl, plus the two hooks.
// Divisions by a pmf go through vplkit_mis_div (mis/heuristics.glsl): x / y for any y, so a
// denormal pmf divides as in C++ on devices that keep denormals (llvmpipe).
#ifndef VPLKIT_ESTIMATORS_VPL_SAMPLING_ESTIMATOR_GLSL
#define VPLKIT_ESTIMATORS_VPL_SAMPLING_ESTIMATOR_GLSL

#include "vplkit/core/gather_point.glsl"
#include "vplkit/distribution/discrete_sample.glsl"
#include "vplkit/estimators/estimator_state.glsl"
#include "vplkit/estimators/vpl_sum.glsl"
#include "vplkit/mis/heuristics.glsl"
#include "vplkit/sampling/rng.glsl"
#include "vplkit/visibility/visibility_callables.glsl"
#include "vplkit/vpl/dprsm_view.glsl"

vplkit_discrete_sample vplkit_estimator_distribution_sample(uint distribution, float u);
float vplkit_estimator_distribution_pmf(uint distribution, uint index);

// c / p per component, p > 0 (vplkit_mis_div: GLSL specifies x / y only for |y| in [2^-126, 2^126]).
vec3 vplkit_estimator_div(vec3 c, float p) {
  return vec3(vplkit_mis_div(c.x, p), vplkit_mis_div(c.y, p), vplkit_mis_div(c.z, p));
}

// One sample's value L_t V / p(t) for the draw u (0 when pmf is 0 or t is out of range).
vec3 vplkit_vpl_sampling_sample(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution, float u,
                                vplkit_visibility visibility, float dmin) {
  vplkit_discrete_sample s = vplkit_estimator_distribution_sample(distribution, u);
  float pmf = s.pmf;
  if (!(pmf > 0.0) || s.index >= uint(vplkit_dprsm_view_texel_count(view))) return vec3(0.0);
  vec3 c = vplkit_vpl_visible_contribution(gp, view, int(s.index), visibility, dmin);
  // A denormal pmf can overflow the quotient: such a draw has negligible probability, and an Inf
  // would poison the image, so it adds 0.
  return vplkit_estimator_finite_or_zero(vplkit_estimator_div(c, pmf));
}

// Samples [begin, end) of vplkit_estimate_vpl_sampling (estimator_state.glsl).
void vplkit_estimate_vpl_sampling_range(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution,
                                        inout vplkit_estimator_state state, int begin, int end,
                                        vplkit_visibility visibility, float dmin) {
  if (!vplkit_gather_point_valid(gp)) return;
  for (int k = begin; k < end; ++k)
    state.sum += vplkit_vpl_sampling_sample(gp, view, distribution, vplkit_rng_next_unit(state.rng), visibility,
                                            dmin);
}

vec3 vplkit_estimate_vpl_sampling_finish(vplkit_estimator_state state, int n_samples) {
  return n_samples > 0 ? state.sum / float(n_samples) : vec3(0.0);
}

vec3 vplkit_estimate_vpl_sampling(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution,
                                  inout vplkit_counter_rng rng, int n_samples, vplkit_visibility visibility,
                                  float dmin) {
  if (!vplkit_gather_point_valid(gp) || n_samples <= 0) return vec3(0.0);
  vplkit_estimator_state state = vplkit_make_estimator_state(rng);
  vplkit_estimate_vpl_sampling_range(gp, view, distribution, state, 0, n_samples, visibility, dmin);
  rng = state.rng;
  return vplkit_estimate_vpl_sampling_finish(state, n_samples);
}

#endif  // VPLKIT_ESTIMATORS_VPL_SAMPLING_ESTIMATOR_GLSL
