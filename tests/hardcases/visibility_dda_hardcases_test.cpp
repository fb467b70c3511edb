// SPDX-License-Identifier: MIT
// docs/math.md section 10, DDA: axis-parallel rays, rays outside the grid, zero length; plus rays
// along voxel boundaries and exactly through voxel corners. One TEST_CASE per hard case; every case
// checks that nothing NaN or infinite comes out.
#include <vplkit/visibility/dda.hpp>
#include <vplkit/visibility/voxel_visible.hpp>
#include <vplkit/visibility/voxelize.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

using vplkit::ivec3;

namespace {

// [0, n]^3 with unit voxels: every voxel plane is an exact integer.
template <class T>
vplkit::voxel_grid<T> unit_grid(int n) {
  return vplkit::voxel_grid<T>(vplkit::vec3<T>(T(0)), vplkit::vec3<T>(T(n)), ivec3(n));
}

template <class T>
vplkit::dda_hit<T> march(const vplkit::voxel_grid<T>& g, vplkit::vec3<T> o, vplkit::vec3<T> d,
                         T t_max = std::numeric_limits<T>::infinity()) {
  const vplkit::dda_hit<T> h = vplkit::dda_first_hit(g.view(), o, d, t_max);
  REQUIRE(std::isfinite(h.t));
  REQUIRE(h.t >= T(0));
  if (!h.hit) REQUIRE(h.voxel == ivec3(-1));
  if (h.hit) REQUIRE(g.test(h.voxel));
  return h;
}

// The voxels visited in order, found by occupying one voxel at a time: a voxel is visited iff a
// march through a grid where only it is occupied hits it.
template <class T>
bool visits(int n, ivec3 v, vplkit::vec3<T> o, vplkit::vec3<T> d, T* t = nullptr) {
  auto g = unit_grid<T>(n);
  g.set(v);
  const auto h = march(g, o, d);
  if (t != nullptr) *t = h.t;
  return h.hit;
}

template <class T>
void axis_parallel() {
  using v3 = vplkit::vec3<T>;
  for (int a = 0; a < 3; ++a) {
    for (int s : {1, -1}) {
      auto g = unit_grid<T>(8);
      ivec3 target(3, 4, 5);
      target[a] = s > 0 ? 6 : 1;
      g.set(target);
      v3 o(T(3.5), T(4.5), T(5.5));
      o[a] = s > 0 ? T(0.5) : T(7.5);
      v3 d(T(0));
      d[a] = T(s);
      INFO("axis " << a << " sign " << s);
      auto h = march(g, o, d);
      REQUIRE(h.hit);
      REQUIRE(h.voxel == target);
      REQUIRE(h.t == T(5.5));  // exact: integer planes, unit direction
      // Scaled direction, and the same ray from outside the grid.
      h = march(g, o, d * T(1e-3));
      REQUIRE((h.hit && h.voxel == target && h.t == T(5.5)));
      v3 outside = o;
      outside[a] = s > 0 ? T(-10.5) : T(18.5);
      h = march(g, outside, d);
      REQUIRE((h.hit && h.voxel == target && h.t == T(16.5)));
      // One voxel off on another axis: misses, and so does the reverse direction.
      v3 off = o;
      off[(a + 1) % 3] += T(1);
      REQUIRE_FALSE(march(g, off, d).hit);
      REQUIRE_FALSE(march(g, o, -d).hit);
      // Parallel to the axis but outside the grid's slab on another axis: clipped away.
      off[(a + 1) % 3] = T(-0.001);
      REQUIRE_FALSE(march(g, off, d).hit);
    }
  }
}

}  // namespace

TEST_CASE("DDA hard case: axis-parallel rays along each axis, both directions", "[visibility][hardcase]") {
  axis_parallel<float>();
  axis_parallel<double>();
}

TEST_CASE("DDA hard case: rays starting outside the grid that hit", "[visibility][hardcase]") {
  using v3 = vplkit::vec3<double>;
  auto g = unit_grid<double>(8);
  g.set(ivec3(0, 0, 0));
  g.set(ivec3(7, 7, 7));
  g.set(ivec3(4, 0, 3));
  // Entering exactly through the grid corner (0,0,0).
  auto h = march(g, v3(-1, -1, -1), v3(1, 1, 1));
  REQUIRE((h.hit && h.voxel == ivec3(0, 0, 0)));
  REQUIRE(h.t == Approx(std::sqrt(3.0)));
  // Entering through the opposite corner from beyond it.
  h = march(g, v3(9, 9, 9), v3(-1, -1, -1));
  REQUIRE((h.hit && h.voxel == ivec3(7, 7, 7)));
  REQUIRE(h.t == Approx(std::sqrt(3.0)));
  // Entering through a face, obliquely, from far away.
  const v3 c(4.5, 0.5, 3.5), o = c + v3(-3e3, -7e3, 2e3);
  h = march(g, o, c - o);
  REQUIRE((h.hit && h.voxel == ivec3(4, 0, 3)));
  // Float, from far away: the same voxel.
  auto gf = unit_grid<float>(8);
  gf.set(ivec3(4, 0, 3));
  const vplkit::vec3<float> cf(4.5f, 0.5f, 3.5f), of = cf + vplkit::vec3<float>(-3e3f, -7e3f, 2e3f);
  const auto hf = march(gf, of, cf - of);
  REQUIRE((hf.hit && hf.voxel == ivec3(4, 0, 3)));
  REQUIRE(hf.t == Approx(glm::length(cf - of) - glm::length(cf - of) * 0.5f / 7e3f).epsilon(1e-4));
  // Entering along an edge of the grid box (the line y = 0, z = 0): touches voxel row (x, 0, 0).
  h = march(g, v3(-5, 0, 0), v3(1, 0, 0));
  REQUIRE((h.hit && h.voxel == ivec3(0, 0, 0) && h.t == 5.0));
}

TEST_CASE("DDA hard case: rays starting outside the grid that miss", "[visibility][hardcase]") {
  using v3 = vplkit::vec3<float>;
  auto g = unit_grid<float>(8);
  for (int z = 0; z < 8; ++z)
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) g.set(ivec3(x, y, z));  // everything occupied
  REQUIRE_FALSE(march(g, v3(-1, 4, 4), v3(-1, 0, 0)).hit);          // pointing away
  REQUIRE_FALSE(march(g, v3(-1, 4, 4), v3(0, 1, 0)).hit);           // parallel to the face, outside
  REQUIRE_FALSE(march(g, v3(-1, -1, 4), v3(1, -0.001f, 0)).hit);    // passing beside an edge
  REQUIRE_FALSE(march(g, v3(-1, 9, 4), v3(1, 1, 0)).hit);           // passing beyond a corner
  REQUIRE_FALSE(march(g, v3(-1.0f, 9.0f, 4), v3(1, -0.1f, 0)).hit); // reaches y = 8 only beyond x = 8
  REQUIRE(march(g, v3(-1.0f, 9.0f, 4), v3(1, -1.0f, 0)).hit);       // touches the grid's edge x = 0, y = 8
  REQUIRE_FALSE(march(g, v3(-10, 4, 4), v3(1, 0, 0), 9.5f).hit);    // t_max ends before the grid
  REQUIRE(march(g, v3(-10, 4, 4), v3(1, 0, 0), 10.0f).hit);         // ... or exactly at its face
  REQUIRE_FALSE(march(g, v3(1e30f, 4, 4), v3(1, 0, 0)).hit);        // far away, pointing away
  // Far away, pointing at it: o + t * d has lost every digit of the grid, but the face the ray
  // enters through fixes the first layer exactly.
  const auto far = march(g, v3(1e30f, 4.5f, 4.5f), v3(-1, 0, 0));
  REQUIRE(far.hit);
  REQUIRE(far.voxel == ivec3(7, 4, 4));
  REQUIRE(far.t == Approx(1e30f));
}

TEST_CASE("DDA hard case: zero-length, denormal and non-finite rays", "[visibility][hardcase]") {
  using v3 = vplkit::vec3<float>;
  auto g = unit_grid<float>(4);
  g.set(ivec3(1, 1, 1));
  const v3 inside(1.5f, 1.5f, 1.5f);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const float den = std::numeric_limits<float>::denorm_min();
  // Even from inside an occupied voxel: no direction, no hit.
  REQUIRE_FALSE(march(g, inside, v3(0.0f)).hit);
  REQUIRE_FALSE(march(g, inside, v3(-0.0f, 0.0f, -0.0f)).hit);
  REQUIRE_FALSE(march(g, inside, v3(den, 0.0f, den)).hit);  // what a GPU flushes to zero
  REQUIRE_FALSE(march(g, inside, v3(nan, 1.0f, 0.0f)).hit);
  REQUIRE_FALSE(march(g, inside, v3(inf, 0.0f, 0.0f)).hit);
  REQUIRE_FALSE(march(g, v3(nan, 1.5f, 1.5f), v3(1, 0, 0)).hit);
  REQUIRE_FALSE(march(g, v3(-inf, 1.5f, 1.5f), v3(1, 0, 0)).hit);
  vplkit::vec3<float> unit(0.0f);
  REQUIRE_FALSE(vplkit::dda_unit_direction(v3(den), unit));
  REQUIRE(unit == v3(0.0f));
  // The smallest normal float is a direction; a tiny component next to a large one becomes 0.
  REQUIRE(vplkit::dda_unit_direction(v3(std::numeric_limits<float>::min(), 0, 0), unit));
  REQUIRE(unit == v3(1, 0, 0));
  REQUIRE(vplkit::dda_unit_direction(v3(1.0f, 1000.0f * den, 0), unit));
  REQUIRE(unit == v3(1, 0, 0));
  // The same in double: parity with float, not double's own denormal range.
  vplkit::vec3<double> ud(0.0);
  REQUIRE_FALSE(vplkit::dda_unit_direction(vplkit::vec3<double>(1e-39, 0, 0), ud));
  // Visibility and trace with zero-length segments: x == y is visible, the trace misses.
  REQUIRE(vplkit::voxel_visible(g.view(), inside, v3(0, 0, 1), inside));
  const auto tr = vplkit::dda_trace_hit_point(g.view(), inside, v3(0.0f));
  REQUIRE_FALSE(tr.hit);
  REQUIRE(tr.point == inside);
}

TEST_CASE("DDA hard case: rays along voxel boundaries", "[visibility][hardcase]") {
  using v3 = vplkit::vec3<double>;
  // A ray in the plane x = 3 walks the layer above the plane (x = 3), not x = 2.
  REQUIRE(visits(8, ivec3(3, 5, 4), v3(3, 0.5, 4.5), v3(0, 1, 0)));
  REQUIRE_FALSE(visits(8, ivec3(2, 5, 4), v3(3, 0.5, 4.5), v3(0, 1, 0)));
  // On the edge line x = 3, z = 4: layer (3, *, 4) only.
  REQUIRE(visits(8, ivec3(3, 6, 4), v3(3, 0.5, 4), v3(0, 1, 0)));
  for (ivec3 v : {ivec3(2, 6, 4), ivec3(3, 6, 3), ivec3(2, 6, 3)}) REQUIRE_FALSE(visits(8, v, v3(3, 0.5, 4), v3(0, 1, 0)));
  // Oblique within the plane x = 3.
  double t = -1;
  REQUIRE(visits(8, ivec3(3, 4, 6), v3(3, 0.5, 2.5), v3(0, 1, 1), &t));
  REQUIRE(t == Approx(3.5 * std::sqrt(2.0)));
  REQUIRE_FALSE(visits(8, ivec3(2, 4, 6), v3(3, 0.5, 2.5), v3(0, 1, 1)));
  // In the grid's max face x = 8: the last layer (x = 7); in its min face: x = 0.
  REQUIRE(visits(8, ivec3(7, 5, 4), v3(8, 0.5, 4.5), v3(0, 1, 0)));
  REQUIRE(visits(8, ivec3(0, 5, 4), v3(0, -3, 4.5), v3(0, 1, 0)));
  // A ray along a boundary plane but moving across planes on the other axes: every crossing is
  // exact; t is the exact plane distance.
  REQUIRE(visits(8, ivec3(5, 3, 0), v3(0.25, 3, 0), v3(1, 0, 0), &t));
  REQUIRE(t == 4.75);
  // Float: the same.
  REQUIRE(visits(8, ivec3(3, 5, 4), vplkit::vec3<float>(3, 0.5f, 4.5f), vplkit::vec3<float>(0, 1, 0)));
  REQUIRE_FALSE(visits(8, ivec3(2, 5, 4), vplkit::vec3<float>(3, 0.5f, 4.5f), vplkit::vec3<float>(0, 1, 0)));
}

TEST_CASE("DDA hard case: rays exactly through voxel corners", "[visibility][hardcase]") {
  using v3 = vplkit::vec3<double>;
  const double s3 = std::sqrt(3.0);
  // The main diagonal from the grid corner: ties on all three axes at every corner. Tie rule x,
  // then y, then z: (0,0,0) (1,0,0) (1,1,0) (1,1,1) (2,1,1) ...; the voxels only touched at a
  // corner that the rule does not pick, such as (0,1,0), are not visited.
  double t = -1;
  REQUIRE(visits(8, ivec3(0, 0, 0), v3(0), v3(1, 1, 1), &t));
  REQUIRE(t == 0.0);
  for (ivec3 v : {ivec3(1, 0, 0), ivec3(1, 1, 0), ivec3(1, 1, 1), ivec3(2, 1, 1), ivec3(7, 7, 7)}) {
    INFO(v.x << " " << v.y << " " << v.z);
    REQUIRE(visits(8, v, v3(0), v3(1, 1, 1), &t));
    REQUIRE(t == Approx(s3 * std::max(v.x, std::max(v.y, v.z))));
  }
  for (ivec3 v : {ivec3(0, 1, 0), ivec3(0, 0, 1), ivec3(0, 1, 1), ivec3(1, 0, 1)})
    REQUIRE_FALSE(visits(8, v, v3(0), v3(1, 1, 1)));
  // Negative direction from the grid's max corner: (7,7,7) (6,7,7) (6,6,7) (6,6,6).
  for (ivec3 v : {ivec3(7, 7, 7), ivec3(6, 7, 7), ivec3(6, 6, 7), ivec3(6, 6, 6)})
    REQUIRE(visits(8, v, v3(8), v3(-1, -1, -1)));
  REQUIRE_FALSE(visits(8, ivec3(7, 6, 7), v3(8), v3(-1, -1, -1)));
  // Float: the same ties (the normalised components are equal, so the crossings tie exactly).
  REQUIRE(visits(8, ivec3(1, 1, 0), vplkit::vec3<float>(0), vplkit::vec3<float>(1, 1, 1)));
  REQUIRE_FALSE(visits(8, ivec3(0, 1, 0), vplkit::vec3<float>(0), vplkit::vec3<float>(1, 1, 1)));

  // A diagonal wall of voxels (i, 7 - i, z), 8-connected: rays crossing it exactly through the
  // corners its voxels share must not slip between them.
  auto g = unit_grid<double>(8);
  for (int i = 0; i < 8; ++i)
    for (int z = 0; z < 8; ++z) g.set(ivec3(i, 7 - i, z));
  for (int i = 0; i < 7; ++i) {
    const v3 corner(i + 1, 7 - i, 3.5);
    for (const v3 d : {v3(1, 1, 0), v3(-1, -1, 0), v3(1, 1, 0.3), v3(-1, -1, -0.7)}) {
      INFO("corner " << i << " dir " << d.x << " " << d.y << " " << d.z);
      const auto h = march(g, corner - 0.5 * d, d);
      REQUIRE(h.hit);
      REQUIRE(h.t <= glm::length(0.5 * d) + 1e-12);
    }
  }
}

TEST_CASE("DDA hard case: a closed box with faces on voxel planes holds every ray from inside",
          "[visibility][hardcase]") {
  // Box [2, 6]^3 in [0, 8]^3 at 8^3: every face lies exactly on a voxel plane, so it marks the
  // layers on both sides; the empty inside is [3, 5]^3. Rays from lattice points inside (voxel
  // corners, edge midpoints, centres), in lattice and random directions.
  using v3 = vplkit::vec3<float>;
  const v3 c(4.0f);
  std::vector<v3> p;
  for (int i = 0; i < 8; ++i) p.push_back(c + v3((i & 1) ? 2.0f : -2.0f, (i & 2) ? 2.0f : -2.0f, (i & 4) ? 2.0f : -2.0f));
  const std::uint32_t f[36] = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                               2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  auto g = unit_grid<float>(8);
  vplkit::voxelize(g, p.data(), p.size(), f, 36);
  REQUIRE(g.count() == 6 * 6 * 6 - 2 * 2 * 2);
  std::vector<v3> dirs;
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y)
      for (int z = -1; z <= 1; ++z)
        if (x != 0 || y != 0 || z != 0) dirs.push_back(v3(float(x), float(y), float(z)));
  std::mt19937 rng(8);
  std::normal_distribution<float> n01(0.0f, 1.0f);
  for (int i = 0; i < 200; ++i) dirs.push_back(v3(n01(rng), n01(rng), n01(rng)));
  int rays = 0;
  for (float ox : {3.0f, 3.5f, 4.0f, 4.5f, 5.0f})
    for (float oy : {3.0f, 3.5f, 4.0f, 4.5f, 5.0f})
      for (float oz : {3.0f, 4.0f, 4.5f, 5.0f})
        for (const v3& d : dirs) {
          const v3 o(ox, oy, oz);
          const auto h = march(g, o, d);
          INFO("origin " << ox << " " << oy << " " << oz << " dir " << d.x << " " << d.y << " " << d.z);
          REQUIRE(h.hit);
          // No later than the box surface (at most 3 units away along any axis-aligned path).
          vplkit::vec3<float> u(0.0f);
          REQUIRE(vplkit::dda_unit_direction(d, u));
          float t_exit = std::numeric_limits<float>::max();
          for (int a = 0; a < 3; ++a)
            if (u[a] != 0.0f) t_exit = std::min(t_exit, ((u[a] > 0 ? 6.0f : 2.0f) - o[a]) / u[a]);
          REQUIRE(h.t <= t_exit + 1e-5f);
          ++rays;
        }
  CHECK(rays == 100 * int(dirs.size()));
}
