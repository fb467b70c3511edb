// SPDX-License-Identifier: MIT
#pragma once
// Resampled VPL sampling as the VPL strategy of MIS with cosine gathering (docs/math.md,
// "Resampled importance sampling of VPLs", "RIS with gathering"). estimate_mis's solid_angle mode
// weighs n1 gathering directions (density p1 = cos(theta2)/pi) against n2 VPL samples from a
// distribution over the texels (density p2 = pmf d2^2 / (A cos(theta1)) at x) by the balance
// heuristic, w2 = n2 p2 / (n1 p1 + n2 p2), w1 = 1 - w2. Here the VPL samples are N RIS samples
// instead, each one kept of M candidates drawn from that same distribution, and the weights count
// each of them as c = max(1, M/2) samples of p2: n2 = c N (ris_mis_vpl_samples). A RIS sample of
// M candidates has, where its target is large, up to M times p2's density; weights that count it
// once give gathering the share of the integral that the candidates would take with less variance.
// Any c > 0 keeps the weights deterministic functions of the point with w1 + w2 = 1 everywhere, so
// c changes the variance only; M/2 was the best of the constants measured at M = 8-64 (docs/math.md,
// "The VPL strategy's share"). With M <= 2, c = 1: estimate_mis's weights.
//   F = sum_{j<n1} f(X_j) / (n1 p1 + n2 p2)                       (gathering: mis_gathering_sample)
//     + (1/N) sum_{k<N} h(Y_k) V(x, Y_k) W_k                       (RIS with the target lum(h))
// with, over the sample space of a texel t and its jitter xi (counting measure times the unit
// square, where the distribution's draw has density pmf(t)),
//   h(t, xi) = n2 pmf(t) f(y) / (n1 p1(y) + n2 p2(y))   = w2(y) f(y) / (p2(y) / pmf(t)),
// y the texel's point (vpl_mode::point) or its jittered patch point (vpl_mode::patch). Since
// E_{t ~ pmf, xi}[h / pmf] is the integral of w2 f over the directions the VPL strategy reaches, and
// RIS's contribution weight W makes E[g(Y) W] = that sum for every g that vanishes where the target
// does, the second line estimates the integral of w2 f and the first that of w1 f: F is unbiased
// for the unclamped one-bounce integral, as estimate_mis is. No dmin clamp: near x, p2 grows as d2^2
// and h stays bounded (gathering takes the near field), so the target has no 1/d2^2 spike and the
// estimator needs no clamp compensation.
//
// The target is lum(h) without visibility: the candidates go where VPL sampling beats gathering,
// weighed by their unshadowed contribution there. With n1 = 0 it is RIS of the unclamped patch
// contribution (h = pmf f / p2), with n2 = 0 plain cosine gathering. The parts of patches whose
// points move to the texel centre (dprsm_patch.hpp) and hits in front of their texel's surface belong
// to gathering alone when n1 > 0, as in estimate_mis: h is 0 at such points (the VPL strategy never
// draws a point in front of its texel).
//
// Random numbers (the GLSL mirror follows them): step j < max(n1, N) draws, if j < N, the M
// candidates of one reservoir (per candidate u, with vpl_mode::patch u0 and u1, then the selection
// u: ris_estimator.hpp's layout), then, if j < n1, u0 and u1 for the direction. n_candidates <= 0
// counts as N = 0. An invalid gather point gives 0 and draws nothing; never NaN or Inf.
#include <vplkit/core/gather_point.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/distribution/weighted_reservoir.hpp>
#include <vplkit/estimators/estimator_state.hpp>
#include <vplkit/estimators/mis_estimator.hpp>
#include <vplkit/estimators/ris_reservoir.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/sampling/cosine_hemisphere.hpp>
#include <vplkit/sampling/orthonormal_basis.hpp>
#include <vplkit/sampling/rng.hpp>
#include <vplkit/vpl/dprsm_patch.hpp>
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/luminance.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <cstddef>
#include <cstdint>

namespace vplkit {

// n2 of the balance weights for n_ris RIS samples of n_candidates candidates each: c n_ris with
// c = max(1, M/2) (the header). 0 where either count is not positive. Exact in T for the counts
// vplrender takes (products of integers and 1/2 below 2^24); the GLSL mirror makes the same bits.
template <class T>
inline T ris_mis_vpl_samples(int n_ris, int n_candidates) {
  if (n_ris <= 0 || n_candidates <= 0) return T(0);
  return T(n_ris) * (T(n_candidates > 2 ? n_candidates : 2) * T(0.5));
}

// h(t, xi) of the header without visibility, for the sample s of a texel drawn with probability
// pmf; v receives the point it stands for (for the visibility query). 0 (and v without flux) where
// the sample is empty or outside the view, pmf is not positive, the point cannot light x, or (n1 > 0)
// the patch moved the point to the texel centre. rx = make_mis_receiver(gp), made once per gather
// point for all its candidates; a patch point's unit normal comes from its texel's plane record
// (dprsm_view::plane_at: unit_or_zero(n_t) wherever the point has flux). The same bits as
// normalising both per candidate.
template <class T>
inline vec3<T> ris_mis_unshadowed(const gather_point<T>& gp, const mis_receiver<T>& rx, const dprsm_view<T>& view,
                                  const ris_sample<T>& s, T pmf, T n1, T n2, vpl_mode mode, T depth_tolerance,
                                  vpl<T>& v) {
  v = vpl<T>{vec3<T>(T(0)), vec3<T>(T(0)), vec3<T>(T(0))};
  if (!(pmf > T(0)) || !(n2 > T(0)) || s.texel < 0 || s.texel >= view.texel_count()) return vec3<T>(T(0));
  T area;
  vec3<T> n_v;
  if (mode == vpl_mode::patch) {
    const dprsm_patch_sample<T> p = dprsm_patch_vpl(view, s.texel, s.xi, depth_tolerance);
    if (p.at_centre && n1 > T(0)) return vec3<T>(T(0));
    v = p.point;
    if (!vpl_has_flux(v)) return vec3<T>(T(0));
    // A point with flux has a plane (height != 0), whose normal is unit_or_zero(n_t).
    n_v = view.plane_at(s.texel).normal;
    area = vpl_patch_area(p.solid_angle, p.distance, p.cos_alpha);
  } else {
    v = view.vpl_at(s.texel);
    n_v = unit_or_zero(v.normal);
    area = mis_texel_patch_area(view, s.texel);
  }
  return estimator_finite_or_zero(mis_vpl_unshadowed_unit(gp, rx, view, s.texel, v, n_v, pmf, area, n1, n2) *
                                  (n2 * pmf));
}

template <class T>
inline vec3<T> ris_mis_unshadowed(const gather_point<T>& gp, const dprsm_view<T>& view, const ris_sample<T>& s,
                                  T pmf, T n1, T n2, vpl_mode mode, T depth_tolerance, vpl<T>& v) {
  return ris_mis_unshadowed(gp, make_mis_receiver(gp), view, s, pmf, n1, n2, mode, depth_tolerance, v);
}

// A candidate's draw: its sample (texel -1 where the draw is empty or its index lies outside the
// view) and the pmf it was drawn with (0 then).
template <class T>
struct ris_mis_draw {
  ris_sample<T> s{};
  T pmf = T(0);
};

// The first half of a candidate: samples the distribution with u; xi is the jitter (u0, u1 with
// vpl_mode::patch, else 0).
template <class T, class Distribution>
inline ris_mis_draw<T> ris_mis_draw_candidate(const dprsm_view<T>& view, const Distribution& distribution, T u,
                                              vec2<T> xi) {
  ris_mis_draw<T> c;
  c.s.xi = xi;
  const auto d = distribution.sample(u);
  const T pmf = estimator_pmf(T(d.pmf));
  if (!(pmf > T(0)) || d.index >= std::size_t(view.texel_count())) return c;
  c.s.texel = int(d.index);
  c.pmf = pmf;
  return c;
}

// What the shade of a reservoir needs of its kept sample, made while the candidate was weighed: h
// (RGB) and the point's position and normal for the visibility query. ris_mis_shade would compute
// the same h again (the draw's pmf is the distribution's pmf(texel), bit for bit), which at M = 2
// is a third of a step's evaluations.
template <class T>
struct ris_mis_kept {
  vec3<T> h{T(0)};
  vec3<T> position{T(0)};
  vec3<T> normal{T(0)};
};

// The second half: sets target = lum(h) and returns the resampling weight target / pmf (0 where
// the target is 0 or the draw is empty; a weight that overflows is not usable and the reservoir
// skips it). rx as in ris_mis_unshadowed. kept receives h and the point (h 0 where the weight is).
template <class T>
inline T ris_mis_weigh_candidate(const gather_point<T>& gp, const mis_receiver<T>& rx, const dprsm_view<T>& view,
                                 const ris_mis_draw<T>& c, T n1, T n2, vpl_mode mode, T depth_tolerance, T& target,
                                 ris_mis_kept<T>& kept) {
  target = T(0);
  kept = ris_mis_kept<T>{};
  if (c.s.texel < 0) return T(0);
  vpl<T> v;
  const vec3<T> h = ris_mis_unshadowed(gp, rx, view, c.s, c.pmf, n1, n2, mode, depth_tolerance, v);
  const T p = luminance(h);
  if (!reservoir_weight_usable(p)) return T(0);
  target = p;
  kept = ris_mis_kept<T>{h, v.position, v.normal};
  return p / c.pmf;
}

template <class T>
inline T ris_mis_weigh_candidate(const gather_point<T>& gp, const mis_receiver<T>& rx, const dprsm_view<T>& view,
                                 const ris_mis_draw<T>& c, T n1, T n2, vpl_mode mode, T depth_tolerance, T& target) {
  ris_mis_kept<T> kept;
  return ris_mis_weigh_candidate(gp, rx, view, c, n1, n2, mode, depth_tolerance, target, kept);
}

// One candidate (the draw, then its weight): sets its sample s and its target lum(h), and returns
// its resampling weight target / pmf.
template <class T, class Distribution>
inline T ris_mis_candidate(const gather_point<T>& gp, const mis_receiver<T>& rx, const dprsm_view<T>& view,
                           const Distribution& distribution, counter_rng& rng, T n1, T n2, vpl_mode mode,
                           T depth_tolerance, ris_sample<T>& s, T& target) {
  const T u = rng_next_unit<T>(rng);
  vec2<T> xi(T(0));
  if (mode == vpl_mode::patch) {
    xi.x = rng_next_unit<T>(rng);
    xi.y = rng_next_unit<T>(rng);
  }
  const ris_mis_draw<T> c = ris_mis_draw_candidate(view, distribution, u, xi);
  s = c.s;
  return ris_mis_weigh_candidate(gp, rx, view, c, n1, n2, mode, depth_tolerance, target);
}

template <class T, class Distribution>
inline T ris_mis_candidate(const gather_point<T>& gp, const dprsm_view<T>& view, const Distribution& distribution,
                           counter_rng& rng, T n1, T n2, vpl_mode mode, T depth_tolerance, ris_sample<T>& s,
                           T& target) {
  return ris_mis_candidate(gp, make_mis_receiver(gp), view, distribution, rng, n1, n2, mode, depth_tolerance, s,
                           target);
}

// Candidates drawn ahead of their evaluation in ris_mis_resample.
inline constexpr int ris_mis_draw_batch = 8;

// One reservoir of n_candidates candidates with the target lum(h) (ris_resample's layout and
// normalisation: weight_sum = (1/M) sum w_i, confidence M), and in `kept` the kept sample's h and
// point (ris_mis_shade_kept). Empty for an invalid gather point,
// n_candidates <= 0 or n2 <= 0 (no numbers drawn then). The candidates go in batches of
// ris_mis_draw_batch: first each one's numbers (u, the jitter, then its selection u: the layout of
// the one-at-a-time loop, which the GLSL mirror runs), with the distribution's first memory
// prefetched (distribution_prefetch), then each one's draw, with its texel's data prefetched, then
// their weights and reservoir updates in order. The same numbers, samples and updates as one
// candidate at a time, so the same reservoir; the texels' memory latencies overlap.
template <class T, class Distribution>
inline ris_reservoir<T> ris_mis_resample(const gather_point<T>& gp, const dprsm_view<T>& view,
                                         const Distribution& distribution, counter_rng& rng, int n_candidates, T n1,
                                         T n2, vpl_mode mode, T depth_tolerance, ris_mis_kept<T>& kept) {
  ris_reservoir<T> r;
  kept = ris_mis_kept<T>{};
  if (!gather_point_valid(gp) || n_candidates <= 0 || !(n2 > T(0))) return r;
  weighted_reservoir<T> res;
  const mis_receiver<T> rx = make_mis_receiver(gp);
  for (int i0 = 0; i0 < n_candidates; i0 += ris_mis_draw_batch) {
    const int n = n_candidates - i0 < ris_mis_draw_batch ? n_candidates - i0 : ris_mis_draw_batch;
    ris_mis_draw<T> c[ris_mis_draw_batch];
    T u[ris_mis_draw_batch], u_keep[ris_mis_draw_batch];
    vec2<T> xi[ris_mis_draw_batch];
    for (int k = 0; k < n; ++k) {
      u[k] = rng_next_unit<T>(rng);
      xi[k] = vec2<T>(T(0));
      if (mode == vpl_mode::patch) {
        xi[k].x = rng_next_unit<T>(rng);
        xi[k].y = rng_next_unit<T>(rng);
      }
      u_keep[k] = rng_next_unit<T>(rng);
      distribution_prefetch(distribution, u[k]);
    }
    for (int k = 0; k < n; ++k) {
      c[k] = ris_mis_draw_candidate(view, distribution, u[k], xi[k]);
      if (c[k].s.texel >= 0) dprsm_patch_prefetch(view, c[k].s.texel);
    }
    for (int k = 0; k < n; ++k) {
      T target;
      ris_mis_kept<T> made;
      const T w = ris_mis_weigh_candidate(gp, rx, view, c[k], n1, n2, mode, depth_tolerance, target, made);
      if (reservoir_update(res, std::uint32_t(i0 + k), w, u_keep[k])) {
        r.kept = c[k].s;
        r.target = target;
        kept = made;
      }
    }
  }
  const T m = T(n_candidates);
  r.confidence = m;
  if (!reservoir_empty_of(res)) r.weight_sum = res.weight_sum / m;
  return r;
}

template <class T, class Distribution>
inline ris_reservoir<T> ris_mis_resample(const gather_point<T>& gp, const dprsm_view<T>& view,
                                         const Distribution& distribution, counter_rng& rng, int n_candidates, T n1,
                                         T n2, vpl_mode mode, T depth_tolerance) {
  ris_mis_kept<T> kept;
  return ris_mis_resample(gp, view, distribution, rng, n_candidates, n1, n2, mode, depth_tolerance, kept);
}

// h(y) V(x, y) W for the reservoir's sample y, W = weight_sum / target: one RIS estimate of the
// integral of w2 f (V queried only where h is not 0). h uses distribution.pmf(texel), the
// distribution the candidates came from. 0 for an invalid gather point or an empty reservoir.
template <class T, class Distribution, class Visibility>
inline vec3<T> ris_mis_shade(const gather_point<T>& gp, const dprsm_view<T>& view, const Distribution& distribution,
                             const ris_reservoir<T>& r, const Visibility& visibility, T n1, T n2, vpl_mode mode,
                             T depth_tolerance) {
  if (!gather_point_valid(gp) || !ris_reservoir_has_sample(r)) return vec3<T>(T(0));
  if (r.kept.texel >= view.texel_count()) return vec3<T>(T(0));
  const T pmf = estimator_pmf(T(distribution.pmf(std::size_t(r.kept.texel))));
  vpl<T> v;
  const vec3<T> h = ris_mis_unshadowed(gp, view, r.kept, pmf, n1, n2, mode, depth_tolerance, v);
  if (!(h.x > T(0) || h.y > T(0) || h.z > T(0))) return vec3<T>(T(0));
  if (!visibility(gp.position, gp.normal, v.position, v.normal)) return vec3<T>(T(0));
  return estimator_finite_or_zero(h * (r.weight_sum / r.target));
}

// ris_mis_shade for the reservoir that ris_mis_resample made at gp, from the h and point it kept:
// the same value bit for bit, without evaluating h again. Not for a reservoir after spatial reuse
// (its sample may be a neighbour's, whose h at gp nobody made): ris_mis_shade.
template <class T, class Visibility>
inline vec3<T> ris_mis_shade_kept(const gather_point<T>& gp, const ris_reservoir<T>& r, const ris_mis_kept<T>& kept,
                                  const Visibility& visibility) {
  if (!gather_point_valid(gp) || !ris_reservoir_has_sample(r)) return vec3<T>(T(0));
  const vec3<T> h = kept.h;
  if (!(h.x > T(0) || h.y > T(0) || h.z > T(0))) return vec3<T>(T(0));
  if (!visibility(gp.position, gp.normal, kept.position, kept.normal)) return vec3<T>(T(0));
  return estimator_finite_or_zero(h * (r.weight_sum / r.target));
}

// Steps [begin, end) of estimate_ris_mis (estimator_state.hpp); the steps run to
// max(n_dirs, n_ris). Negative counts count as 0; n_candidates <= 0 makes n_ris 0. Both strategies'
// weights take n2 = ris_mis_vpl_samples(n_ris, n_candidates); each RIS value is divided by n_ris.
template <class T, class Distribution, class Tracer, class Visibility>
inline void estimate_ris_mis_range(const gather_point<T>& gp, const dprsm_view<T>& view,
                                   const Distribution& distribution, estimator_state<T>& state, int begin, int end,
                                   int n_dirs, int n_ris, int n_candidates, const Tracer& tracer,
                                   const Visibility& visibility, T depth_tolerance,
                                   vpl_mode vmode = vpl_mode::point) {
  if (!gather_point_valid(gp)) return;
  if (n_dirs < 0) n_dirs = 0;
  if (n_ris < 0 || n_candidates <= 0) n_ris = 0;
  const T n1 = T(n_dirs), n2 = ris_mis_vpl_samples<T>(n_ris, n_candidates);
  const orthonormal_basis<T> frame = make_orthonormal_basis(gather_point_shading_normal(gp));
  for (int j = begin; j < end; ++j) {
    if (j < n_ris) {
      ris_mis_kept<T> kept;
      const ris_reservoir<T> r =
          ris_mis_resample(gp, view, distribution, state.rng, n_candidates, n1, n2, vmode, depth_tolerance, kept);
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

// The 1/n_i are inside the terms (as estimate_mis_finish's solid_angle mode).
template <class T>
inline vec3<T> estimate_ris_mis_finish(const estimator_state<T>& state) {
  return state.sum;
}

// F of the header at gp: n_dirs gathering directions and n_ris RIS samples of n_candidates
// candidates each from `distribution`; n_dirs + n_ris visibility queries (a direction's is its
// gathering ray), n_ris n_candidates candidate evaluations.
template <class T, class Distribution, class Tracer, class Visibility>
inline vec3<T> estimate_ris_mis(const gather_point<T>& gp, const dprsm_view<T>& view, const Distribution& distribution,
                                counter_rng& rng, int n_dirs, int n_ris, int n_candidates, const Tracer& tracer,
                                const Visibility& visibility, T depth_tolerance, vpl_mode vmode = vpl_mode::point) {
  if (!gather_point_valid(gp)) return vec3<T>(T(0));
  if (n_dirs < 0) n_dirs = 0;
  if (n_ris < 0 || n_candidates <= 0) n_ris = 0;
  if (n_dirs == 0 && n_ris == 0) return vec3<T>(T(0));
  estimator_state<T> state = make_estimator_state<T>(rng);
  estimate_ris_mis_range(gp, view, distribution, state, 0, n_dirs > n_ris ? n_dirs : n_ris, n_dirs, n_ris,
                         n_candidates, tracer, visibility, depth_tolerance, vmode);
  rng = state.rng;
  return estimate_ris_mis_finish(state);
}

}  // namespace vplkit
