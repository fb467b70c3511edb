// SPDX-License-Identifier: MIT
#pragma once
// Presampled candidates for ris-mis (docs/math.md, "Presampled candidates"): the light-tile idea of
// RTXDI's local-light presampling (Wyman and Panteleev 2021) applied to the DPRSM's VPLs. Once per
// frame, P entries are drawn from the candidate distribution (texel t with probability pmf(t), a
// jitter xi uniform on the unit square) and everything about each one that does not depend on the
// gather point is made then: its patch point y, unit normal n_t, reflected radiance L_o(y) (a
// diffuse texel sends the same radiance every way), pmf(t) and the area of its p2. A gather point's
// candidate is then an entry drawn uniformly from the pool; weighing it is a few dot products on
// one record instead of a CDF search, a patch construction and a light evaluation on five arrays.
//
// Unbiased: a uniformly drawn entry of a pool of independent draws is itself a draw of (t, xi)
// with density pmf(t) (marginally, over the pool's randomness), and RIS's estimate
// (1/M) sum_i f(X_i) / p(X_i) over its candidates needs only each candidate's marginal density,
// not their independence (math.md). Candidates of one gather point, and of neighbouring ones, may
// share entries: that adds the variance of a P-sample estimate, small where P is much larger than
// the candidates one gather point draws, and it correlates the noise of neighbouring pixels.
//
// The pool is filled once per frame (ris_pool_draw_entry for i < P, in any order: entries are
// independent) and read by every gather point of that frame. With per-region distributions (the
// local source) each region has its own pool. Used by ris-mis (the renderer's --candidate-pool);
// its estimate and MIS weights are those of ris_mis_estimator.hpp, only the candidates' origin
// changes, so a gathering direction's p2 is still pmf(t) of the same distribution.
//
// Random numbers (the GLSL mirror follows them): entry i of a pool filled with seed s takes
// counter_rng(s, i): u, then with vpl_mode::patch xi0 and xi1 (ris_mis_resample's per-candidate
// layout). A candidate from the pool takes u (the entry ris_pool_index(u, P)) and then its selection
// u: 2 M numbers per reservoir, whatever the vpl_mode.
#include <vplkit/core/gather_point.hpp>
#include <vplkit/core/prefetch.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/distribution/weighted_reservoir.hpp>
#include <vplkit/estimators/mis_estimator.hpp>
#include <vplkit/estimators/ris_mis_estimator.hpp>
#include <vplkit/estimators/ris_reservoir.hpp>
#include <vplkit/estimators/estimator_state.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/sampling/cosine_hemisphere.hpp>
#include <vplkit/sampling/orthonormal_basis.hpp>
#include <vplkit/sampling/rng.hpp>
#include <vplkit/vpl/dprsm_patch.hpp>
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/luminance.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <cstdint>

namespace vplkit {

// One presampled candidate: what weighing it at any gather point needs (64 bytes for float, the
// layout of the buffer record ris_pool_params.h). pmf 0: an empty entry (the
// draw was empty, left the view, or its point has no flux), which every gather point weighs 0.
template <class T>
struct ris_pool_entry {
  vec3<T> position{T(0)};  // y: the texel's point (vpl_mode::point) or its jittered patch point
  T pmf = T(0);            // pmf(t) of the distribution the pool was drawn from
  vec3<T> normal{T(0)};    // unit n_t (also the normal the visibility query gets)
  T area = T(0);           // the A of p2 (A_t, or A(uv) for a patch point)
  vec3<T> radiance{T(0)};  // L_o(y) = rho_t I cos(alpha) / (pi d1^2), the same bits as at the gather point
  int texel = -1;
  vec2<T> xi{T(0)};        // the jitter (0 with vpl_mode::point)
  int at_centre = 0;       // 1: the patch moved the point to the texel centre (gathering's alone when n1 > 0)
  int pad = 0;
};

// Entry for the draw c (ris_mis_draw_candidate) with its jitter already in c.s.xi.
template <class T>
inline ris_pool_entry<T> ris_pool_make_entry(const dprsm_view<T>& view, const ris_mis_draw<T>& c, vpl_mode mode,
                                             T depth_tolerance) {
  ris_pool_entry<T> e;
  e.texel = c.s.texel;
  e.xi = c.s.xi;
  if (c.s.texel < 0 || !(c.pmf > T(0))) return e;
  vpl<T> v;
  vec3<T> n_v;
  T area;
  if (mode == vpl_mode::patch) {
    const dprsm_patch_sample<T> p = dprsm_patch_vpl(view, c.s.texel, c.s.xi, depth_tolerance);
    v = p.point;
    if (!vpl_has_flux(v)) return e;
    n_v = view.plane_at(c.s.texel).normal;
    area = vpl_patch_area(p.solid_angle, p.distance, p.cos_alpha);
    e.at_centre = p.at_centre ? 1 : 0;
  } else {
    v = view.vpl_at(c.s.texel);
    if (!vpl_has_flux(v)) return e;
    n_v = unit_or_zero(v.normal);
    area = mis_texel_patch_area(view, c.s.texel);
  }
  e.position = v.position;
  e.normal = n_v;
  e.area = area;
  e.radiance = reflected_radiance_unit_normal(view.light.position, view.light.intensity, v.position, n_v,
                                              view.albedo[c.s.texel]);
  e.pmf = c.pmf;
  return e;
}

// Entry i of a pool: draws u, then with vpl_mode::patch xi0, xi1, from counter_rng(seed, i).
template <class T, class Distribution>
inline ris_pool_entry<T> ris_pool_draw_entry(const dprsm_view<T>& view, const Distribution& distribution,
                                             std::uint32_t seed, std::uint32_t i, vpl_mode mode, T depth_tolerance) {
  counter_rng rng = make_counter_rng(seed, i);
  const T u = rng_next_unit<T>(rng);
  vec2<T> xi(T(0));
  if (mode == vpl_mode::patch) {
    xi.x = rng_next_unit<T>(rng);
    xi.y = rng_next_unit<T>(rng);
  }
  return ris_pool_make_entry(view, ris_mis_draw_candidate(view, distribution, u, xi), mode, depth_tolerance);
}

// h of ris_mis_unshadowed for entry e: the same expressions on the stored parts, so the same bits.
template <class T>
inline vec3<T> ris_pool_unshadowed(const gather_point<T>& gp, const mis_receiver<T>& rx, const ris_pool_entry<T>& e,
                                   T n1, T n2) {
  const T pmf = estimator_pmf(e.pmf);  // a denormal pmf counts as 0, as on a GPU that flushes (vpl_sum.hpp)
  if (!(pmf > T(0)) || !(n2 > T(0))) return vec3<T>(T(0));
  if (e.at_centre != 0 && n1 > T(0)) return vec3<T>(T(0));
  if (vpl_points_coincide(gp.position, e.position)) return vec3<T>(T(0));
  const vec3<T> wd = unit_or_zero(e.position - gp.position);  // x -> y
  const T cos2 = glm::dot(rx.shading_unit, wd);
  const T cos1 = -glm::dot(e.normal, wd);
  if (!(cos2 > T(0)) || !(cos1 > T(0)) || !(glm::dot(rx.geometric_unit, wd) > T(0))) return vec3<T>(T(0));
  const vec3<T> f = gp.albedo * e.radiance * (cos2 / vpl_pi<T>);
  const T p1 = cosine_pdf_solid_angle(cos2);
  const vec3<T> w = gp.position - e.position;
  const T p2 = vpl_pdf_solid_angle(pmf, glm::dot(w, w), e.area, cos1);
  return estimator_finite_or_zero(mis_balance_value(f, n1, p1, n2, p2) * (n2 * pmf));
}

// The entry that u in [0, 1) picks of a pool of pool_size > 0 entries: floor(u P), clamped below
// P (u P rounds up to P for u within half an ulp of 1).
template <class T>
inline std::uint32_t ris_pool_index(T u, std::uint32_t pool_size) {
  const T x = u * T(pool_size);
  if (!(x > T(0))) return 0u;  // NaN and negative u: the first entry
  const std::uint32_t i = x < T(pool_size) ? std::uint32_t(x) : pool_size;
  return i < pool_size ? i : pool_size - 1u;
}

// One reservoir of n_candidates candidates drawn uniformly from the pool (pool_size entries):
// ris_mis_resample's normalisation (weight_sum = (1/M) sum target / pmf, confidence M) and kept
// record (ris_mis_shade_kept shades it), the kept sample as (texel, xi) so that spatial reuse
// (ris_mis_spatial_reuse) re-evaluates it at a neighbour as any other. Empty for an invalid gather
// point, n_candidates <= 0, n2 <= 0 or an empty pool (no numbers drawn then). The candidates go in
// batches of ris_mis_draw_batch: first each one's two numbers (u, then its selection u: the
// one-at-a-time layout, which the GLSL mirror runs) and a prefetch of its entry, then their
// weights and reservoir updates in order: the same reservoir, with the entries' cache misses
// overlapped (a pool of 16384 entries is 1 MiB).
template <class T>
inline ris_reservoir<T> ris_mis_resample_pooled(const gather_point<T>& gp, const ris_pool_entry<T>* pool,
                                                std::uint32_t pool_size, counter_rng& rng, int n_candidates, T n1,
                                                T n2, ris_mis_kept<T>& kept) {
  ris_reservoir<T> r;
  kept = ris_mis_kept<T>{};
  if (!gather_point_valid(gp) || n_candidates <= 0 || !(n2 > T(0)) || pool_size == 0) return r;
  weighted_reservoir<T> res;
  const mis_receiver<T> rx = make_mis_receiver(gp);
  for (int k0 = 0; k0 < n_candidates; k0 += ris_mis_draw_batch) {
    const int n = n_candidates - k0 < ris_mis_draw_batch ? n_candidates - k0 : ris_mis_draw_batch;
    const ris_pool_entry<T>* e[ris_mis_draw_batch];
    T u_keep[ris_mis_draw_batch];
    for (int k = 0; k < n; ++k) {
      const T u = rng_next_unit<T>(rng);
      u_keep[k] = rng_next_unit<T>(rng);
      e[k] = pool + ris_pool_index(u, pool_size);
      prefetch_read(e[k]);
    }
    for (int k = 0; k < n; ++k) {
      const vec3<T> h = ris_pool_unshadowed(gp, rx, *e[k], n1, n2);
      const T target = luminance(h);
      if (!reservoir_weight_usable(target)) continue;
      // A usable target means a normal-range pmf (ris_pool_unshadowed), so the quotient is finite or +Inf.
      if (reservoir_update(res, std::uint32_t(k0 + k), target / estimator_pmf(e[k]->pmf), u_keep[k])) {
        r.kept = ris_sample<T>{e[k]->texel, e[k]->xi};
        r.target = target;
        kept = ris_mis_kept<T>{h, e[k]->position, e[k]->normal};
      }
    }
  }
  const T m = T(n_candidates);
  r.confidence = m;
  if (!reservoir_empty_of(res)) r.weight_sum = res.weight_sum / m;
  return r;
}

// Steps [begin, end) of estimate_ris_mis_pooled (estimator_state.hpp): estimate_ris_mis_range with
// each reservoir's candidates from the pool. `distribution` is the one the pool was drawn from (the
// gathering directions' p2 reads its pmf). Negative counts count as 0; n_candidates <= 0 or an
// empty pool (pool_size 0) makes n_ris 0: gathering alone, with its weights at n2 = 0, as
// estimate_ris_mis does for n_candidates <= 0 (RIS lines that add nothing beside weights that count
// them would lose the integral of w2 f).
template <class T, class Distribution, class Tracer, class Visibility>
inline void estimate_ris_mis_pooled_range(const gather_point<T>& gp, const dprsm_view<T>& view,
                                          const Distribution& distribution, const ris_pool_entry<T>* pool,
                                          std::uint32_t pool_size, estimator_state<T>& state, int begin, int end,
                                          int n_dirs, int n_ris, int n_candidates, const Tracer& tracer,
                                          const Visibility& visibility, T depth_tolerance,
                                          vpl_mode vmode = vpl_mode::point) {
  if (!gather_point_valid(gp)) return;
  if (n_dirs < 0) n_dirs = 0;
  if (n_ris < 0 || n_candidates <= 0 || pool_size == 0) n_ris = 0;  // an empty pool: gathering alone
  const T n1 = T(n_dirs), n2 = ris_mis_vpl_samples<T>(n_ris, n_candidates);
  const orthonormal_basis<T> frame = make_orthonormal_basis(gather_point_shading_normal(gp));
  for (int j = begin; j < end; ++j) {
    if (j < n_ris) {
      ris_mis_kept<T> kept;
      const ris_reservoir<T> r = ris_mis_resample_pooled(gp, pool, pool_size, state.rng, n_candidates, n1, n2, kept);
      state.sum += ris_mis_shade_kept(gp, r, kept, visibility) / T(n_ris);
    }
    if (j < n_dirs) {
      const T u0 = rng_next_unit<T>(state.rng);
      const T u1 = rng_next_unit<T>(state.rng);
      state.sum += mis_gathering_sample(gp, view, distribution, frame, sample_cosine_hemisphere(vec2<T>(u0, u1)),
                                        tracer, depth_tolerance, n1, n2, mis_mode::solid_angle, vmode);
    }
  }
}

// estimate_ris_mis with the candidates of every reservoir drawn from the pool; finish with
// estimate_ris_mis_finish (the range form). F of ris_mis_estimator.hpp, unbiased for the same
// integral.
template <class T, class Distribution, class Tracer, class Visibility>
inline vec3<T> estimate_ris_mis_pooled(const gather_point<T>& gp, const dprsm_view<T>& view,
                                       const Distribution& distribution, const ris_pool_entry<T>* pool,
                                       std::uint32_t pool_size, counter_rng& rng, int n_dirs, int n_ris,
                                       int n_candidates, const Tracer& tracer, const Visibility& visibility,
                                       T depth_tolerance, vpl_mode vmode = vpl_mode::point) {
  if (!gather_point_valid(gp)) return vec3<T>(T(0));
  if (n_dirs < 0) n_dirs = 0;
  if (n_ris < 0 || n_candidates <= 0 || pool_size == 0) n_ris = 0;  // an empty pool: gathering alone
  if (n_dirs == 0 && n_ris == 0) return vec3<T>(T(0));
  estimator_state<T> state = make_estimator_state<T>(rng);
  estimate_ris_mis_pooled_range(gp, view, distribution, pool, pool_size, state, 0, n_dirs > n_ris ? n_dirs : n_ris,
                                n_dirs, n_ris, n_candidates, tracer, visibility, depth_tolerance, vmode);
  rng = state.rng;
  return estimate_ris_mis_finish(state);
}

}  // namespace vplkit
