// SPDX-License-Identifier: MIT
// vplkit GLSL pack: gathering-based global (GBG) weights (paper 5.3 and Alg. 2, docs/math.md
// section 4); mirrors include/vplkit/builders/gbg_weights.hpp (T = float): the same random numbers
// (stream = pixel, direction j = counters 2j, 2j + 1), rays, lookups and hit values. The kernels
// gbg_accumulate.comp (per gather point) and gbg_finish.comp (per texel) run it.
// The C++ `double* acc` becomes the HOOK void vplkit_store_gbg_hit(int texel, float value), called
// once per lit hit; gbg_accumulate.comp adds the value in 64-bit fixed point with 32-bit atomics,
// with the helpers below (format, precision, the choice of scale and max_units:
// docs/glsl/builders.md, "GBG"). The tracer is a vplkit_voxel_tracer. ACCESSORS: the DPRSM's and
// vplkit_load_voxel_word; define them and the hook whenever this file is included
// (docs/glsl.md, "Accessors and Mesa's linker").
#ifndef VPLKIT_BUILDERS_GBG_WEIGHTS_GLSL
#define VPLKIT_BUILDERS_GBG_WEIGHTS_GLSL

#include "vplkit/core/gather_point.glsl"
#include "vplkit/core/unit_or_zero.glsl"
#include "vplkit/sampling/cosine_hemisphere.glsl"
#include "vplkit/sampling/orthonormal_basis.glsl"
#include "vplkit/sampling/rng.glsl"
#include "vplkit/visibility/visibility_callables.glsl"
#include "vplkit/vpl/dprsm_lookup.glsl"
#include "vplkit/vpl/dprsm_view.glsl"
#include "vplkit/vpl/luminance.glsl"
#include "vplkit/vpl/vpl.glsl"

// C++ enum class gbg_accumulator { paper, gathering }.
const int vplkit_gbg_accumulator_paper = 0;      // luminance of the VPL's contribution to x (eq. 5)
const int vplkit_gbg_accumulator_gathering = 1;  // luminance of the gathering estimator's rho_x L_o(y)

struct vplkit_gbg_params {
  int n_dirs;             // NBDIR, >= 1 (validated by the host)
  float dmin;             // VPL distance clamp of the paper accumulator
  float depth_tolerance;  // of vplkit_dprsm_lookup (add vplkit_voxel_tracer_depth_tolerance)
  uint seed;              // streams are pixel indices
  int accumulator;
  bool fill_holes;        // gbg_finish.comp: run the hole-aware median fill
};

void vplkit_store_gbg_hit(int texel, float value);

// Value accumulated for one lit hit.
float vplkit_gbg_hit_value(vplkit_gather_point g, vplkit_dprsm_view view, vplkit_dprsm_lookup_result lookup,
                           vplkit_ray_hit hit, float dmin, int accumulator, float depth_tolerance) {
  if (accumulator == vplkit_gbg_accumulator_paper)
    return vplkit_luminance(vplkit_vpl_contribution(g, vplkit_dprsm_view_vpl_at(view, lookup.texel), dmin));
  // As the gathering estimator: one-sided, a hit on a known surface shaded as itself, an inexact
  // hit evaluated on the texel's plane.
  return vplkit_luminance(g.albedo * vplkit_dprsm_hit_radiance(view, lookup, g.position, hit, depth_tolerance));
}

// Direction j of gather point `pixel` (the counter is set explicitly: any order, one thread each).
vec3 vplkit_gbg_direction(vec3 n_x, int pixel, int j, uint seed) {
  vplkit_counter_rng rng = vplkit_make_counter_rng(seed, uint(pixel));
  rng.counter = 2u * uint(j);
  float u0 = vplkit_rng_next_unit(rng);
  float u1 = vplkit_rng_next_unit(rng);
  return vplkit_to_world(vplkit_make_orthonormal_basis(n_x), vplkit_sample_cosine_hemisphere(vec2(u0, u1)));
}

// Directions dir_begin .. dir_end - 1 of one valid gather point (the C++ runs 0 .. n_dirs - 1;
// the range lets a host split the rays over several dispatches, see gbg_accumulate.comp). Calls
// vplkit_store_gbg_hit once per lit hit; returns (hits, lit hits) as the C++ stats count them.
ivec2 vplkit_gbg_accumulate_gather_point(vplkit_gather_point g, int pixel, vplkit_dprsm_view view,
                                         vplkit_voxel_tracer tracer, vplkit_gbg_params params, int dir_begin,
                                         int dir_end) {
  vplkit_orthonormal_basis frame = vplkit_make_orthonormal_basis(vplkit_gather_point_shading_normal(g));
  vplkit_counter_rng rng = vplkit_make_counter_rng(params.seed, uint(pixel));
  rng.counter = 2u * uint(dir_begin);
  int hits = 0, lit = 0;
  for (int j = dir_begin; j < dir_end; ++j) {
    float u0 = vplkit_rng_next_unit(rng);
    float u1 = vplkit_rng_next_unit(rng);
    vec3 local = vplkit_sample_cosine_hemisphere(vec2(u0, u1));
    if (!(local.z > 0.0)) continue;  // on the horizon p1 = 0: no contribution, no trace
    vec3 dir = vplkit_to_world(frame, local);
    if (!vplkit_gather_point_accepts_direction(g, dir)) continue;  // below the geometric surface: 0
    vplkit_ray_hit h = vplkit_voxel_tracer_trace(tracer, g.position, g.normal, dir);
    if (!h.hit) continue;
    ++hits;
    if (vplkit_vpl_hit_on_own_plane(g.position, h)) continue;  // edge-on from x: no light for x's VPLs
    vplkit_dprsm_lookup_result r = vplkit_dprsm_lookup(view, h.position, params.depth_tolerance);
    if (!r.lit || !vplkit_vpl_has_flux(vplkit_dprsm_view_vpl_at(view, r.texel))) continue;
    ++lit;
    vplkit_store_gbg_hit(r.texel, vplkit_gbg_hit_value(g, view, r, h, params.dmin, params.accumulator, params.depth_tolerance));
  }
  return ivec2(hits, lit);
}

// ---- 64-bit fixed point (see the header) --------------------------------------------------------

// Units of one value as (lo, hi): roundEven(min(v * scale, max_units)); 0 for v <= 0 or NaN.
// max_units <= 2^63.
uvec2 vplkit_gbg_fixed_units(float value, float scale, float max_units) {
  if (!(value > 0.0) || vplkit_is_nan(value)) return uvec2(0u);
  float q = roundEven(min(value * scale, max_units));
  float hi = floor(q * 2.3283064365386962890625e-10);  // q / 2^32, exact
  float lo = q - hi * 4294967296.0;                     // exact: the multiples of q's ulp below 2^32
  return uvec2(uint(lo), uint(hi));
}

// Does the value saturate (v * scale > max_units)?
bool vplkit_gbg_fixed_saturates(float value, float scale, float max_units) {
  return value * scale > max_units;
}

// The accumulated integer hi * 2^32 + lo as a float (within 1.5 ulps).
float vplkit_gbg_fixed_to_float(uint lo, uint hi) {
  return float(hi) * 4294967296.0 + float(lo);
}

#endif  // VPLKIT_BUILDERS_GBG_WEIGHTS_GLSL
