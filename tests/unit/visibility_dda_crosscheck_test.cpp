// SPDX-License-Identifier: MIT
// Cross-check of the DDA against brute force: for thousands of random rays in a random occupancy
// grid, the first hit equals the smallest entry distance of a ray / closed-box slab test over ALL
// occupied voxels.
//
// Tie rule: at an exact (or, after rounding, near) edge or corner crossing the DDA may visit a
// side voxel that the ray only grazes, or skip one; both change nothing that a sliver of width eps
// could not. So the brute force runs twice, with every box shrunk and grown by eps voxels, and the
// DDA must lie between the two answers:
//   - grown boxes miss        => the DDA misses;
//   - shrunk boxes hit at ts  => the DDA hits, at t <= ts + tol;
//   - the DDA hits at t       => t >= (grown-box first entry) - tol, the voxel is occupied, and the
//                               ray meets that voxel's grown box around t.
// And the test is not vacuous: for almost every ray the two brute forces agree and the DDA returns
// exactly their voxel.
#include <vplkit/visibility/dda.hpp>
#include <vplkit/visibility/voxel_grid.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace {

using dvec3 = glm::dvec3;

struct box_hit {
  bool hit;
  double t_in, t_out;
};

// Slab test of the closed box [lo, hi] against o + t d, t in [0, t_max], in double.
box_hit slab(dvec3 o, dvec3 d, dvec3 lo, dvec3 hi, double t_max) {
  double t0 = 0.0, t1 = t_max;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      if (o[a] < lo[a] || o[a] > hi[a]) return {false, 0, 0};
      continue;
    }
    double ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (t0 > t1) return {false, 0, 0};
  return {true, t0, t1};
}

struct brute {
  bool hit;
  double t;
  vplkit::ivec3 voxel;
};

template <class T>
brute brute_first_hit(const vplkit::voxel_grid<T>& g, const std::vector<vplkit::ivec3>& occupied, dvec3 o,
                      dvec3 d, double t_max, double grow_voxels) {
  const dvec3 bmin(g.bounds_min()), size(g.voxel_size());
  brute best{false, std::numeric_limits<double>::infinity(), vplkit::ivec3(-1)};
  for (const vplkit::ivec3& v : occupied) {
    const dvec3 lo = bmin + dvec3(v) * size - grow_voxels * size;
    const dvec3 hi = bmin + dvec3(v + 1) * size + grow_voxels * size;
    const box_hit h = slab(o, d, lo, hi, t_max);
    if (h.hit && h.t_in < best.t) best = {true, h.t_in, v};
  }
  return best;
}

// lattice = false: random origins (inside the box or in a shell around it), random directions,
// random grid bounds. lattice = true: the worst case for ties: power-of-two voxel sizes, origins on
// voxel corners, edges and faces, directions with small integer components, so that rays run
// along boundary planes and through edges and corners exactly.
template <class T>
void crosscheck(std::uint32_t seed, double eps_voxels, int rays, bool lattice = false) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  // Non-cubic voxels, bounds not at the origin, sizes that are not powers of two.
  const vplkit::vec3<T> bmin = lattice ? vplkit::vec3<T>(T(-4), T(0), T(8)) : vplkit::vec3<T>(T(-3.1), T(0.7), T(10.2));
  const vplkit::vec3<T> bmax = lattice ? vplkit::vec3<T>(T(4), T(4), T(16)) : vplkit::vec3<T>(T(4.3), T(5.9), T(19.9));
  const vplkit::ivec3 res = lattice ? vplkit::ivec3(16, 16, 32) : vplkit::ivec3(23, 17, 31);
  vplkit::voxel_grid<T> grid(bmin, bmax, res);
  std::vector<vplkit::ivec3> occupied;
  for (int z = 0; z < res.z; ++z)
    for (int y = 0; y < res.y; ++y)
      for (int x = 0; x < res.x; ++x)
        if (u01(rng) < (lattice ? 0.08 : 0.05)) {
          grid.set(vplkit::ivec3(x, y, z));
          occupied.push_back(vplkit::ivec3(x, y, z));
        }
  const auto view = grid.view();
  const double tol = eps_voxels * double(grid.voxel_length());
  std::normal_distribution<double> n01(0.0, 1.0);

  int clean = 0, ties = 0, hits = 0, misses = 0, outside_starts = 0;
  for (int r = 0; r < rays; ++r) {
    // Origins inside the box, or in a shell around it (then the ray must be clipped first).
    const bool outside = (r % 2) == 1;
    const double pad = outside ? 0.6 : 0.0;
    vplkit::vec3<T> o(T(0));
    for (int a = 0; a < 3; ++a) {
      const double lo = double(bmin[a]), hi = double(bmax[a]), ext = hi - lo;
      o[a] = T(lo - pad * ext + u01(rng) * (1.0 + 2.0 * pad) * ext);
    }
    if (o.x < bmin.x || o.y < bmin.y || o.z < bmin.z || o.x > bmax.x || o.y > bmax.y || o.z > bmax.z)
      ++outside_starts;
    vplkit::vec3<T> dir(T(n01(rng)), T(n01(rng)), T(n01(rng)));
    if (lattice) {
      // Half-voxel lattice points (corners, edge and face midpoints, centres), some outside.
      const vplkit::vec3<T> size = grid.voxel_size();
      for (int a = 0; a < 3; ++a) {
        const int k = int(u01(rng) * (2 * res[a] + 9)) - 4;
        o[a] = bmin[a] + T(k) * T(0.5) * size[a];
      }
      do {
        for (int a = 0; a < 3; ++a) dir[a] = T(int(u01(rng) * 5.0) - 2) * size[a];
      } while (dir == vplkit::vec3<T>(T(0)));
    }
    const T t_max = (r % 3 == 0) ? T(u01(rng) * 15.0) : std::numeric_limits<T>::infinity();

    vplkit::vec3<T> dn(T(0));
    REQUIRE(vplkit::dda_unit_direction(dir, dn));
    const dvec3 od(o), dd(dn);
    const double tm = double(t_max);
    const brute grown = brute_first_hit(grid, occupied, od, dd, tm, eps_voxels);
    const brute shrunk = brute_first_hit(grid, occupied, od, dd, tm, -eps_voxels);
    const vplkit::dda_hit<T> h = vplkit::dda_first_hit(view, o, dir, t_max);

    INFO("ray " << r << " origin " << o.x << " " << o.y << " " << o.z << " dir " << dir.x << " " << dir.y << " "
                << dir.z << " t_max " << t_max);
    REQUIRE(std::isfinite(h.t));
    if (!grown.hit) REQUIRE_FALSE(h.hit);
    if (shrunk.hit) {
      REQUIRE(h.hit);
      REQUIRE(double(h.t) <= shrunk.t + tol);
    }
    if (h.hit) {
      ++hits;
      REQUIRE(grown.hit);
      REQUIRE(grid.test(h.voxel));
      REQUIRE(double(h.t) >= grown.t - tol);
      REQUIRE(double(h.t) <= tm);
      const dvec3 lo = dvec3(bmin) + dvec3(h.voxel) * dvec3(grid.voxel_size()) - eps_voxels * dvec3(grid.voxel_size());
      const dvec3 hi = dvec3(bmin) + dvec3(h.voxel + 1) * dvec3(grid.voxel_size()) +
                       eps_voxels * dvec3(grid.voxel_size());
      const box_hit own = slab(od, dd, lo, hi, std::numeric_limits<double>::infinity());
      REQUIRE(own.hit);
      REQUIRE(double(h.t) >= own.t_in - tol);
      REQUIRE(double(h.t) <= own.t_out + tol);
    } else {
      ++misses;
    }
    // Unambiguous rays: both brute forces name the same voxel, and the DDA must name it too.
    // (On lattice rays several voxels often share the first entry distance; there only the
    // bracket above applies, and `ties` counts the rays where the two brute forces differ.)
    if (grown.hit == shrunk.hit && (!grown.hit || grown.voxel == shrunk.voxel)) {
      if (h.hit == grown.hit && (!h.hit || h.voxel == grown.voxel)) ++clean;
    } else {
      ++ties;
    }
  }
  // Rays that are not near a tie must give exactly the brute-force voxel.
  if (lattice)
    CHECK(ties > rays / 10);  // the lattice rays really do exercise exact ties
  else
    CHECK(clean >= rays - rays / 200);
  CHECK(hits > rays / 4);
  CHECK(misses > rays / 20);
  CHECK(outside_starts > rays / (lattice ? 10 : 3));
}

}  // namespace

TEST_CASE("DDA first hit equals brute force over all occupied voxels (double)", "[visibility][dda]") {
  crosscheck<double>(12345u, 1e-9, 4000);
}

TEST_CASE("DDA first hit equals brute force over all occupied voxels (float)", "[visibility][dda]") {
  crosscheck<float>(777u, 1e-4, 4000);
}

TEST_CASE("DDA equals brute force on lattice rays through edges and corners (double)", "[visibility][dda]") {
  crosscheck<double>(4242u, 1e-9, 4000, true);
}

TEST_CASE("DDA equals brute force on lattice rays through edges and corners (float)", "[visibility][dda]") {
  crosscheck<float>(99u, 1e-4, 4000, true);
}
