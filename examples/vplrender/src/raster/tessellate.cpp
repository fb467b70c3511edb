// SPDX-License-Identifier: MIT
#include "raster/tessellate.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

namespace vplrender {

double tessellation_angle_for_resolution(int R) { return std::sqrt(2.0 / static_cast<double>(R > 0 ? R : 1)); }

double tessellation_min_edge(const std::vector<triangle>& tris) {
  if (tris.empty()) return 0.0;
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const triangle& t : tris)
    for (const vec3& p : t.p) {
      lo = glm::min(lo, glm::dvec3(p));
      hi = glm::max(hi, glm::dvec3(p));
    }
  return 1e-7 * glm::length(hi - lo);
}

namespace {

// Angle between two directions from the light, by atan2 (accurate for small and large angles).
double angle_between(const glm::dvec3& a, const glm::dvec3& b) {
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

// A corner in double; the normal is interpolated unnormalised (linear, as barycentric
// interpolation of the parent's corners) and normalised on output.
struct corner {
  glm::dvec3 p, n;
  glm::dvec2 uv;
};

corner midpoint(const corner& a, const corner& b) {
  // (a + b) * 0.5 is symmetric in a and b: both triangles sharing an edge get the same point.
  return corner{(a.p + b.p) * 0.5, (a.n + b.n) * 0.5, (a.uv + b.uv) * 0.5};
}

struct pending {
  corner c[3];
  int depth;
};

}  // namespace

std::vector<triangle> tessellate_for_light(const std::vector<triangle>& tris, vec3 light,
                                           const tessellation_params& params, tessellation_stats* stats) {
  std::vector<triangle> out;
  tessellation_stats st;
  st.input = tris.size();
  const glm::dvec3 c(light);
  double min_edge = params.min_edge;
  if (!(min_edge > 0.0) && !tris.empty()) min_edge = tessellation_min_edge(tris);
  // Angle the edge subtends if it must be split, else -1 (depends on the two end points only).
  // The end points are put in a fixed (lexicographic) order first, so the result cannot depend on
  // the edge's direction even if the compiler contracts the cross product into FMAs.
  auto split_angle = [&](const corner& a0, const corner& b0) {
    const bool swap = std::tie(b0.p.x, b0.p.y, b0.p.z) < std::tie(a0.p.x, a0.p.y, a0.p.z);
    const glm::dvec3& a = swap ? b0.p : a0.p;
    const glm::dvec3& b = swap ? a0.p : b0.p;
    if (!(params.max_angle > 0.0) || !(glm::length(a - b) > min_edge)) return -1.0;
    const double ang = angle_between(a - c, b - c);
    return ang > params.max_angle ? ang : -1.0;
  };
  auto emit = [&](const pending& q, const triangle& parent) {
    triangle s;
    s.material = parent.material;
    for (std::size_t k = 0; k < 3; ++k) {
      const corner& v = q.c[k];
      const double ln = glm::length(v.n);
      s.p[k] = vec3(v.p);
      s.n[k] = ln > 0.0 ? vec3(v.n / ln) : parent.n[k];
      s.uv[k] = vec2(v.uv);
    }
    out.push_back(s);
  };
  std::vector<pending> stack;
  for (const triangle& t : tris) {
    pending root{};
    for (std::size_t k = 0; k < 3; ++k) root.c[k] = corner{glm::dvec3(t.p[k]), glm::dvec3(t.n[k]), glm::dvec2(t.uv[k])};
    root.depth = 0;
    stack.push_back(root);
    while (!stack.empty()) {
      const pending q = stack.back();
      stack.pop_back();
      // The edge to halve: the widest (in angle) of those over max_angle; edge e joins corners e, e+1.
      int e = -1;
      double widest = -1.0;
      for (int k = 0; k < 3; ++k) {
        const double ang = split_angle(q.c[k], q.c[(k + 1) % 3]);
        if (ang > widest) {
          widest = ang;
          e = k;
        }
      }
      if (e < 0 || q.depth >= params.max_depth) {
        bool over = false;  // an edge still over the angle (short, or the depth cap): counted
        for (int k = 0; k < 3 && params.max_angle > 0.0; ++k)
          over = over || angle_between(q.c[k].p - c, q.c[(k + 1) % 3].p - c) > params.max_angle;
        if (over) ++st.capped;
        emit(q, t);
        continue;
      }
      // Bisect the widest edge through the opposite corner o: (a, m, o) and (m, b, o) keep the
      // parent's winding.
      const corner& a = q.c[e];
      const corner& b = q.c[(e + 1) % 3];
      const corner& o = q.c[(e + 2) % 3];
      const corner m = midpoint(a, b);
      stack.push_back(pending{{a, m, o}, q.depth + 1});
      stack.push_back(pending{{m, b, o}, q.depth + 1});
    }
  }
  st.output = out.size();
  if (stats) *stats = st;
  return out;
}

}  // namespace vplrender
