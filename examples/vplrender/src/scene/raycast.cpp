// SPDX-License-Identifier: MIT
#include "scene/raycast.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace vplrender {

namespace {

glm::dvec3 d3(const vec3& v) { return glm::dvec3(v); }

// Ericson, Real-Time Collision Detection 5.1.5: closest point on triangle abc to p.
glm::dvec3 closest_point_on_triangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                                     const glm::dvec3& c) {
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const glm::dvec3 bp = p - b;
  const double d3v = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3v >= 0.0 && d4 <= d3v) return b;
  const double vc = d1 * d4 - d3v * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3v <= 0.0) return a + ab * (d1 / (d1 - d3v));
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + ac * (d2 / (d2 - d6));
  const double va = d3v * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3v) >= 0.0 && (d5 - d6) >= 0.0)
    return b + (c - b) * ((d4 - d3v) / ((d4 - d3v) + (d5 - d6)));
  const double denom = va + vb + vc;
  if (!(denom > 0.0)) return a;  // degenerate triangle: any vertex is as good as the next
  const double v = vb / denom, w = vc / denom;
  return a + ab * v + ac * w;
}

}  // namespace

namespace {

// Moller-Trumbore, two-sided: the hit's t (in units of |dir|), or NaN for a miss. The one test
// behind cast_ray and rays_from_point, so that both answer bit for bit alike.
double hit_distance(const triangle& tri, const glm::dvec3& origin, const glm::dvec3& dir) {
  const double miss = std::numeric_limits<double>::quiet_NaN();
  const glm::dvec3 p0 = d3(tri.p[0]);
  const glm::dvec3 e1 = d3(tri.p[1]) - p0, e2 = d3(tri.p[2]) - p0;
  const glm::dvec3 pv = glm::cross(dir, e2);
  const double det = glm::dot(e1, pv);
  if (det == 0.0 || !std::isfinite(det)) return miss;
  const double inv = 1.0 / det;
  const glm::dvec3 tv = origin - p0;
  const double u = glm::dot(tv, pv) * inv;
  if (u < 0.0 || u > 1.0) return miss;
  const glm::dvec3 qv = glm::cross(tv, e1);
  const double v = glm::dot(dir, qv) * inv;
  if (v < 0.0 || u + v > 1.0) return miss;
  return glm::dot(e2, qv) * inv;
}

// Keeps the nearest t > t_min; on equal t the lower index (the order the triangles are tested in).
struct nearest_hit {
  ray_hit best;
  double best_t = std::numeric_limits<double>::infinity();
  void offer(std::size_t i, double t, double t_min) {
    if (t > t_min && t < best_t) {  // false for NaN (a miss)
      best_t = t;
      best.hit = true;
      best.t = t;
      best.triangle = i;
    }
  }
  ray_hit finish(const std::vector<triangle>& tris, const glm::dvec3& dir) {
    if (best.hit) best.back_face = glm::dot(d3(facing_normal(tris[best.triangle])), dir) > 0.0;
    return best;
  }
};

}  // namespace

ray_hit cast_ray(const std::vector<triangle>& tris, const glm::dvec3& origin, const glm::dvec3& dir,
                 double t_min) {
  nearest_hit n;
  for (std::size_t i = 0; i < tris.size(); ++i) n.offer(i, hit_distance(tris[i], origin, dir), t_min);
  return n.finish(tris, dir);
}

rays_from_point::rays_from_point(const std::vector<triangle>& tris, const glm::dvec3& origin)
    : tris_(&tris), origin_(origin), cones_(tris.size()) {
  for (std::size_t i = 0; i < tris.size(); ++i) {
    const triangle& t = tris[i];
    glm::dvec3 v[3];
    double extent = 0.0;
    bool usable = true;
    for (int k = 0; k < 3; ++k) {
      v[k] = d3(t.p[k]) - origin;
      const double l = glm::length(v[k]);
      if (!(l > 0.0) || !std::isfinite(l)) usable = false;  // origin on a vertex, or no finite cone
      extent = std::max(extent, l);
      if (usable) v[k] /= l;
    }
    if (!usable) continue;
    // An origin within rounding of the plane: the test's determinant is noise there and may
    // report hits in directions no cone holds.
    const glm::dvec3 n = glm::cross(d3(t.p[1]) - d3(t.p[0]), d3(t.p[2]) - d3(t.p[0]));
    const double nl = glm::length(n);
    if (!(nl > 0.0) || std::abs(glm::dot(n / nl, origin - d3(t.p[0]))) <= 1e-9 * extent) continue;
    const glm::dvec3 sum = v[0] + v[1] + v[2];
    const double sl = glm::length(sum);
    if (!(sl > 0.0)) continue;
    const glm::dvec3 axis = sum / sl;
    // The cap of the vertices' widest angle holds their spherical triangle while it is below 90
    // degrees (a cap up to a hemisphere is convex on the sphere).
    const double cos_half = std::min({glm::dot(axis, v[0]), glm::dot(axis, v[1]), glm::dot(axis, v[2])}) - 1e-9;
    if (!(cos_half > 0.0)) continue;
    cones_[i] = cone{axis, cos_half};
  }
}

ray_hit rays_from_point::cast(const glm::dvec3& dir, double t_min) const {
  if (!(t_min >= 0.0)) return cast_ray(*tris_, origin_, dir, t_min);  // hits behind: no cone holds them
  const double len = glm::length(dir);
  nearest_hit n;
  for (std::size_t i = 0; i < cones_.size(); ++i) {
    const cone& c = cones_[i];
    if (glm::dot(c.axis, dir) < c.cos_half * len) continue;  // outside the cone: cannot meet it
    n.offer(i, hit_distance((*tris_)[i], origin_, dir), t_min);
  }
  return n.finish(*tris_, dir);
}

std::vector<glm::dvec3> sphere_directions(std::size_t n) {
  std::vector<glm::dvec3> dirs;
  dirs.reserve(n);
  const double pi = 3.14159265358979323846;
  const double golden = pi * (3.0 - std::sqrt(5.0));
  for (std::size_t i = 0; i < n; ++i) {
    const double z = 1.0 - (2.0 * static_cast<double>(i) + 1.0) / static_cast<double>(n);
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = golden * static_cast<double>(i);
    dirs.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
  }
  return dirs;
}

double distance_to_triangle(const triangle& t, const glm::dvec3& p) {
  return glm::length(p - closest_point_on_triangle(p, d3(t.p[0]), d3(t.p[1]), d3(t.p[2])));
}

double distance_to_geometry(const std::vector<triangle>& tris, const glm::dvec3& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const triangle& t : tris) best = std::min(best, distance_to_triangle(t, p));
  return best;
}

point_classification classify_point(const std::vector<triangle>& tris, const glm::dvec3& p,
                                    double surface_tolerance, std::size_t rays) {
  point_classification c;
  c.nearest = distance_to_geometry(tris, p);
  if (c.nearest <= surface_tolerance) {
    c.kind = point_class::on_surface;
    return c;
  }
  const rays_from_point from_p(tris, p);
  for (const glm::dvec3& d : sphere_directions(rays)) {
    const ray_hit h = from_p.cast(d);
    ++c.rays;
    if (!h.hit) continue;
    ++c.hits;
    if (h.back_face) ++c.back_hits;
  }
  if (c.hits > 0 && 4 * c.back_hits >= 3 * c.hits) c.kind = point_class::inside_solid;
  return c;
}

}  // namespace vplrender
