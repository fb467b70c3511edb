// SPDX-License-Identifier: MIT
#include "raster/tessellate.hpp"

#include "raster/on_all_cores.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
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

// The shortcut applies for 0 < max_angle < 1.5 (an edge with u . v <= 0 subtends pi/2 or more):
// an edge whose s / d lies below tan(max_angle) by a relative 1e-9 subtends an angle below
// max_angle by at least 1e-9 sin(max_angle) cos(max_angle) (7e-11 rad at 1.5), far beyond atan2's
// rounding (an ulp: 2e-16 rad at 1), so it decides as atan2 does. The band around the threshold,
// NaN, infinities and u . v <= 0 go to atan2.
edge_angle_test::edge_angle_test(double max_angle_in)
    : max_angle(max_angle_in), tan_below(max_angle_in > 0.0 && max_angle_in < 1.5 ? std::tan(max_angle_in) * (1.0 - 1e-9) : -1.0) {}

bool edge_angle_test::clearly_within(double s, double d) const {
  return tan_below > 0.0 && d > 0.0 && s >= 0.0 && s < d * tan_below;
}

bool edge_angle_test::exceeds(const glm::dvec3& u, const glm::dvec3& v) const {
  const double s = glm::length(glm::cross(u, v)), d = glm::dot(u, v);
  return !clearly_within(s, d) && std::atan2(s, d) > max_angle;
}

namespace {

double angle_of(double sine_part, double cosine_part) { return std::atan2(sine_part, cosine_part); }

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

// What the split knows of an edge (joining corners k and k + 1): the angle it subtends if it must be
// split, else -1, and whether the shortcut of edge_angle_test found it clearly within the angle
// (then no order of its end points can put it over: the kept-edge check skips it).
struct edge_state {
  double angle;
  bool clear;
  bool known;
};

// A triangle waiting to be split, with its edges as far as they are known: a child inherits one
// edge of its parent, and the two children share the edge through the midpoint (the split test
// depends on an edge's end points only, in either order), so each split computes three edges.
struct pending {
  corner c[3];
  edge_state e[3];
  int depth;
};

}  // namespace

void tessellate_append(const triangle* first, const triangle* last, vec3 light, const tessellation_params& params,
                       std::vector<triangle>& out, tessellation_stats& st) {
  st.input += static_cast<std::size_t>(last - first);
  const glm::dvec3 c(light);
  const double min_edge = params.min_edge;
  const edge_angle_test angle_test(params.max_angle);
  // Angle the edge subtends if it must be split, else -1 (depends on the two end points only).
  // The end points are put in a fixed (lexicographic) order first, so the result cannot depend on
  // the edge's direction even if the compiler contracts the cross product into FMAs.
  auto split_angle = [&](const corner& a0, const corner& b0) {
    const bool swap = std::tie(b0.p.x, b0.p.y, b0.p.z) < std::tie(a0.p.x, a0.p.y, a0.p.z);
    const glm::dvec3& a = swap ? b0.p : a0.p;
    const glm::dvec3& b = swap ? a0.p : b0.p;
    if (!(params.max_angle > 0.0) || !(glm::length(a - b) > min_edge)) return edge_state{-1.0, false, true};
    const glm::dvec3 u = a - c, v = b - c;
    const double s = glm::length(glm::cross(u, v)), d = glm::dot(u, v);
    if (angle_test.clearly_within(s, d)) return edge_state{-1.0, true, true};
    const double ang = angle_of(s, d);
    return edge_state{ang > params.max_angle ? ang : -1.0, false, true};
  };
  // Does the edge from corner a to b subtend more than max_angle (a kept edge: short, or the depth
  // cap)? In the corners' own order, as the count of capped triangles always was.
  auto over_angle = [&](const corner& a, const corner& b) { return angle_test.exceeds(a.p - c, b.p - c); };
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
  for (const triangle* it = first; it != last; ++it) {
    const triangle& t = *it;
    pending root{};
    for (std::size_t k = 0; k < 3; ++k) {
      root.c[k] = corner{glm::dvec3(t.p[k]), glm::dvec3(t.n[k]), glm::dvec2(t.uv[k])};
      root.e[k] = edge_state{-1.0, false, false};
    }
    root.depth = 0;
    stack.push_back(root);
    while (!stack.empty()) {
      pending q = stack.back();
      stack.pop_back();
      // The edge to halve: the widest (in angle) of those over max_angle; edge e joins corners e, e+1.
      int e = -1;
      double widest = -1.0;
      for (int k = 0; k < 3; ++k) {
        if (!q.e[k].known) q.e[k] = split_angle(q.c[k], q.c[(k + 1) % 3]);
        if (q.e[k].angle > widest) {
          widest = q.e[k].angle;
          e = k;
        }
      }
      if (e < 0 || q.depth >= params.max_depth) {
        bool over = false;  // an edge still over the angle (short, or the depth cap): counted
        for (int k = 0; k < 3 && params.max_angle > 0.0; ++k)
          over = over || (!q.e[k].clear && over_angle(q.c[k], q.c[(k + 1) % 3]));
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
      const edge_state unknown{-1.0, false, false};
      const edge_state through_m = split_angle(m, o);  // the children's shared edge, m-o / o-m
      stack.push_back(pending{{a, m, o}, {unknown, through_m, q.e[(e + 2) % 3]}, q.depth + 1});
      stack.push_back(pending{{m, b, o}, {unknown, q.e[(e + 1) % 3], through_m}, q.depth + 1});
    }
  }
}

std::vector<triangle> tessellate_for_light(const std::vector<triangle>& tris, vec3 light,
                                           const tessellation_params& params, tessellation_stats* stats) {
  tessellation_params p = params;
  if (!(p.min_edge > 0.0) && !tris.empty()) p.min_edge = tessellation_min_edge(tris);
  std::vector<triangle> out;
  out.reserve(tris.size());
  tessellation_stats st;
  tessellate_append(tris.data(), tris.data() + tris.size(), light, p, out, st);
  st.output = out.size();
  if (stats) *stats = st;
  return out;
}

std::vector<triangle> tessellate_on_all_cores(const std::vector<triangle>& tris, vec3 light, tessellation_params tess,
                                              tessellation_stats* ts) {
  if (!(tess.min_edge > 0.0)) tess.min_edge = tessellation_min_edge(tris);
  const chunk_plan plan = plan_chunks(tris.size());
  if (plan.chunks <= 1 || plan.threads == 1) return tessellate_for_light(tris, light, tess, ts);
  std::vector<std::vector<triangle>> parts(plan.chunks);
  std::vector<tessellation_stats> stats(plan.chunks);
  run_chunks(plan, [&](std::size_t c) {
    const triangle* first = tris.data() + plan.begin(c, tris.size());
    const triangle* last = tris.data() + plan.end(c, tris.size());
    parts[c].reserve(static_cast<std::size_t>(last - first));
    tessellate_append(first, last, light, tess, parts[c], stats[c]);
  });
  std::vector<triangle> out;
  std::size_t n = 0;
  for (const std::vector<triangle>& part : parts) n += part.size();
  out.reserve(n);
  tessellation_stats total;
  for (std::size_t c = 0; c < plan.chunks; ++c) {
    out.insert(out.end(), parts[c].begin(), parts[c].end());
    total.input += stats[c].input;
    total.capped += stats[c].capped;
  }
  total.output = out.size();
  if (ts) *ts = total;
  return out;
}

}  // namespace vplrender
