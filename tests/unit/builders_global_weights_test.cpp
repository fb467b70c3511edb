// SPDX-License-Identifier: MIT
// Global (BRSM) weights: equal to an independent brute-force double loop, exactly 0 where no VPL
// is, background skipped, and the argument checks.
#include <vplkit/builders/gather_subset.hpp>
#include <vplkit/builders/global_weights.hpp>
#include <vplkit/core/error.hpp>

#include <synthetic_scene.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

using vplkit::vec3;

namespace {

constexpr double kPi = 3.14159265358979323846;

// The global weight of texel t written out from docs/math.md section 1-3.2 in double, sharing no
// code with the library except the texel layout.
double brute_force_weight(const vplkit::dprsm_view<double>& view,
                          const std::vector<vplkit::gather_point<double>>& pts, int t,
                          double dmin) {
  const int R = view.resolution;
  const int face_size = R * R;
  const int in_face = t % face_size;
  const int x = in_face % R, y = in_face / R;
  const double u = (x + 0.5) / R * 2 - 1, v = (y + 0.5) / R * 2 - 1;
  const double r2 = u * u + v * v;
  if (r2 > 1) return 0.0;
  const double omega = 4.0 / ((1 + r2) * (1 + r2)) * (2.0 / R) * (2.0 / R);
  const vec3<double> yt = view.position[t];
  const vec3<double> nt = glm::normalize(view.normal[t]);
  const vec3<double> rho_t = view.albedo[t];
  if (rho_t == vec3<double>(0)) return 0.0;
  const double cos_alpha = glm::dot(nt, glm::normalize(view.light.position - yt));
  if (cos_alpha <= 0) return 0.0;
  const vec3<double> flux = rho_t * view.light.intensity * omega;
  double sum = 0;
  for (const auto& g : pts) {
    const vec3<double> d = yt - g.position;
    const double dist2 = glm::dot(d, d);
    const vec3<double> w = d / std::sqrt(dist2);
    const double c2 = std::max(0.0, glm::dot(glm::normalize(g.normal), w));
    const double c1 = std::max(0.0, -glm::dot(nt, w));
    const vec3<double> L = g.albedo / kPi * flux * c1 * c2 / (kPi * std::max(dist2, dmin * dmin));
    sum += 0.299 * L.x + 0.587 * L.y + 0.114 * L.z;
  }
  return pts.empty() ? 0.0 : sum / double(pts.size());
}

template <class T>
std::vector<T> global_weights(const vplkit_test::gbuffer_data<T>& gb,
                              const vplkit_test::dprsm_data<T>& d, const std::vector<int>& subset,
                              T dmin) {
  return vplkit::build_global_weights(gb.view(), subset, d.view(), dmin);
}

}  // namespace

TEMPLATE_TEST_CASE("builders: global weights equal a brute-force double loop", "[builders]", float,
                   double) {
  using T = TestType;
  const vplkit_test::synthetic_scene<double> sd;
  const vplkit_test::synthetic_scene<T> s;
  const int R = 8;
  const auto dd = sd.make_dprsm(R);
  const auto d = s.make_dprsm(R);
  const auto gbd = sd.make_gbuffer(12, 10);
  const auto gb = s.make_gbuffer(12, 10);
  const std::vector<int> subset = vplkit::stratified_gather_subset(gb.view(), {0, 0, 12, 10}, 20, 5u);
  REQUIRE(subset.size() == 20);  // the closed room has no background
  std::vector<vplkit::gather_point<double>> pts;
  for (int p : subset) pts.push_back(gbd.view().at(p));

  for (double dmin : {0.0, 0.25}) {
    const std::vector<T> w = global_weights(gb, d, subset, T(dmin));
    REQUIRE(w.size() == std::size_t(2 * R * R));
    int nonzero = 0;
    for (int t = 0; t < 2 * R * R; ++t) {
      const double ref = brute_force_weight(dd.view(), pts, t, dmin);
      INFO("texel " << t << " dmin " << dmin);
      if (ref == 0.0) {
        REQUIRE(w[std::size_t(t)] == T(0));
      } else {
        ++nonzero;
        // float: the DPRSM itself was traced in float (positions differ by ~1e-6 relative)
        REQUIRE(double(w[std::size_t(t)]) ==
                Approx(ref).epsilon(std::is_same<T, float>::value ? 2e-4 : 1e-12));
      }
    }
    REQUIRE(nonzero > R * R);  // most valid texels of both faces see a lit surface
  }
}

TEST_CASE("builders: global weight of a texel is exactly 0 where no VPL is", "[builders]") {
  const vplkit_test::synthetic_scene<float> s;
  const int R = 16;
  const auto d = s.make_dprsm(R);
  const auto view = d.view();
  const auto gb = s.make_gbuffer(8, 8);
  std::vector<int> all;
  for (int p = 0; p < 64; ++p) all.push_back(p);
  const std::vector<float> w = vplkit::build_global_weights(gb.view(), all, view, 0.0f);
  int invalid = 0, no_flux_valid = 0, positive = 0;
  for (int t = 0; t < view.texel_count(); ++t) {
    const bool carries = vplkit::vpl_has_flux(view.vpl_at(t));
    if (!view.texel_valid(t)) {
      ++invalid;
      REQUIRE(w[std::size_t(t)] == 0.0f);
      REQUIRE(!std::signbit(w[std::size_t(t)]));
    } else if (!carries) {
      ++no_flux_valid;
      REQUIRE(w[std::size_t(t)] == 0.0f);
    } else {
      REQUIRE(w[std::size_t(t)] >= 0.0f);
      positive += w[std::size_t(t)] > 0.0f;
    }
  }
  REQUIRE(invalid > 0);
  REQUIRE(positive > R * R);
  // per-texel function agrees with the builder
  std::vector<vplkit::gather_point<float>> pts;
  for (int p : all) pts.push_back(gb.view().at(p));
  for (int t = 0; t < view.texel_count(); t += 7)
    REQUIRE(vplkit::global_weight_texel(view, t, pts.data(), int(pts.size()), 0.0f) ==
            w[std::size_t(t)]);
  (void)no_flux_valid;
}

TEST_CASE("builders: a texel seeing a surface from behind carries no VPL and gets 0",
          "[builders]") {
  // One texel on the front face made to see a surface facing away from the light.
  const vplkit_test::synthetic_scene<double> s;
  auto d = s.make_dprsm(8);
  const auto gb = s.make_gbuffer(6, 6);
  const int t = vplkit::texel_index(0, 4, 4, 8);
  REQUIRE(vplkit::vpl_has_flux(d.view().vpl_at(t)));
  d.normal[std::size_t(t)] = -d.normal[std::size_t(t)];
  REQUIRE(!vplkit::vpl_has_flux(d.view().vpl_at(t)));
  const std::vector<double> w = vplkit::build_global_weights(gb.view(), {0, 7, 14, 21}, d.view(), 0.0);
  REQUIRE(w[std::size_t(t)] == 0.0);
  REQUIRE(w[std::size_t(t + 1)] > 0.0);
}

TEST_CASE("builders: background pixels in a subset are skipped and not counted", "[builders]") {
  const vplkit_test::synthetic_scene<double> s;
  const auto d = s.make_dprsm(8);
  auto gb = s.make_gbuffer(6, 6);
  const std::vector<int> valid_only{3, 10, 20};
  const std::vector<double> a = vplkit::build_global_weights(gb.view(), valid_only, d.view(), 0.1);
  gb.normal[5] = vec3<double>(0);                                     // background
  gb.position[9] = vec3<double>(std::numeric_limits<double>::quiet_NaN());  // non-finite: background
  std::vector<double> b(a.size(), -1.0);
  const std::vector<int> mixed{3, 5, 10, 9, 20};
  const int used = vplkit::build_global_weights(gb.view(), mixed.data(), mixed.size(), d.view(),
                                                0.1, b.data(), b.size());
  REQUIRE(used == 3);
  REQUIRE(a == b);
}

TEST_CASE("builders: global builder rejects bad arguments", "[builders]") {
  const vplkit_test::synthetic_scene<double> s;
  const auto d = s.make_dprsm(4);
  const auto gb = s.make_gbuffer(4, 4);
  std::vector<double> w(std::size_t(d.view().texel_count()));
  const std::vector<int> sub{1, 2};
  using vplkit::build_global_weights;
  CHECK_THROWS_AS(build_global_weights(gb.view(), sub.data(), 2, d.view(), 0.0, w.data(), w.size() - 1),
                  vplkit::invalid_input);
  CHECK_THROWS_AS(build_global_weights(gb.view(), sub.data(), 2, d.view(), -1.0, w.data(), w.size()),
                  vplkit::invalid_input);
  CHECK_THROWS_AS(build_global_weights(gb.view(), sub.data(), 2, d.view(),
                                       std::numeric_limits<double>::quiet_NaN(), w.data(), w.size()),
                  vplkit::invalid_input);
  CHECK_THROWS_AS(build_global_weights(gb.view(), std::vector<int>{16}, d.view(), 0.0),
                  vplkit::invalid_input);
  CHECK_THROWS_AS(build_global_weights(gb.view(), std::vector<int>{-1}, d.view(), 0.0),
                  vplkit::invalid_input);
  CHECK_THROWS_AS(build_global_weights(gb.view(), sub.data(), 2, d.view(), 0.0,
                                       static_cast<double*>(nullptr), w.size()),
                  vplkit::invalid_input);
  auto bad = d.view();
  bad.resolution = 0;
  CHECK_THROWS_AS(build_global_weights(gb.view(), sub, bad, 0.0), vplkit::invalid_input);
  try {
    build_global_weights(gb.view(), sub.data(), 2, d.view(), 0.0, w.data(), 3);
    FAIL("no exception");
  } catch (const vplkit::invalid_input& e) {
    CHECK(std::string(e.what()).find("build_global_weights") != std::string::npos);
    CHECK(std::string(e.what()).find("32") != std::string::npos);  // names the expected size
  }
}
