// SPDX-License-Identifier: MIT
#include "scene/triangulate.hpp"

#include <glm/geometric.hpp>

#include <cmath>

namespace vplrender {

namespace {

struct p2 {
  double x, y;
};

double cross2(p2 a, p2 b, p2 c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); }

bool same(p2 a, p2 b) { return a.x == b.x && a.y == b.y; }

// Inclusive: a point on an edge blocks the ear, which keeps the result free of overlaps.
bool inside_or_on(p2 a, p2 b, p2 c, p2 p) {
  return cross2(a, b, p) >= 0.0 && cross2(b, c, p) >= 0.0 && cross2(c, a, p) >= 0.0;
}

}  // namespace

triangulation triangulate_polygon(const std::vector<glm::dvec3>& poly, std::size_t max_ear_clip) {
  triangulation out;
  const std::size_t n = poly.size();
  if (n < 3) return out;

  // Newell's method, about the centroid to limit cancellation far from the origin.
  glm::dvec3 centroid(0.0);
  for (const glm::dvec3& p : poly) centroid += p;
  centroid /= static_cast<double>(n);
  glm::dvec3 nrm(0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec3 a = poly[i] - centroid, b = poly[(i + 1) % n] - centroid;
    nrm += glm::dvec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
  }
  const double len = glm::length(nrm);
  if (!(len > 0.0) || !std::isfinite(len)) return out;
  out.normal = nrm / len;
  if (n == 3) {
    out.triangles.push_back({0, 1, 2});
    return out;
  }

  // Project on the plane of the dominant axis, keeping the winding counter-clockwise.
  const glm::dvec3 an = glm::abs(out.normal);
  int ax = 0, ay = 1;
  double sign = out.normal.z;
  if (an.x >= an.y && an.x >= an.z) {
    ax = 1; ay = 2; sign = out.normal.x;
  } else if (an.y >= an.z) {
    ax = 2; ay = 0; sign = out.normal.y;
  }
  std::vector<p2> q(n);
  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec3 d = poly[i] - centroid;
    q[i] = p2{d[ax], sign < 0.0 ? -d[ay] : d[ay]};
  }

  std::vector<std::size_t> ring(n);
  for (std::size_t i = 0; i < n; ++i) ring[i] = i;

  auto fan_rest = [&]() {
    out.fan_fallback = true;
    for (std::size_t i = 1; i + 1 < ring.size(); ++i) out.triangles.push_back({ring[0], ring[i], ring[i + 1]});
    ring.clear();
  };
  if (n > max_ear_clip) {
    fan_rest();
    return out;
  }

  while (ring.size() > 3) {
    const std::size_t r = ring.size();
    bool clipped = false;
    for (std::size_t k = 0; k < r && !clipped; ++k) {
      const std::size_t ip = ring[(k + r - 1) % r], ic = ring[k], in = ring[(k + 1) % r];
      const double c = cross2(q[ip], q[ic], q[in]);
      if (c == 0.0) {  // straight (or a spike of zero width): drop the vertex, no area lost
        ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(k));
        clipped = true;
        break;
      }
      if (c < 0.0) continue;  // reflex
      bool blocked = false;
      for (std::size_t j = 0; j < r && !blocked; ++j) {
        const std::size_t io = ring[j];
        if (io == ip || io == ic || io == in) continue;
        if (same(q[io], q[ip]) || same(q[io], q[ic]) || same(q[io], q[in])) continue;
        blocked = inside_or_on(q[ip], q[ic], q[in], q[io]);
      }
      if (blocked) continue;
      out.triangles.push_back({ip, ic, in});
      ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(k));
      clipped = true;
    }
    if (!clipped) {
      fan_rest();
      return out;
    }
  }
  if (ring.size() == 3 && cross2(q[ring[0]], q[ring[1]], q[ring[2]]) != 0.0)
    out.triangles.push_back({ring[0], ring[1], ring[2]});
  return out;
}

}  // namespace vplrender
