// SPDX-License-Identifier: MIT
#pragma once
// Unbiased spatial reuse of RIS reservoirs (docs/math.md section 13.2): a pixel q combines its own
// reservoir (the canonical one, c) with those of up to K neighbours j, picked at random in a
// square of the image around q and rejected where their surface differs (normal, distance from
// q's tangent plane). Each input i brings its sample y_i and its contribution weight W_i; the
// combination is generalized RIS (Lin et al. 2022): input i gets the resampling weight
//     w_i = m_i(y_i) p_hat_q(y_i) W_i,
// one is kept by a weighted reservoir, and the output has W = (sum_i w_i) / p_hat_q(y). It is
// unbiased for every choice of neighbours as long as the MIS weights m_i sum to 1 over the inputs
// that can produce a sample and vanish where input i cannot (p_hat_i = 0). The target has no
// visibility, so nothing but the target is re-evaluated at q: no ray is traced by the reuse. The
// sample is a texel and a jitter, the same at every pixel (the shift map is the identity).
//
// The target is a parameter (ris_combine_with, ris_spatial_reuse_with: a callable
// target(pixel, g, s), p_hat of the sample s at the gather point g of pixel `pixel`), so that any
// resampled estimator whose target a pixel can evaluate for any sample reuses this: --method ris
// (ris_combine, ris_spatial_reuse: ris_target, the unshadowed clamped contribution) and --method
// ris-mis (ris_mis_spatial_reuse.hpp: the MIS-weighted unclamped contribution h of
// ris_mis_estimator.hpp, with the pmf of the pixel's own candidate distribution).
//
// The MIS weights, with confidences M_i (candidates behind each input), M = M_c + sum_j M_j:
//  - pairwise (default; Bitterli 2022, Wyman et al. 2023, the defensive form with confidence
//    weights): the canonical competes with each neighbour in a pair, and keeps M_c / M for itself,
//        m_c(y) = M_c / M + sum_j (M_j / M) M_c p_hat_c(y) / (M_c p_hat_c(y) + (M - M_c) p_hat_j(y))
//        m_j(y) = (M_j / M) (M - M_c) p_hat_j(y) / ((M - M_c) p_hat_j(y) + M_c p_hat_c(y)).
//    For every y the terms sum to 1. Costs 2K target evaluations (p_hat_q at each neighbour's
//    sample, each neighbour's p_hat at the canonical sample; p_hat_j(y_j) is stored).
//  - balance (the generalized balance heuristic): m_i(y) = M_i p_hat_i(y) / sum_s M_s p_hat_s(y),
//    K (K + 1) target evaluations. Kept for comparison (docs/math.md says what each costs).
//
// Random numbers, in this order (the GLSL mirror follows it): the canonical's selection u, then per
// attempt a < K: u0, u1 (the neighbour's pixel) and its selection u: 1 + 3K numbers, also for
// rejected attempts. An invalid gather point consumes none and returns an empty reservoir.
#include <vplkit/core/gather_point.hpp>
#include <vplkit/core/unit_or_zero.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/distribution/weighted_reservoir.hpp>
#include <vplkit/estimators/ris_estimator.hpp>
#include <vplkit/estimators/ris_reservoir.hpp>
#include <vplkit/sampling/rng.hpp>
#include <vplkit/vpl/dprsm_patch.hpp>
#include <vplkit/vpl/dprsm_view.hpp>

#include <cmath>
#include <cstdint>
#include <limits>

namespace vplkit {

// The most neighbours one reuse takes (the GLSL mirror's VPLKIT_RIS_MAX_NEIGHBOURS).
inline constexpr int ris_max_neighbours = 16;

enum class ris_reuse_mis { pairwise, balance };

// How a pixel picks its neighbours.
template <class T>
struct ris_spatial_settings {
  int neighbours = 4;          // K attempts (at most ris_max_neighbours)
  int radius = 16;             // pixels: a neighbour lies in the (2 radius + 1)^2 square around q
  T min_normal_cos = T(0.9);   // reject where the geometric normals differ by more (25.8 degrees)
  T max_plane_slope = T(0.1);  // reject where |n_q . (x_j - x_q)| > this |x_j - x_q|
  ris_reuse_mis mis = ris_reuse_mis::pairwise;
};

// What a pixel offers its neighbours: its gather point and its reservoir (of its own candidates).
template <class T>
struct ris_neighbour {
  gather_point<T> gp{};
  ris_reservoir<T> reservoir{};
};

// The neighbour picked by (u0, u1) for the pixel `pixel` of a width x height image: uniform in the
// (2 radius + 1)^2 square around it (u0 across, u1 down; one product and a floor each, so the GPU
// picks the same pixel). -1 for the pixel itself, a pixel outside the image, radius <= 0.
template <class T>
inline int ris_neighbour_pixel(int pixel, int width, int height, int radius, T u0, T u1) {
  if (radius <= 0 || width <= 0 || height <= 0 || pixel < 0 || pixel >= width * height) return -1;
  const int side = 2 * radius + 1;
  const auto offset = [&](T u) {
    const T s = !(u >= T(0)) ? T(0) : u * T(side);  // NaN and negative: 0
    const int k = s < T(side) ? int(std::floor(s)) : side - 1;
    return k - radius;
  };
  const int dx = offset(u0), dy = offset(u1);
  const int x = pixel % width + dx, y = pixel / width + dy;
  if ((dx == 0 && dy == 0) || x < 0 || y < 0 || x >= width || y >= height) return -1;
  return y * width + x;
}

// Does the neighbour's surface resemble the receiver's? Both valid, the geometric normals within
// acos(min_normal_cos), and the neighbour near the receiver's tangent plane: |n_q . (x_j - x_q)| <=
// max_plane_slope |x_j - x_q| (the "depth difference" seen along the receiver's normal, which
// needs no camera: a neighbour across a depth edge lies far off the plane). Only variance depends
// on this test; the reuse is unbiased whatever it decides.
template <class T>
inline bool ris_neighbour_similar(const gather_point<T>& receiver, const gather_point<T>& neighbour, T min_normal_cos,
                                  T max_plane_slope) {
  if (!gather_point_valid(receiver) || !gather_point_valid(neighbour)) return false;
  const vec3<T> nq = unit_or_zero(receiver.normal), nj = unit_or_zero(neighbour.normal);
  if (!(glm::dot(nq, nj) >= min_normal_cos)) return false;
  const vec3<T> d = neighbour.position - receiver.position;
  return std::abs(glm::dot(nq, d)) <= max_plane_slope * std::sqrt(glm::dot(d, d));
}

namespace detail {

// a / (a + b) for a, b >= 0; 0 when both are 0.
template <class T>
inline T ris_pair_share(T a, T b) {
  const T s = a + b;
  return s > T(0) ? a / s : T(0);
}

}  // namespace detail

// The target of --method ris at any pixel: p_hat = ris_target of the sample's VPL (the pixel index
// is not used: the target depends on the gather point alone).
template <class T>
struct ris_unshadowed_target {
  const dprsm_view<T>* view = nullptr;
  T dmin = T(0);
  vpl_mode mode = vpl_mode::point;
  T depth_tolerance = std::numeric_limits<T>::infinity();
  T operator()(int, const gather_point<T>& g, const ris_sample<T>& s) const {
    return ris_target(g, ris_sample_vpl(*view, s, mode, depth_tolerance), dmin);
  }
};

// Combines the canonical reservoir of gp (the gather point of pixel `pixel`; its own candidates'
// reservoir, whose target is p_hat_q) with the reservoirs of the neighbours at
// neighbour_pixels[0 .. n) (at most ris_max_neighbours; load(pixel) -> ris_neighbour<T> gives each
// one's gather point and reservoir), with the MIS weights of `mis` and one selection number per
// input: u[0] the canonical's, u[1 + j] neighbour j's (offered in the order neighbours, then
// canonical). target(pixel, g, s) -> T is p_hat at the gather point g of pixel `pixel` of the
// sample s: >= 0 and finite (0 where not usable), and, at every pixel, the target that pixel's
// candidate pass stored in its reservoir (the stored targets are read, not recomputed). The
// output's target is p_hat_q of its sample and its confidence the inputs' sum.
template <class T, class Load, class Target>
inline ris_reservoir<T> ris_combine_with(const gather_point<T>& gp, int pixel, const ris_reservoir<T>& canonical,
                                         const int* neighbour_pixels, int n, const Load& load, const T* u,
                                         ris_reuse_mis mis, const Target& target) {
  ris_reservoir<T> out;
  if (!gather_point_valid(gp)) return out;
  if (n > ris_max_neighbours) n = ris_max_neighbours;
  if (n < 0) n = 0;
  const bool has_c = ris_reservoir_has_sample(canonical);
  const T m_c_conf = canonical.confidence;
  T m_sum = m_c_conf, m_n = T(0);
  for (int j = 0; j < n; ++j) m_n += load(neighbour_pixels[j]).reservoir.confidence;
  m_sum += m_n;
  if (!(m_sum > T(0))) return out;

  // One pass over the neighbours: each one's resampling weight goes into the reservoir at once,
  // while the canonical's MIS weight accumulates; the canonical is offered last (the order of the
  // offers does not change the probabilities), so nothing per neighbour is kept but the kept one's
  // target: no arrays, which a GPU would hold in local memory.
  weighted_reservoir<T> res;
  int kept = -1;  // -1: the canonical (or none yet); j: neighbour j
  T kept_target = T(0);
  T m_c = mis == ris_reuse_mis::pairwise ? m_c_conf / m_sum : T(0);
  T balance_c = m_c_conf * canonical.target;  // balance: sum_s M_s p_hat_s(y_c)
  for (int j = 0; j < n; ++j) {
    const int pj = neighbour_pixels[j];
    const ris_neighbour<T> nb = load(pj);
    const T m_j = nb.reservoir.confidence;
    const T p_j_at_c = has_c ? target(pj, nb.gp, canonical.kept) : T(0);  // p_hat_j(y_c)
    if (mis == ris_reuse_mis::pairwise)
      m_c += (m_j / m_sum) * detail::ris_pair_share(m_c_conf * canonical.target, m_n * p_j_at_c);
    else
      balance_c += m_j * p_j_at_c;
    if (!ris_reservoir_has_sample(nb.reservoir)) continue;
    const T target_q = target(pixel, gp, nb.reservoir.kept);  // p_hat_q(y_j)
    if (!(target_q > T(0))) continue;
    // w_j = m_j(y_j) p_hat_q(y_j) W_j with W_j = weight_sum_j / p_hat_j(y_j).
    T w = T(0);
    if (mis == ris_reuse_mis::pairwise) {
      const T share = detail::ris_pair_share(m_n * nb.reservoir.target, m_c_conf * target_q);
      w = (m_j / m_sum) * share * target_q * (nb.reservoir.weight_sum / nb.reservoir.target);
    } else {
      // sum_s M_s p_hat_s(y_j): the canonical's (at q), j's own (stored) and every other one's.
      T denominator = m_c_conf * target_q + m_j * nb.reservoir.target;
      for (int s = 0; s < n; ++s) {
        if (s == j) continue;
        const ris_neighbour<T> other = load(neighbour_pixels[s]);
        denominator += other.reservoir.confidence * target(neighbour_pixels[s], other.gp, nb.reservoir.kept);
      }
      // m_j p_hat_q W_j = M_j p_hat_j / denominator * p_hat_q * weight_sum_j / p_hat_j.
      w = denominator > T(0) ? m_j * target_q * nb.reservoir.weight_sum / denominator : T(0);
    }
    if (reservoir_update(res, std::uint32_t(j + 1), w, u[j + 1])) {
      kept = j;
      kept_target = target_q;
    }
  }
  if (mis == ris_reuse_mis::balance)
    m_c = balance_c > T(0) ? m_c_conf * canonical.target / balance_c : T(0);
  const T w_c = has_c ? m_c * canonical.weight_sum : T(0);  // m_c p_hat_q(y_c) W_c
  if (reservoir_update(res, 0u, w_c, u[0])) kept = -1;
  out.confidence = m_sum;
  if (reservoir_empty_of(res)) return out;
  if (kept < 0) {
    out.kept = canonical.kept;
    out.target = canonical.target;
  } else {
    out.kept = load(neighbour_pixels[kept]).reservoir.kept;
    out.target = kept_target;
  }
  out.weight_sum = res.weight_sum;
  return out;
}

// ris_combine_with for --method ris's target (ris_unshadowed_target: ris_target at each gather point).
template <class T, class Load>
inline ris_reservoir<T> ris_combine(const gather_point<T>& gp, const dprsm_view<T>& view,
                                    const ris_reservoir<T>& canonical, const int* neighbour_pixels, int n,
                                    const Load& load, const T* u, ris_reuse_mis mis, T dmin,
                                    vpl_mode mode = vpl_mode::point,
                                    T depth_tolerance = std::numeric_limits<T>::infinity()) {
  return ris_combine_with(gp, -1, canonical, neighbour_pixels, n, load, u, mis,
                          ris_unshadowed_target<T>{&view, dmin, mode, depth_tolerance});
}

// Picks up to settings.neighbours neighbours of `pixel` (ris_neighbour_pixel, kept where
// ris_neighbour_similar) and combines their reservoirs with gp's canonical one (ris_combine_with,
// with the target `target`). load(pixel) -> ris_neighbour<T>: the neighbour's gather point and
// reservoir of its own candidates (the same pass's, not an output of this function). Random
// numbers: see the header.
template <class T, class Load, class Target>
inline ris_reservoir<T> ris_spatial_reuse_with(const gather_point<T>& gp, int pixel, int width, int height,
                                               const ris_reservoir<T>& canonical, const Load& load,
                                               const ris_spatial_settings<T>& settings, counter_rng& rng,
                                               const Target& target) {
  if (!gather_point_valid(gp)) return ris_reservoir<T>{};
  const int attempts = settings.neighbours < 0 ? 0
                       : settings.neighbours > ris_max_neighbours ? ris_max_neighbours
                                                                  : settings.neighbours;
  int pixels[ris_max_neighbours];
  T u[ris_max_neighbours + 1];
  int n = 0;
  u[0] = rng_next_unit<T>(rng);
  for (int a = 0; a < attempts; ++a) {
    const T u0 = rng_next_unit<T>(rng);
    const T u1 = rng_next_unit<T>(rng);
    const T us = rng_next_unit<T>(rng);
    const int p = ris_neighbour_pixel(pixel, width, height, settings.radius, u0, u1);
    if (p < 0 || !ris_neighbour_similar(gp, load(p).gp, settings.min_normal_cos, settings.max_plane_slope)) continue;
    pixels[n] = p;
    u[n + 1] = us;
    ++n;
  }
  return ris_combine_with(gp, pixel, canonical, pixels, n, load, u, settings.mis, target);
}

// ris_spatial_reuse_with for --method ris's target (ris_unshadowed_target).
template <class T, class Load>
inline ris_reservoir<T> ris_spatial_reuse(const gather_point<T>& gp, int pixel, int width, int height,
                                          const dprsm_view<T>& view, const ris_reservoir<T>& canonical,
                                          const Load& load, const ris_spatial_settings<T>& settings,
                                          counter_rng& rng, T dmin, vpl_mode mode = vpl_mode::point,
                                          T depth_tolerance = std::numeric_limits<T>::infinity()) {
  return ris_spatial_reuse_with(gp, pixel, width, height, canonical, load, settings, rng,
                                ris_unshadowed_target<T>{&view, dmin, mode, depth_tolerance});
}

}  // namespace vplkit
