// SPDX-License-Identifier: MIT
#include <vplkit/core/error.hpp>
#include <vplkit/paraboloid/texel_grid.hpp>
#include <vplkit/vpl/direct_light.hpp>
#include <vplkit/vpl/dprsm_lookup.hpp>
#include <vplkit/vpl/dprsm_raycast.hpp>
#include <vplkit/vpl/dprsm_view.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <vector>

using vplkit::vec3;

namespace {

// Infinite plane z = -1 (normal +z), albedo (0.5, 0.25, 1).
template <class T>
std::optional<vplkit::dprsm_hit<T>> trace_floor(vec3<T> o, vec3<T> d) {
  if (!(d.z < T(0))) return std::nullopt;
  const T t = (T(-1) - o.z) / d.z;
  if (!(t > T(0))) return std::nullopt;
  return vplkit::dprsm_hit<T>{o + t * d, vec3<T>(0, 0, 1), vec3<T>(T(0.5), T(0.25), T(1))};
}

template <class T>
bool message_contains(const vplkit::dprsm_view<T>& view, const std::string& needle) {
  try {
    view.validate();
  } catch (const vplkit::invalid_input& e) {
    INFO(e.what());
    return std::string(e.what()).find(needle) != std::string::npos;
  }
  return false;
}

}  // namespace

TEMPLATE_TEST_CASE("dprsm: a floor under a downward-looking light fills the front face", "[vpl]",
                   float, double) {
  using T = TestType;
  const int R = 32;
  const auto light = vplkit::make_point_light(vec3<T>(T(0.3), T(-0.2), T(2)), vec3<T>(10, 20, 30),
                                              vec3<T>(0, 0, -1));
  std::vector<vec3<T>> P, N, A;
  const vplkit::dprsm_view<T> view = vplkit::render_dprsm(light, R, trace_floor<T>, P, N, A);
  REQUIRE(view.texel_count() == 2 * R * R);
  REQUIRE(P.size() == std::size_t(2 * R * R));
  int hits = 0;
  for (int i = 0; i < view.texel_count(); ++i) {
    const vplkit::vpl<T> v = view.vpl_at(i);
    const int face = vplkit::texel_face(i, R);
    if (!view.texel_valid(i) || face == vplkit::paraboloid_back) {
      REQUIRE(v.flux == vec3<T>(0));  // invalid texel, or the back face sees the empty sky
      if (!view.texel_valid(i)) REQUIRE(A[std::size_t(i)] == vec3<T>(0));
      continue;
    }
    // every valid front texel looks below the horizon and hits the floor
    ++hits;
    REQUIRE(v.position.z == Approx(-1.0));
    REQUIRE(v.normal == vec3<T>(0, 0, 1));
    const T omega = view.solid_angle(i);
    REQUIRE(v.flux.x == Approx(0.5 * 10 * double(omega)));
    REQUIRE(v.flux.z == Approx(1.0 * 30 * double(omega)));
    // projecting the hit back into the DPRSM finds the same texel
    REQUIRE(view.texel_of_point(v.position) == i);
  }
  const double expected = 3.14159265358979323846 / 4 * R * R;
  CHECK(double(hits) == Approx(expected).epsilon(0.05));
}

TEMPLATE_TEST_CASE("dprsm: texels that see a surface from behind carry no flux", "[vpl]", float,
                   double) {
  using T = TestType;
  const int R = 8;
  const auto light = vplkit::make_point_light(vec3<T>(0, 0, 2), vec3<T>(1), vec3<T>(0, 0, -1));
  std::vector<vec3<T>> P, N, A;
  // the floor's normal points down, away from the light above it
  auto flipped = [](vec3<T> o, vec3<T> d) {
    auto h = trace_floor<T>(o, d);
    if (h) h->normal = -h->normal;
    return h;
  };
  const auto view = vplkit::render_dprsm(light, R, flipped, P, N, A);
  int seen = 0;
  for (int i = 0; i < view.texel_count(); ++i) {
    REQUIRE(view.vpl_at(i).flux == vec3<T>(0));
    seen += A[std::size_t(i)] != vec3<T>(0) ? 1 : 0;
  }
  CHECK(seen > 0);
}

TEMPLATE_TEST_CASE("dprsm: validate names the first bad texel", "[vpl]", float, double) {
  using T = TestType;
  const int R = 4;
  const auto light = vplkit::make_point_light(vec3<T>(0), vec3<T>(1));
  std::vector<vec3<T>> P(32, vec3<T>(0)), N(32, vec3<T>(0, 0, 1)), A(32, vec3<T>(T(0.5)));
  vplkit::dprsm_view<T> view{R, P.data(), N.data(), A.data(), light};
  CHECK_NOTHROW(view.validate());
  const T nan = std::numeric_limits<T>::quiet_NaN(), inf = std::numeric_limits<T>::infinity();

  P[21].y = nan;  // face 1, x 1, y 1
  CHECK(message_contains(view, "texel 21 (face 1, x 1, y 1) has a non-finite position"));
  P[21].y = 0;
  N[3].x = inf;
  N[30].x = inf;
  CHECK(message_contains(view, "texel 3 (face 0, x 3, y 0) has a non-finite normal"));
  N[3].x = 0;
  N[30].x = 0;
  A[16].z = -inf;
  CHECK(message_contains(view, "texel 16 (face 1, x 0, y 0) has a non-finite albedo"));
  A[16].z = T(-0.25);
  CHECK(message_contains(view, "texel 16 (face 1, x 0, y 0) has a negative albedo"));
  A[16].z = 0;
  CHECK_NOTHROW(view.validate());
}

TEMPLATE_TEST_CASE("dprsm: validate rejects bad sizes, null arrays and bad lights", "[vpl]", float,
                   double) {
  using T = TestType;
  std::vector<vec3<T>> P(32, vec3<T>(0)), N(32, vec3<T>(0)), A(32, vec3<T>(0));
  const auto light = vplkit::make_point_light(vec3<T>(0), vec3<T>(1));
  const vplkit::dprsm_view<T> good{4, P.data(), N.data(), A.data(), light};
  CHECK_NOTHROW(good.validate());
  auto v = good;
  v.resolution = 0;
  CHECK(message_contains(v, "resolution 0"));
  v.resolution = -3;
  CHECK(message_contains(v, "resolution -3"));
  v.resolution = vplkit::paraboloid_max_resolution + 1;
  CHECK(message_contains(v, "is not in [1, 16384]"));
  v = good;
  v.normal = nullptr;
  CHECK(message_contains(v, "null"));
  v = good;
  v.light.intensity.y = T(-1);
  CHECK(message_contains(v, "intensity"));
  v = good;
  v.light.position.x = std::numeric_limits<T>::quiet_NaN();
  CHECK(message_contains(v, "light position"));
  v = good;
  v.light.position.x = T(1);  // frame left at the origin
  CHECK(message_contains(v, "frame.position"));
  CHECK_THROWS_AS(vplkit::make_point_light(vec3<T>(0), vec3<T>(1), vec3<T>(0)),
                  vplkit::invalid_input);
}

TEMPLATE_TEST_CASE("dprsm: render_dprsm rejects bad resolutions and non-finite hits", "[vpl]",
                   float, double) {
  using T = TestType;
  const auto light = vplkit::make_point_light(vec3<T>(0), vec3<T>(1));
  std::vector<vec3<T>> P, N, A;
  CHECK_THROWS_AS(vplkit::render_dprsm(light, 0, trace_floor<T>, P, N, A), vplkit::invalid_input);
  auto broken = [](vec3<T> o, vec3<T> d) {
    auto h = trace_floor<T>(o, d);
    if (h) h->albedo.x = std::numeric_limits<T>::quiet_NaN();
    return h;
  };
  // light looking along +z (default): the floor is on the back face
  try {
    vplkit::render_dprsm(light, 8, broken, P, N, A);
    FAIL("no exception");
  } catch (const vplkit::invalid_input& e) {
    CHECK(std::string(e.what()).find("(face 1,") != std::string::npos);
    CHECK(std::string(e.what()).find("non-finite albedo") != std::string::npos);
  }
}

TEMPLATE_TEST_CASE("dprsm: texel_of_direction agrees with the texel centres", "[vpl]", float,
                   double) {
  using T = TestType;
  const int R = 48;
  const auto light = vplkit::make_point_light(vec3<T>(1, 2, 3), vec3<T>(1), vec3<T>(1, -2, T(0.5)));
  const vplkit::dprsm_view<T> view{R, nullptr, nullptr, nullptr, light};
  for (int i = 0; i < view.texel_count(); ++i) {
    if (!view.texel_valid(i)) continue;
    const vplkit::ivec2 xy = vplkit::texel_coords(i, R);
    const vec3<T> d = light.frame.to_world(vplkit::paraboloid_to_direction(
        vplkit::texel_face(i, R), vplkit::texel_center_uv<T>(xy.x, xy.y, R)));
    REQUIRE(view.texel_of_direction(d) == i);
    REQUIRE(view.texel_of_point(light.position + T(5) * d) == i);
  }
}

TEMPLATE_TEST_CASE("dprsm: every direction at the rim finds the surface the light sees there", "[vpl]", float,
                   double) {
  // A cylinder of radius 1 around the light's front axis straddles the seam between the two faces:
  // the light sees it in every direction near the rim. Every such direction must be filed under a
  // texel that carries that surface (dprsm_lookup lit with tolerance 0, as direct_light asks): the
  // parts of invalid rim squares inside the disk belong to a valid neighbour (texel_owner_from_uv).
  using T = TestType;
  const double pi = 3.14159265358979323846;
  const auto light = vplkit::make_point_light(vec3<T>(1, 2, 3), vec3<T>(1), vec3<T>(1, -2, T(0.5)));
  const auto trace_cylinder = [&](vec3<T> o, vec3<T> d) -> std::optional<vplkit::dprsm_hit<T>> {
    const vec3<T> l = light.frame.to_light(d);
    const T r = std::sqrt(l.x * l.x + l.y * l.y);
    if (!(r > T(0))) return std::nullopt;
    const vec3<T> n = -light.frame.to_world(vec3<T>(l.x / r, l.y / r, T(0)));
    return vplkit::dprsm_hit<T>{o + d / r, n, vec3<T>(T(0.5))};
  };
  for (int R : {8, 17, 64, 255}) {
    std::vector<vec3<T>> P, N, A;
    const vplkit::dprsm_view<T> view = vplkit::render_dprsm(light, R, trace_cylinder, P, N, A);
    int tried = 0, unlit = 0, not_contained = 0;
    const int n_angles = 4000;
    for (int k = 0; k < n_angles; ++k) {
      const double phi = 2.0 * pi * (k + 0.5) / n_angles;
      for (int j = -6; j <= 6; ++j) {
        const double z = j * 0.5 / R;  // light-space height: within 3 texel widths of the rim
        const double s = std::sqrt(1.0 - z * z);
        const vec3<T> d = light.frame.to_world(vec3<T>(T(s * std::cos(phi)), T(s * std::sin(phi)), T(z)));
        const vec3<T> y = light.position + d / T(s);  // the cylinder, where the light sees it in d
        const vplkit::dprsm_lookup_result r = vplkit::dprsm_lookup(view, y, T(0));  // as direct_light
        ++tried;
        if (!r.lit) {
          ++unlit;
          const auto q = vplkit::paraboloid_from_direction(light.frame.to_light(d));
          UNSCOPED_INFO("R " << R << " phi " << phi << " z " << z << ": texel " << r.texel << " face " << q.face
                             << " uv " << q.uv.x << ", " << q.uv.y << " valid " << view.texel_valid(r.texel));
        }
        const auto q = vplkit::paraboloid_from_direction(light.frame.to_light(d));
        not_contained += vplkit::texel_from_uv(q.uv, R) != vplkit::texel_coords(r.texel, R);
      }
    }
    std::printf("cylinder across the rim, R %3d: %d directions within 3 texels of the rim, %d unlit, %d filed under a "
                "neighbour of the texel holding them\n",
                R, tried, unlit, not_contained);
    REQUIRE(unlit == 0);
    CHECK(not_contained > 0);
  }
}
