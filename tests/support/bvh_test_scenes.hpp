#pragma once
// Triangle meshes and an independent double-precision reference for the BVH tests and benchmarks
// (not part of the library). Header-only, namespace vplkit_test, float meshes (the GPU layout).
//
// The reference (reference_closest) decides what a correct closest hit is, up to the two
// ambiguities no float intersector can resolve:
//  - near an edge: a ray whose exact barycentrics lie within `eps` of 0 on a triangle may hit or
//    miss it;
//  - near a tie: triangles hit at parameters within a relative `eps` of the closest may be
//    reported instead of it.
// It solves o + t d = v0 + b1 (v1 - v0) + b2 (v2 - v0) in double by Cramer's rule (Moeller-
// Trumbore without any epsilon), which has nothing in common with the Woop test under test.
#include <vplkit/core/vector.hpp>

#include <glm/mat3x3.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace vplkit_test {

using v3f = vplkit::vec3<float>;
using v3d = vplkit::vec3<double>;

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

// mt19937's output is fixed by the standard; the mapping to floats is ours, so the inputs are
// the same with every standard library.
struct random_source {
  std::mt19937 g;
  explicit random_source(std::uint32_t seed) : g(seed) {}
  double unit() { return double(g() >> 5) * (1.0 / 134217728.0); }  // [0, 1), 27 bits
  double uniform(double a, double b) { return a + (b - a) * unit(); }
  int integer(int lo, int hi) { return lo + int(g() % std::uint32_t(hi - lo + 1)); }
  double normal() {
    const double u1 = 1.0 - unit(), u2 = unit();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
  }
  v3d direction() {
    v3d d(0.0);
    do d = v3d(normal(), normal(), normal());
    while (glm::dot(d, d) < 1e-6);
    return d / std::sqrt(glm::dot(d, d));
  }
  v3f point_in(v3d lo, v3d hi) { return v3f(uniform(lo.x, hi.x), uniform(lo.y, hi.y), uniform(lo.z, hi.z)); }
};

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
  bool valid = false;  // det != 0 (the ray is not parallel to the triangle's plane)
  double t = 0.0;
  double b0 = 0.0, b1 = 0.0, b2 = 0.0;  // barycentrics of the ray / plane point (may be < 0)
};

inline ref_ray_triangle_result ref_ray_triangle(v3d o, v3d d, v3d v0, v3d v1, v3d v2) {
  ref_ray_triangle_result r;
  const v3d e1 = v1 - v0, e2 = v2 - v0, p = glm::cross(d, e2);
  const double det = glm::dot(e1, p);
  if (det == 0.0 || !std::isfinite(det)) return r;
  const v3d s = o - v0, q = glm::cross(s, e1);
  r.valid = true;
  r.b1 = glm::dot(s, p) / det;
  r.b2 = glm::dot(d, q) / det;
  r.b0 = 1.0 - r.b1 - r.b2;
  r.t = glm::dot(e2, q) / det;
  return r;
}

// Which answers of a closest-hit query are correct for the ray o + t d, t in (t_min, t_max].
struct reference_answer {
  double t_sure = std::numeric_limits<double>::infinity();  // closest hit inside every triangle by >= eps
  int sure = -1;                                            // its triangle (-1: none)
  std::vector<int> candidates;  // triangles that may be reported: within eps of their edges, t <= t_sure (1 + eps)
  bool miss_ok = true;          // no triangle is hit for sure
  bool acceptable(bool hit, int triangle) const {
    if (!hit) return miss_ok;
    return std::find(candidates.begin(), candidates.end(), triangle) != candidates.end();
  }
};

// eps: relative, on barycentrics and on t (a tie is t within eps * (t + scale / |d|)).
inline reference_answer reference_closest(const tri_mesh& m, v3f of, v3f df, double t_min, double t_max, double eps,
                                          double scale) {
  const v3d o(of), d(df);
  const double tie = eps * scale / std::sqrt(glm::dot(d, d));
  std::vector<ref_ray_triangle_result> r(m.triangle_count());
  reference_answer a;
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    r[t] = ref_ray_triangle(o, d, v3d(m.vertex(t, 0)), v3d(m.vertex(t, 1)), v3d(m.vertex(t, 2)));
    const auto& h = r[t];
    if (!h.valid) continue;
    const double bmin = std::min(h.b0, std::min(h.b1, h.b2));
    if (bmin >= eps && h.t > t_min + eps * (h.t + tie) && h.t <= t_max - eps * (h.t + tie) && h.t < a.t_sure) {
      a.t_sure = h.t;
      a.sure = int(t);
    }
  }
  a.miss_ok = a.sure < 0;
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    const auto& h = r[t];
    if (!h.valid) continue;
    const double bmin = std::min(h.b0, std::min(h.b1, h.b2));
    const double slack = eps * (h.t + tie) + tie;
    if (bmin >= -eps && h.t > t_min - slack && h.t <= t_max + slack && h.t <= a.t_sure + eps * a.t_sure + tie)
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
