// SPDX-License-Identifier: MIT
#pragma once
// Deterministic references for the estimator tests (not part of the library): midpoint-rule
// quadrature over the cosine-hemisphere primary sample square, and the exact expectations of the
// MIS estimators. All in double.
#include <synthetic_scene.hpp>

#include <vplkit/distribution/alias_table.hpp>
#include <vplkit/distribution/defensive_mixture.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/distribution/discrete_sample.hpp>
#include <vplkit/distribution/face_roulette.hpp>
#include <vplkit/estimators/gathering_estimator.hpp>
#include <vplkit/estimators/mis_estimator.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/sampling/cosine_hemisphere.hpp>
#include <vplkit/sampling/orthonormal_basis.hpp>
#include <vplkit/sampling/rng.hpp>
#include <vplkit/vpl/luminance.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <vector>

namespace vplkit_test {

// E_{omega ~ cos/pi}[g(local)] by the midpoint rule on an m x m grid of (u0, u1): the integral of
// g(omega) cos/pi over the hemisphere (g = f/p1 gives int f domega).
template <class G>
inline vec3<double> cosine_quadrature(const vplkit::gather_point<double>& gp, int m, G&& g) {
  const vplkit::orthonormal_basis<double> frame = vplkit::make_orthonormal_basis(gp.normal);
  vec3<double> sum(0.0);
  for (int j = 0; j < m; ++j) {
    vec3<double> row(0.0);
    for (int i = 0; i < m; ++i) {
      const vplkit::vec2<double> u((i + 0.5) / m, (j + 0.5) / m);
      row += g(frame, vplkit::sample_cosine_hemisphere(u));
    }
    sum += row;
  }
  return sum / (double(m) * double(m));
}

// The estimand of estimate_gathering (exact tracer, DPRSM lookup): int (rho/pi) L_o cos domega.
inline vec3<double> gathering_integral(const synthetic_scene<double>& s, const vplkit::dprsm_view<double>& view,
                                       const vplkit::gather_point<double>& gp, double tol, int m) {
  const exact_tracer<double> tracer{&s};
  return cosine_quadrature(gp, m, [&](const vplkit::orthonormal_basis<double>& f, vec3<double> local) {
    return vplkit::gathering_sample(gp, view, f, local, tracer, tol);
  });
}

// The gathering integral with the shadow-ray lit test (vplkit::with_light_visibility): the DPRSM
// gives each hit only its texel's albedo.
inline vec3<double> gathering_integral_shadow_ray(const synthetic_scene<double>& s,
                                                  const vplkit::dprsm_view<double>& view,
                                                  const vplkit::gather_point<double>& gp, int m) {
  const auto tracer = vplkit::with_light_visibility(exact_tracer<double>{&s}, exact_visibility<double>{&s});
  return cosine_quadrature(gp, m, [&](const vplkit::orthonormal_basis<double>& f, vec3<double> local) {
    return vplkit::gathering_sample(gp, view, f, local, tracer, 0.0);
  });
}

// The physical one-bounce integral with exact shadow rays and the true normal / albedo at the hit
// (no DPRSM at all): what the DPRSM-based integral approximates.
inline vec3<double> physical_integral(const synthetic_scene<double>& s, const vplkit::gather_point<double>& gp, int m) {
  return cosine_quadrature(gp, m, [&](const vplkit::orthonormal_basis<double>& f, vec3<double> local) {
    if (!(local.z > 0.0)) return vec3<double>(0.0);
    const vec3<double> x = gp.position + synthetic_scene<double>::surface_epsilon() * f.n;
    const scene_hit<double> h = s.intersect(x, vplkit::to_world(f, local));
    if (!h.hit || glm::dot(h.normal, gp.position - h.position) <= 0.0 || !s.lit(h.position, h.normal))
      return vec3<double>(0.0);
    return gp.albedo * vplkit::reflected_radiance(s.light.position, s.light.intensity, h.position, h.normal, h.albedo);
  });
}

// A distribution that always "draws" index t with the pmf of the wrapped one: evaluates one
// estimator sample at a chosen texel.
template <class Distribution>
struct single_index_distribution {
  const Distribution* dist;
  std::size_t index;
  vplkit::discrete_sample<double> sample(double) const { return {index, double(dist->pmf(index))}; }
  double pmf(std::size_t i) const { return double(dist->pmf(i)); }
};

// Exact expectation of estimate_mis (either mode) with the exact tracer and visibility:
// n_dirs E_{p1}[gathering sample] + n_vpls sum_t pmf(t) [VPL sample at t], divided by n_dirs for
// as_published. The gathering part by quadrature (m x m), the VPL part exactly. n_vpls is the
// count the balance weights take: estimate_ris_mis's is ris_mis_vpl_samples(n_ris, M), not always
// an integer.
template <class Distribution>
inline vec3<double> mis_expectation(const synthetic_scene<double>& s, const vplkit::dprsm_view<double>& view,
                                    const Distribution& dist, const vplkit::gather_point<double>& gp, int n_dirs,
                                    double n_vpls, double tol, vplkit::mis_mode mode, int m) {
  const exact_tracer<double> tracer{&s};
  const exact_visibility<double> vis{&s};
  const double n1 = n_dirs, n2 = n_vpls;
  const vec3<double> g = cosine_quadrature(gp, m, [&](const vplkit::orthonormal_basis<double>& f, vec3<double> local) {
    return vplkit::mis_gathering_sample(gp, view, dist, f, local, tracer, tol, n1, n2, mode);
  });
  // The VPL sample at t: draw it with a u inside t's CDF bin -> evaluate directly instead.
  vec3<double> v(0.0);
  for (int t = 0; t < view.texel_count(); ++t) {
    const double p = dist.pmf(std::size_t(t));
    if (!(p > 0.0)) continue;
    const single_index_distribution<Distribution> one{&dist, std::size_t(t)};
    v += p * vplkit::mis_vpl_sample(gp, view, one, 0.5, vis, n1, n2, mode);
  }
  const vec3<double> e = n1 * g + n2 * v;
  return mode == vplkit::mis_mode::as_published ? e / (n_dirs > 0 ? n1 : n2) : e;
}

// ---- repeated independent estimates -------------------------------------------------------------

// Mean and standard error of the mean (per channel and of the luminance) of K estimates, each
// drawn with its own stream make_counter_rng(seed, k).
struct run_stats {
  vec3<double> mean{0.0};
  vec3<double> sem{0.0};
  double lum_mean = 0.0;
  double lum_sem = 0.0;
  double lum_var = 0.0;  // variance of one estimate's luminance
  int runs = 0;
};

// |a - b| within k combined standard errors on every channel (two independent estimates).
inline bool runs_agree(const run_stats& a, const run_stats& b, double k) {
  for (int c = 0; c < 3; ++c)
    if (!(std::abs(a.mean[c] - b.mean[c]) <= k * std::sqrt(a.sem[c] * a.sem[c] + b.sem[c] * b.sem[c]))) return false;
  return true;
}

template <class F>
inline run_stats repeat_estimates(int runs, std::uint32_t seed, F&& estimate) {
  vec3<double> s1(0.0), s2(0.0);
  double l1 = 0.0, l2 = 0.0;
  for (int k = 0; k < runs; ++k) {
    vplkit::counter_rng rng = vplkit::make_counter_rng(seed, std::uint32_t(k));
    const vec3<double> e(estimate(rng));
    s1 += e;
    s2 += e * e;
    const double l = vplkit::luminance(e);
    l1 += l;
    l2 += l * l;
  }
  run_stats r;
  const double n = runs;
  r.runs = runs;
  r.mean = s1 / n;
  const vec3<double> var = glm::max((s2 / n - r.mean * r.mean) * (n / (n - 1.0)), vec3<double>(0.0));
  r.sem = glm::sqrt(var / n);
  r.lum_mean = l1 / n;
  r.lum_var = std::max(0.0, (l2 / n - r.lum_mean * r.lum_mean) * (n / (n - 1.0)));
  r.lum_sem = std::sqrt(r.lum_var / n);
  return r;
}

// |mean - ref| <= k sigma_mean + slack, on every channel (slack: the reference's own accuracy).
inline bool within_sigma(const run_stats& r, vec3<double> ref, double k, vec3<double> slack) {
  for (int c = 0; c < 3; ++c)
    if (!(std::abs(r.mean[c] - ref[c]) <= k * r.sem[c] + slack[c])) return false;
  return true;
}

// Largest |mean - ref| / sigma_mean over the channels (for the printed tables).
inline double z_score(const run_stats& r, vec3<double> ref) {
  double z = 0.0;
  for (int c = 0; c < 3; ++c) {
    const double d = std::abs(r.mean[c] - ref[c]);
    z = std::max(z, r.sem[c] > 0.0 ? d / r.sem[c] : (d > 0.0 ? 1e300 : 0.0));
  }
  return z;
}

// ---- CDF weights for the tests ----------------------------------------------------------------

// Importance weights in the spirit of the global builder: luminance of the unoccluded
// contribution (dmin 0.1) summed over `points`, plus floor * luminance(flux) so every texel with
// flux has p > 0 when floor > 0.
template <class T>
inline std::vector<T> importance_weights(const vplkit::dprsm_view<T>& view,
                                         const std::vector<vplkit::gather_point<T>>& points, T floor) {
  std::vector<T> w(std::size_t(view.texel_count()), T(0));
  for (int t = 0; t < view.texel_count(); ++t) {
    const vplkit::vpl<T> v = view.vpl_at(t);
    double a = 0.0;
    for (const auto& g : points)
      a += double(vplkit::luminance(vplkit::vpl_contribution(g.position, g.normal, g.albedo, v, T(0.1))));
    w[std::size_t(t)] = T(a) + floor * vplkit::luminance(v.flux);
  }
  return w;
}

// 1 on every valid texel: the defensive fallback.
template <class T>
inline std::vector<T> uniform_valid_weights(const vplkit::dprsm_view<T>& view) {
  std::vector<T> w(std::size_t(view.texel_count()), T(0));
  for (int t = 0; t < view.texel_count(); ++t) w[std::size_t(t)] = view.texel_valid(t) ? T(1) : T(0);
  return w;
}

template <class T>
inline std::vector<vplkit::gather_point<T>> plain_points(const std::vector<named_gather_point<T>>& named) {
  std::vector<vplkit::gather_point<T>> p;
  for (const auto& n : named) p.push_back(n.gp);
  return p;
}

// The four global distributions VPL sampling is tested with, over the same importance weights:
// discrete_cdf, alias_table, the defensive mixture (eps 0.1, uniform over the valid texels) and
// the face roulette (one CDF per paraboloid face).
template <class T>
struct vpl_sampling_distributions {
  vplkit::discrete_cdf<T> cdf;
  vplkit::alias_table<T> alias;
  vplkit::defensive_mixture<T> mix;
  vplkit::face_roulette<T> roulette;
  vpl_sampling_distributions(const std::vector<T>& weights, const vplkit::dprsm_view<T>& view)
      : cdf(weights), alias(weights),
        mix(vplkit::discrete_cdf<T>(weights), vplkit::discrete_cdf<T>(uniform_valid_weights(view)), T(0.1)),
        roulette(vplkit::discrete_cdf<T>(weights.data(), face_texels(view)),
                 vplkit::discrete_cdf<T>(weights.data() + face_texels(view), face_texels(view))) {}
  static std::size_t face_texels(const vplkit::dprsm_view<T>& view) {
    return std::size_t(view.resolution) * std::size_t(view.resolution);
  }
};

}  // namespace vplkit_test
