// SPDX-License-Identifier: MIT
#pragma once
// Triangle meshes and an independent double-precision reference for the BVH tests and benchmarks
// (not part of the library). Header-only, namespace vplkit_test, float meshes (the GPU layout).
//
// The reference (reference_closest) decides what a correct closest hit is, up to the two
// ambiguities no float intersector can resolve:
//  - near an edge: a ray passing within eps * scale of a triangle's edge may hit or miss it;
//  - near a tie: a triangle hit within eps * scale (along the ray) of the closest hit may be
//    reported instead of it.
// It works in double with Pluecker side products and the plane equation, which have nothing in
// common with the Woop test under test.
#include <random_streams.hpp>

#include <vplkit/core/vector.hpp>

#include <glm/mat3x3.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace vplkit_test {

struct tri_mesh {
  std::vector<v3f> positions;
  std::vector<std::uint32_t> indices;

  std::size_t triangle_count() const { return indices.size() / 3; }
  v3f vertex(std::size_t t, int k) const { return positions[indices[3 * t + std::size_t(k)]]; }

  void tri(v3f a, v3f b, v3f c) {
    const auto base = std::uint32_t(positions.size());
    positions.insert(positions.end(), {a, b, c});
    indices.insert(indices.end(), {base, base + 1, base + 2});
  }
  void quad(v3f a, v3f b, v3f c, v3f d) {  // a b c d counter-clockwise, shared vertices
    const auto base = std::uint32_t(positions.size());
    positions.insert(positions.end(), {a, b, c, d});
    indices.insert(indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  }
  // An oriented box of 12 triangles over 8 shared vertices: centre, half extents, rotation
  // (columns); faces outward, or inward (a room).
  void solid_box(v3d centre, v3d half, const glm::dmat3& rot, bool inward = false) {
    const auto base = std::uint32_t(positions.size());
    for (int k = 0; k < 8; ++k) {
      const v3d l((k & 1) ? half.x : -half.x, (k & 2) ? half.y : -half.y, (k & 4) ? half.z : -half.z);
      positions.push_back(v3f(centre + rot * l));
    }
    const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& f : faces) {
      std::uint32_t q[4];
      for (int k = 0; k < 4; ++k) q[k] = base + std::uint32_t(f[inward ? 3 - k : k]);
      indices.insert(indices.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
    }
  }
  // An n x n grid of quads (2 triangles each) over the parallelogram corner + [0,1] u + [0,1] v,
  // with shared vertices, so every interior edge is shared by two triangles; each vertex is
  // place(corner + (i/n) u + (j/n) v).
  template <class Place>
  void grid(v3d corner, v3d u, v3d v, int n, bool flip, Place place) {
    const auto base = std::uint32_t(positions.size());
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) positions.push_back(place(corner + (double(i) / n) * u + (double(j) / n) * v));
    const auto at = [&](int i, int j) { return base + std::uint32_t(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const std::uint32_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
        if (flip)
          indices.insert(indices.end(), {a, c, b, a, d, c});
        else
          indices.insert(indices.end(), {a, b, c, a, c, d});
      }
  }
  void grid(v3d corner, v3d u, v3d v, int n, bool flip = false) {
    grid(corner, u, v, n, flip, [](v3d p) { return v3f(p); });
  }
  // A closed box: centre, half extents, rotation (columns); each face an n x n grid (n a power
  // of two). The faces' border vertices are duplicated, but computed from the same local point
  // (exact for a power-of-two n) by the same transform, so their floats are equal and the box
  // is closed (watertight) where its faces meet.
  void box(v3d centre, v3d half, const glm::dmat3& rot, int n = 1, bool inward = false) {
    const auto place = [&](v3d local) { return v3f(centre + rot * local); };
    for (int axis = 0; axis < 3; ++axis)
      for (int s = -1; s <= 1; s += 2) {
        const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
        v3d c(0.0), u(0.0), v(0.0);
        c[axis] = s * half[axis];
        c[a1] = -half[a1];
        c[a2] = -half[a2];
        u[a1] = 2.0 * half[a1];
        v[a2] = 2.0 * half[a2];
        grid(c, u, v, n, (s < 0) != inward, place);
      }
  }
};

inline glm::dmat3 rotation(double ax, double ay, double az) {
  const double cx = std::cos(ax), sx = std::sin(ax), cy = std::cos(ay), sy = std::sin(ay), cz = std::cos(az),
               sz = std::sin(az);
  const glm::dmat3 rx(1, 0, 0, 0, cx, sx, 0, -sx, cx), ry(cy, 0, -sy, 0, 1, 0, sy, 0, cy),
      rz(cz, sz, 0, -sz, cz, 0, 0, 0, 1);
  return rz * ry * rx;
}

// A random point of a random triangle of m (barycentric, rounded to float, so slightly off the
// plane like a rasterised point), and as its normal the triangle's cross(v1 - v0, v2 - v0) times a
// random factor in [len_lo, len_hi] (normals of any length).
inline void random_surface_point(random_source& rnd, const tri_mesh& m, v3f& p, v3f& n, double len_lo, double len_hi) {
  const std::size_t t = std::size_t(rnd.integer(0, int(m.triangle_count()) - 1));
  double u = rnd.unit(), v = rnd.unit();
  if (u + v > 1) u = 1 - u, v = 1 - v;
  p = (1.0f - float(u) - float(v)) * m.vertex(t, 0) + float(u) * m.vertex(t, 1) + float(v) * m.vertex(t, 2);
  n = glm::cross(m.vertex(t, 1) - m.vertex(t, 0), m.vertex(t, 2) - m.vertex(t, 0)) * float(rnd.uniform(len_lo, len_hi));
}

// n triangles with centres uniform in [0, 1]^3, edge lengths log-uniform in [min_size, max_size]:
// they intersect each other, overlap and vary in size over orders of magnitude.
inline tri_mesh random_soup(random_source& rnd, int n, double min_size, double max_size) {
  tri_mesh m;
  for (int i = 0; i < n; ++i) {
    const v3d c(rnd.unit(), rnd.unit(), rnd.unit());
    const double s = min_size * std::pow(max_size / min_size, rnd.unit());
    m.tri(v3f(c + s * rnd.direction()), v3f(c + s * rnd.direction()), v3f(c + s * rnd.direction()));
  }
  return m;
}

// The closed test box: an inward room [-1, 1]^3 of 16 x 16 quads per face with a rotated box
// (8 x 8 per face) and a tilted thin slab inside.
inline tri_mesh closed_room() {
  tri_mesh m;
  m.box(v3d(0.0), v3d(1.0), glm::dmat3(1.0), 16, true);
  m.box(v3d(0.3, -0.2, 0.1), v3d(0.25, 0.4, 0.2), rotation(0.4, 0.7, 0.2), 8);
  m.box(v3d(-0.5, 0.3, -0.3), v3d(0.3, 0.02, 0.4), rotation(0.1, 0.0, 0.5), 2);
  return m;
}

// ---- the double-precision reference ---------------------------------------------------------

struct ref_ray_triangle_result {
  bool valid = false;   // the ray is not parallel to the triangle's plane
  double t = 0.0;       // where the ray meets the plane
  double margin = 0.0;  // signed distance of the ray's line to the triangle's edges, > 0 inside
};

// In double, from the exact float vertices: the side of the ray's line for each edge line
// (Pluecker: dot(d, cross(p - o, q - o)) = distance between the lines * |d x (q - p)|), turned
// into a distance, so "within eps of an edge" is a length, well defined at grazing angles where
// barycentrics are not.
inline ref_ray_triangle_result ref_ray_triangle(v3d o, v3d d, v3d v0, v3d v1, v3d v2) {
  ref_ray_triangle_result r;
  const v3d n = glm::cross(v1 - v0, v2 - v0);
  const double dn = glm::dot(n, d);
  if (dn == 0.0 || !std::isfinite(dn)) return r;
  r.valid = true;
  r.t = glm::dot(n, v0 - o) / dn;
  const v3d p[3] = {v0, v1, v2};
  double side[3], len[3];
  for (int k = 0; k < 3; ++k) {
    const v3d a = p[k], b = p[(k + 1) % 3];
    side[k] = glm::dot(d, glm::cross(a - o, b - o));
    len[k] = glm::length(glm::cross(d, b - a));
  }
  const double sign = side[0] + side[1] + side[2] >= 0.0 ? 1.0 : -1.0;
  r.margin = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) r.margin = std::min(r.margin, len[k] > 0.0 ? sign * side[k] / len[k] : 0.0);
  return r;
}

// Which answers of a closest-hit query are correct for the ray o + t d, t in (t_min, t_max].
struct reference_answer {
  double t_sure = std::numeric_limits<double>::infinity();  // closest hit at least eps inside a triangle
  int sure = -1;                                            // its triangle (-1: none)
  std::vector<int> candidates;  // triangles that may be reported: at most eps outside, t <= t_sure + tie
  bool miss_ok = true;          // no triangle is hit for sure
  bool acceptable(bool hit, int triangle) const {
    if (!hit) return miss_ok;
    return std::find(candidates.begin(), candidates.end(), triangle) != candidates.end();
  }
};

// eps: relative to `scale` (the scene's size), for the distance of the ray to the edges and for
// ties in t (two hits within eps * scale of each other along the ray).
inline reference_answer reference_closest(const tri_mesh& m, v3f of, v3f df, double t_min, double t_max, double eps,
                                          double scale) {
  const v3d o(of), d(df);
  const double dist = eps * scale, tie = dist / std::sqrt(glm::dot(d, d));
  std::vector<ref_ray_triangle_result> r(m.triangle_count());
  reference_answer a;
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    r[t] = ref_ray_triangle(o, d, v3d(m.vertex(t, 0)), v3d(m.vertex(t, 1)), v3d(m.vertex(t, 2)));
    const auto& h = r[t];
    if (h.valid && h.margin >= dist && h.t > t_min + tie && h.t <= t_max - tie && h.t < a.t_sure) {
      a.t_sure = h.t;
      a.sure = int(t);
    }
  }
  a.miss_ok = a.sure < 0;
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    const auto& h = r[t];
    if (h.valid && h.margin >= -dist && h.t > t_min - tie && h.t <= t_max + tie && h.t <= a.t_sure + tie)
      a.candidates.push_back(int(t));
  }
  return a;
}

// Largest extent of the mesh's bounding box.
inline double mesh_scale(const tri_mesh& m) {
  v3f lo = m.positions[0], hi = m.positions[0];
  for (const v3f& p : m.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const v3f e = hi - lo;
  return double(std::max(e.x, std::max(e.y, e.z)));
}

}  // namespace vplkit_test
