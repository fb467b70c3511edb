// SPDX-License-Identifier: MIT
// The DPRSM's plane records (include/vplkit/vpl/dprsm_plane.hpp, dprsm_planes.hpp) and the
// patch-sampled VPLs read through them (dprsm_view::planes):
//  - dprsm_plane_of's classes: {n_u, +h} for a valid lit texel that saw a surface, {n_u, -h} without
//    albedo, {0, 0} for an invalid texel, h <= 0 (facing away, the light on the plane), a zero,
//    NaN or infinite normal;
//  - build_dprsm_planes writes dprsm_plane_of per texel and refuses a view validate() refuses;
//  - the hidden test through the records decides as the formulation without them (below, as it
//    was written before the records: three arrays and a normalisation per neighbour), and every
//    field of dprsm_patch_vpl and dprsm_patch_direction_at_centre is the same bit for bit with and
//    without records, on a room corner (hidden points along the crease) with hard-case texels
//    injected (zero albedo, zero / tiny / back-facing normals, the light on a texel's plane, rim
//    texels). Float and double.
#include <synthetic_scene.hpp>

#include <vplkit/paraboloid/texel_grid.hpp>
#include <vplkit/vpl/dprsm_patch.hpp>
#include <vplkit/vpl/dprsm_planes.hpp>
#include <vplkit/vpl/dprsm_raycast.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <vector>

using namespace vplkit;

namespace {

template <class T>
bool same_bits(T a, T b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}
template <class T>
bool same_bits(vec3<T> a, vec3<T> b) {
  return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z);
}
template <class T>
bool same_bits(vec2<T> a, vec2<T> b) {
  return same_bits(a.x, b.x) && same_bits(a.y, b.y);
}

// The hidden test as written before the plane records: each neighbour's albedo, normal and
// position read and its plane computed here.
template <class T>
bool hidden_without_records(const dprsm_view<T>& view, int t, vec2<T> uv, vec3<T> w, T d1) {
  const int R = view.resolution;
  const ivec2 xy = texel_coords(t, R);
  const vec2<T> centre = texel_center_uv<T>(xy.x, xy.y, R);
  const int dx = uv.x < centre.x ? -1 : 1, dy = uv.y < centre.y ? -1 : 1;
  const ivec2 near[3] = {ivec2(xy.x + dx, xy.y), ivec2(xy.x, xy.y + dy), ivec2(xy.x + dx, xy.y + dy)};
  const vec3<T> c = view.light.position;
  for (const ivec2 q : near) {
    if (q.x < 0 || q.y < 0 || q.x >= R || q.y >= R || !texel_is_valid(q.x, q.y, R)) continue;
    const int u = texel_index(texel_face(t, R), q.x, q.y, R);
    const vec3<T> rho = view.albedo[u];
    if (!(rho.x > T(0) || rho.y > T(0) || rho.z > T(0))) continue;
    const vec3<T> n_u = unit_or_zero(view.normal[u]);
    const T h_u = glm::dot(n_u, c - view.position[u]);
    const T cos_u = -glm::dot(n_u, w);
    if (!(h_u > T(0)) || !(cos_u > dprsm_plane_min_cos<T>())) continue;
    if (d1 * cos_u > h_u * (T(1) + dprsm_patch_hidden_margin<T>())) return true;
  }
  return false;
}

// A room corner (the floor z = 0 and the wall x = 0.3, as in vpl_dprsm_patch_test.cpp) under a
// light at (0, 0, 1), then hard cases written into chosen texels.
template <class T>
struct corner_with_hard_cases {
  std::vector<vec3<T>> position, normal, albedo;
  dprsm_view<T> view;
  std::vector<int> injected;
  explicit corner_with_hard_cases(int R) {
    const point_light<T> light = make_point_light(vec3<T>(0, 0, 1), vec3<T>(1), vec3<T>(0, 0, -1));
    view = render_dprsm(
        light, R,
        [](vec3<T> o, vec3<T> d) -> std::optional<dprsm_hit<T>> {
          const T wall_x = T(0.3);
          T best = std::numeric_limits<T>::infinity();
          std::optional<dprsm_hit<T>> hit;
          if (d.z < 0) {
            const T t = -o.z / d.z;
            const vec3<T> p = o + t * d;
            if (t > 0 && p.x <= wall_x) best = t, hit = dprsm_hit<T>{p, vec3<T>(0, 0, 1), vec3<T>(T(0.5))};
          }
          if (d.x > 0) {
            const T t = (wall_x - o.x) / d.x;
            const vec3<T> p = o + t * d;
            if (t > 0 && t < best && p.z >= 0) hit = dprsm_hit<T>{p, vec3<T>(-1, 0, 0), vec3<T>(T(0.5))};
          }
          return hit;
        },
        position, normal, albedo);
    // Hard cases in a band of texels that straddles the crease and the floor: each kind every
    // seventh lit texel, so every kind has lit neighbours and neighbours of every kind.
    int k = 0;
    for (int t = 0; t < view.texel_count(); ++t) {
      if (!(albedo[t] != vec3<T>(0)) || (t % 7) != 0) continue;
      switch (k++ % 6) {
        case 0: albedo[t] = vec3<T>(0); break;                          // saw nothing (plane kept for itself)
        case 1: normal[t] = vec3<T>(0); break;                          // zero normal: no plane
        case 2: normal[t] = normal[t] * T(1e-30); break;                // tiny normal: the same unit plane
        case 3: normal[t] = -normal[t]; break;                          // facing away
        case 4: position[t].z = light.position.z, normal[t] = vec3<T>(0, 0, 1); break;  // the light on its plane
        case 5: normal[t] = normal[t] * T(1e30); break;                 // huge normal
      }
      injected.push_back(t);
    }
  }
  corner_with_hard_cases(const corner_with_hard_cases&) = delete;
  corner_with_hard_cases& operator=(const corner_with_hard_cases&) = delete;
};

}  // namespace

TEMPLATE_TEST_CASE("dprsm_plane_of: the record's classes", "[vpl]", float, double) {
  using T = TestType;
  const vec3<T> c(0, 0, 2), y(T(0.25), T(-0.5), 0), up(0, 0, 1), rho(T(0.5));
  const T nan = std::numeric_limits<T>::quiet_NaN(), inf = std::numeric_limits<T>::infinity();
  const dprsm_plane<T> lit = dprsm_plane_of(c, true, y, up * T(3), rho);
  CHECK(lit.normal == up);
  CHECK(lit.height == T(2));
  CHECK(dprsm_plane_can_hide(lit));
  const dprsm_plane<T> dark = dprsm_plane_of(c, true, y, up * T(3), vec3<T>(0));
  CHECK(dark.normal == up);
  CHECK(dark.height == T(-2));  // keeps |h| for its own patch, hides nothing
  CHECK_FALSE(dprsm_plane_can_hide(dark));
  const vec3<T> some_albedo_channel(0, 0, T(0.25));
  CHECK(dprsm_plane_of(c, true, y, up, some_albedo_channel).height == T(2));
  for (const dprsm_plane<T>& none :
       {dprsm_plane_of(c, false, y, up, rho),                        // invalid texel
        dprsm_plane_of(c, true, y, -up, rho),                        // facing away
        dprsm_plane_of(c, true, vec3<T>(1, 1, 2), up, rho),          // the light on its plane: h = 0
        dprsm_plane_of(c, true, y, vec3<T>(0), rho),                 // zero normal
        dprsm_plane_of(c, true, y, vec3<T>(nan, 0, 1), rho),         // NaN normal
        dprsm_plane_of(c, true, y, vec3<T>(inf, 0, 1), rho),         // infinite normal
        dprsm_plane_of(c, true, vec3<T>(nan, 0, 0), up, rho)}) {     // NaN position: h NaN
    INFO("normal " << none.normal.x << " " << none.normal.y << " " << none.normal.z << " height " << none.height);
    CHECK(none.normal == vec3<T>(0));
    CHECK(same_bits(none.height, T(0)));
    CHECK_FALSE(dprsm_plane_can_hide(none));
  }
  // The infinite position is the one non-finite record: +inf height, unit normal (validate()
  // refuses such a view; the record function still gives no NaN).
  const dprsm_plane<T> far = dprsm_plane_of(c, true, vec3<T>(0, 0, -inf), up, rho);
  CHECK(far.normal == up);
  CHECK(far.height == inf);
}

TEMPLATE_TEST_CASE("build_dprsm_planes: dprsm_plane_of per texel, plane_at with and without records", "[vpl]", float,
                   double) {
  using T = TestType;
  const corner_with_hard_cases<T> s(16);
  const std::vector<dprsm_plane<T>> planes = build_dprsm_planes(s.view);
  REQUIRE(planes.size() == std::size_t(s.view.texel_count()));
  dprsm_view<T> with = s.view;
  with.planes = planes.data();
  int can_hide = 0, dark = 0, none = 0;
  for (int t = 0; t < s.view.texel_count(); ++t) {
    const dprsm_plane<T> p = planes[std::size_t(t)];
    const dprsm_plane<T> q =
        dprsm_plane_of(s.view.light.position, s.view.texel_valid(t), s.view.position[t], s.view.normal[t], s.view.albedo[t]);
    INFO("texel " << t);
    CHECK(same_bits(p.normal, q.normal));
    CHECK(same_bits(p.height, q.height));
    CHECK(same_bits(s.view.plane_at(t).height, with.plane_at(t).height));
    CHECK(same_bits(s.view.plane_at(t).normal, with.plane_at(t).normal));
    if (!s.view.texel_valid(t)) CHECK(same_bits(p.height, T(0)));
    can_hide += p.height > 0 ? 1 : 0;
    dark += p.height < 0 ? 1 : 0;
    none += p.height == 0 ? 1 : 0;
  }
  CHECK(can_hide > 100);
  CHECK(dark > 0);
  CHECK(none > 0);
  // A view validate() refuses is refused, with its message.
  std::vector<vec3<T>> normal = s.normal;
  normal[5] = vec3<T>(std::numeric_limits<T>::quiet_NaN());
  dprsm_view<T> bad = s.view;
  bad.normal = normal.data();
  CHECK_THROWS_WITH(build_dprsm_planes(bad), Catch::Contains("texel 5") && Catch::Contains("non-finite normal"));
}

TEMPLATE_TEST_CASE("dprsm_patch_vpl through the plane records: the same decisions and bits as without them", "[vpl]",
                   float, double) {
  using T = TestType;
  const int R = 32;
  const corner_with_hard_cases<T> s(R);
  const std::vector<dprsm_plane<T>> planes = build_dprsm_planes(s.view);
  dprsm_view<T> with = s.view;
  with.planes = planes.data();
  const T inf = std::numeric_limits<T>::infinity();
  const vec3<T> c = s.view.light.position;
  long long samples = 0, hidden = 0, hidden_direct = 0, accepted = 0, rim = 0, next_to_injected = 0;
  std::vector<char> injected(std::size_t(s.view.texel_count()), 0);
  for (int t : s.injected) injected[std::size_t(t)] = 1;
  for (int t = 0; t < s.view.texel_count(); ++t) {
    if (!s.view.texel_valid(t)) continue;
    const ivec2 xy = texel_coords(t, R);
    const texel_block block = texel_patch_block(xy.x, xy.y, R);
    rim += block.nx * block.ny != 1 ? 1 : 0;
    bool near_injected = false;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int x = xy.x + dx, y = xy.y + dy;
        if (x >= 0 && y >= 0 && x < R && y < R && injected[std::size_t(texel_index(texel_face(t, R), x, y, R))])
          near_injected = true;
      }
    next_to_injected += near_injected ? 1 : 0;
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) {
        const vec2<T> xi(T(i) / 5 * T(0.999), T(j) / 5 * T(0.999));
        for (const T tol : {inf, T(0.01)}) {
          const dprsm_patch_sample<T> a = dprsm_patch_vpl(s.view, t, xi, tol);
          const dprsm_patch_sample<T> b = dprsm_patch_vpl(with, t, xi, tol);
          ++samples;
          INFO("texel " << t << " xi " << xi.x << " " << xi.y << " tol " << tol);
          REQUIRE(a.at_centre == b.at_centre);
          CHECK(same_bits(a.point.position, b.point.position));
          CHECK(same_bits(a.point.normal, b.point.normal));
          CHECK(same_bits(a.point.flux, b.point.flux));
          CHECK(same_bits(a.uv, b.uv));
          CHECK(same_bits(a.solid_angle, b.solid_angle));
          CHECK(same_bits(a.distance, b.distance));
          CHECK(same_bits(a.cos_alpha, b.cos_alpha));
          accepted += vpl_has_flux(b.point) ? 1 : 0;
          hidden += b.at_centre ? 1 : 0;
        }
        // The hidden test itself along this texel's plane point and at other distances, against
        // the formulation without records.
        const vec2<T> uv = texel_block_point_uv(block, R, xi);
        const vec3<T> w = s.view.light.frame.to_world(paraboloid_to_direction(texel_face(t, R), uv));
        const T d_t = glm::length(s.view.position[t] - c);
        for (const T d1 : {d_t, d_t * T(0.5), d_t * T(2), T(0), inf}) {
          const bool ref = hidden_without_records(s.view, t, uv, w, d1);
          hidden_direct += ref ? 1 : 0;
          INFO("texel " << t << " uv " << uv.x << " " << uv.y << " d1 " << d1);
          CHECK(dprsm_patch_point_hidden(with, t, uv, w, d1) == ref);
          CHECK(dprsm_patch_point_hidden(s.view, t, uv, w, d1) == ref);
        }
        const vec3<T> y = c + d_t * w;
        CHECK(dprsm_patch_direction_at_centre(with, t, y) == dprsm_patch_direction_at_centre(s.view, t, y));
      }
  }
  // A texel without albedo keeps its plane for its own patch (record height -h): its samples are
  // those of the same texel with an albedo, flux 0 (the computation before the records).
  std::vector<vec3<T>> albedo = s.albedo;
  int dark_texels = 0;
  for (int t : s.injected)
    if (s.albedo[t] == vec3<T>(0)) albedo[t] = vec3<T>(T(0.5)), ++dark_texels;
  dprsm_view<T> lit = s.view;
  lit.albedo = albedo.data();
  const std::vector<dprsm_plane<T>> lit_planes = build_dprsm_planes(lit);
  lit.planes = lit_planes.data();
  long long dark_checked = 0;
  for (int t : s.injected) {
    if (!(s.albedo[t] == vec3<T>(0))) continue;
    for (int k = 0; k < 16; ++k) {
      const vec2<T> xi((T(k % 4) + T(0.5)) / 4, (T(k / 4) + T(0.5)) / 4);
      const dprsm_patch_sample<T> a = dprsm_patch_vpl(with, t, xi, inf), b = dprsm_patch_vpl(lit, t, xi, inf);
      INFO("dark texel " << t << " k " << k);
      CHECK(a.point.flux == vec3<T>(0));
      CHECK(same_bits(a.solid_angle, b.solid_angle));
      CHECK(same_bits(a.distance, b.distance));
      CHECK(same_bits(a.point.position, b.point.position));
      CHECK(a.at_centre == b.at_centre);
      dark_checked += b.solid_angle > 0 ? 1 : 0;
    }
  }
  CHECK(dark_texels > 5);
  CHECK(dark_checked > 50);
  CHECK(samples > 10000);
  CHECK(accepted > samples / 4);
  CHECK(hidden > 50);
  CHECK(hidden_direct > 1000);
  CHECK(rim > 50);
  CHECK(next_to_injected > 100);
}
