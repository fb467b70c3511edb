// SPDX-License-Identifier: MIT
// The GBG accumulators are unbiased for their per-texel quantities: the mean of the weights over
// independent seeds matches a deterministic quadrature of
//   Q_t = (1/|G|) sum_x  integral over the hemisphere of x of  1[first hit lit, in texel t] value
//         cos(theta) / pi  d omega
// (value = the accumulator's per-hit value), computed in spherical coordinates with no use of the
// cosine sampler. Holes are not filled (the fill is a deliberate bias).
#include <vplkit/builders/gbg_weights.hpp>

#include <synthetic_scene.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

using vplkit::vec3;

namespace {

constexpr double kPi = 3.14159265358979323846;

vplkit::gbg_params<double> params(vplkit::gbg_accumulator acc, int n_dirs, std::uint32_t seed) {
  vplkit::gbg_params<double> p;
  p.n_dirs = n_dirs;
  p.dmin = 0.1;
  p.depth_tolerance = 0.3;
  p.seed = seed;
  p.accumulator = acc;
  p.fill_holes = false;
  return p;
}

std::vector<double> quadrature(const vplkit_test::synthetic_scene<double>& s,
                               const vplkit::gbuffer_view<double>& gb,
                               const vplkit::dprsm_view<double>& view,
                               const vplkit::gbg_params<double>& p, int n_theta, int n_phi) {
  std::vector<double> q(std::size_t(view.texel_count()), 0.0);
  int G = 0;
  const double dt = 0.5 * kPi / n_theta, dp = 2 * kPi / n_phi;
  for (int pix = 0; pix < gb.pixel_count(); ++pix) {
    const vplkit::gather_point<double> g = gb.at(pix);
    if (!vplkit::gather_point_valid(g)) continue;
    ++G;
    const auto f = vplkit::make_orthonormal_basis(g.normal);
    for (int i = 0; i < n_theta; ++i) {
      const double th = (i + 0.5) * dt;
      const double w = std::cos(th) * std::sin(th) / kPi * dt * dp;
      for (int j = 0; j < n_phi; ++j) {
        const double ph = (j + 0.5) * dp;
        const vec3<double> dir = vplkit::to_world(
            f, vec3<double>(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)));
        const vplkit::ray_hit<double> h = s.trace(g.position, g.normal, dir);
        if (!h.hit) continue;
        const auto r = vplkit::dprsm_lookup(view, h.position, p.depth_tolerance);
        if (!r.lit || !vplkit::vpl_has_flux(view.vpl_at(r.texel))) continue;
        q[std::size_t(r.texel)] +=
            w * vplkit::gbg_hit_value(g, view, r, h, p.dmin, p.accumulator, p.depth_tolerance);
      }
    }
  }
  for (double& x : q) x /= G;
  return q;
}

}  // namespace

TEST_CASE("builders: GBG weights average to their per-texel integrals, both accumulators",
          "[builders][statistical]") {
  const vplkit_test::lit_room<double> room(6);
  // the scene's hand-placed gather points (lit, shadowed, near walls, next to the light, ...)
  vplkit_test::gbuffer_data<double> gb;
  gb.width = int(room.gps.size());
  gb.height = 1;
  for (const auto& n : room.gps) {
    gb.position.push_back(n.gp.position);
    gb.normal.push_back(n.gp.normal);
    gb.albedo.push_back(n.gp.albedo);
  }
  for (auto acc : {vplkit::gbg_accumulator::gathering, vplkit::gbg_accumulator::paper}) {
    INFO("accumulator " << (acc == vplkit::gbg_accumulator::paper ? "paper" : "gathering"));
    const std::vector<double> q = quadrature(room.scene, gb.view(), room.view, params(acc, 1, 0u), 384, 768);
    const int K = 48, n_dirs = 256;
    const std::size_t n = q.size();
    std::vector<double> mean(n, 0.0), m2(n, 0.0);
    for (int k = 0; k < K; ++k) {
      const std::vector<double> w = vplkit::build_gbg_weights(
          gb.view(), room.view, room.tracer, params(acc, n_dirs, std::uint32_t(1000 + k)));
      for (std::size_t t = 0; t < n; ++t) {
        mean[t] += w[t];
        m2[t] += w[t] * w[t];
      }
    }
    double qmax = 0, total_q = 0, total_mean = 0;
    for (std::size_t t = 0; t < n; ++t) {
      mean[t] /= K;
      m2[t] /= K;
      qmax = std::max(qmax, q[t]);
      total_q += q[t];
      total_mean += mean[t];
    }
    int tested = 0;
    for (std::size_t t = 0; t < n; ++t) {
      if (q[t] < 0.02 * qmax) continue;
      const double se = std::sqrt(std::max(0.0, m2[t] - mean[t] * mean[t]) / (K - 1));
      INFO("texel " << t << ": mean " << mean[t] << " quadrature " << q[t] << " se " << se);
      // 4.5 standard errors, plus the quadrature's own error along texel edges
      CHECK(std::abs(mean[t] - q[t]) <= 4.5 * se + 0.01 * q[t]);
      ++tested;
    }
    CHECK(tested > 10);
    CHECK(total_mean == Approx(total_q).epsilon(0.02));
  }
}
