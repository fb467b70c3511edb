// SPDX-License-Identifier: MIT
// The DPRSM tessellation (tessellate.cpp): every output edge within theta_max at the light, even
// next to the light (the sub-triangle that wrapped over the DPRSM's front face at R = 8, see
// tessellate.hpp); the parent tiled exactly (area, winding, plane); shared edges split alike; the
// split over all cores equals the serial one; the per-edge angle test decides as atan2 does.
#include "cli/options.hpp"
#include "cli/scene_setup.hpp"
#include "raster/render_data.hpp"
#include "raster/tessellate.hpp"

#include <catch2/catch.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <tuple>
#include <utility>
#include <vector>

using namespace vplrender;

namespace {

scene cornell() {
  options o;
  o.scene = "cornell";
  return prepare_scene(o).s;
}

// Positions of two equally long triangle lists whose corners, normals, uvs or materials differ.
std::size_t triangles_differing(const std::vector<triangle>& a, const std::vector<triangle>& b) {
  std::size_t differ = 0;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i)
    differ += (a[i].p != b[i].p || a[i].n != b[i].n || a[i].uv != b[i].uv || a[i].material != b[i].material) ? 1u : 0u;
  return differ;
}

double angle_at(const glm::dvec3& c, const vec3& a, const vec3& b) {
  const glm::dvec3 u = glm::dvec3(a) - c, v = glm::dvec3(b) - c;
  return std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v));
}

glm::dvec3 twice_area(const std::array<vec3, 3>& p) {
  return glm::cross(glm::dvec3(p[1]) - glm::dvec3(p[0]), glm::dvec3(p[2]) - glm::dvec3(p[0]));
}

// Output corners lying on the segment a-b (distance to the segment < eps), sorted.
std::vector<std::array<float, 3>> points_on(const std::vector<triangle>& tris, const vec3& a, const vec3& b, double eps) {
  std::vector<std::array<float, 3>> out;
  const glm::dvec3 A(a), B(b);
  const glm::dvec3 d = B - A;
  for (const triangle& t : tris)
    for (const vec3& p : t.p) {
      const glm::dvec3 P(p);
      const double s = glm::dot(P - A, d) / glm::dot(d, d);
      if (s < -1e-9 || s > 1.0 + 1e-9) continue;
      if (glm::length(P - (A + s * d)) < eps) out.push_back({p.x, p.y, p.z});
    }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace

TEST_CASE("every sub-triangle edge subtends at most theta_max at the light -- also right next to it") {
  const scene s = cornell();
  for (float light_y : {1.9f, 1.99f})  // 0.1 and 0.01 below the ceiling
    for (int R : {8, 64}) {
      INFO("light y " << light_y << ", R " << R);
      const glm::dvec3 c(0.0, light_y, 0.0);
      tessellation_params tp;
      tp.max_angle = tessellation_angle_for_resolution(R);
      tessellation_stats st;
      const std::vector<triangle> out = tessellate_for_light(s.triangles, vec3(c), tp, &st);
      CHECK(st.input == s.triangles.size());
      CHECK(st.output == out.size());
      CHECK(st.capped == 0);
      double worst = 0.0;
      for (const triangle& t : out)
        for (int k = 0; k < 3; ++k) worst = std::max(worst, angle_at(c, t.p[k], t.p[(k + 1) % 3]));
      // The old uniform n x n split left a ~150 degree sub-triangle above the light.
      CHECK(worst <= tp.max_angle * (1.0 + 1e-6));
    }
}

TEST_CASE("sub-triangles tile their parent: same plane, winding, material, total area and corners") {
  const scene s = cornell();
  tessellation_params tp;
  tp.max_angle = tessellation_angle_for_resolution(8);
  const glm::dvec3 c(0.0, 1.99, 0.0);
  for (std::size_t i = 0; i < s.triangles.size(); ++i) {
    const triangle& parent = s.triangles[i];
    const std::vector<triangle> out = tessellate_for_light({parent}, vec3(c), tp);
    REQUIRE(!out.empty());
    const glm::dvec3 pa = twice_area(parent.p);
    const double area = glm::length(pa);
    const glm::dvec3 pn = pa / area;
    double sum = 0.0;
    for (const triangle& t : out) {
      const glm::dvec3 a = twice_area(t.p);
      CHECK(glm::dot(a, pn) > 0.0);  // same winding, never degenerate
      sum += glm::length(a);
      for (const vec3& p : t.p) CHECK(std::abs(glm::dot(glm::dvec3(p) - glm::dvec3(parent.p[0]), pn)) < 1e-5);
      CHECK(t.material == parent.material);
      for (const vec3& n : t.n) CHECK(std::abs(glm::length(n) - 1.0f) < 1e-5f);
    }
    CHECK(sum == Approx(area).epsilon(1e-5));
  }
}

TEST_CASE("two triangles sharing an edge split it at the same points (no T-junction, no crack)") {
  const scene s = cornell();
  tessellation_params tp;
  tp.max_angle = tessellation_angle_for_resolution(16);
  const vec3 light(0.0f, 1.99f, 0.0f);
  const double eps = 1e-6 * bounds(s).diagonal();
  int shared = 0, split = 0;
  for (std::size_t i = 0; i < s.triangles.size(); ++i)
    for (std::size_t j = i + 1; j < s.triangles.size(); ++j)
      for (int ei = 0; ei < 3; ++ei)
        for (int ej = 0; ej < 3; ++ej) {
          const vec3 a = s.triangles[i].p[static_cast<std::size_t>(ei)], b = s.triangles[i].p[static_cast<std::size_t>((ei + 1) % 3)];
          const vec3 c = s.triangles[j].p[static_cast<std::size_t>(ej)], d = s.triangles[j].p[static_cast<std::size_t>((ej + 1) % 3)];
          if (!((a == c && b == d) || (a == d && b == c))) continue;
          ++shared;
          const auto pi = points_on(tessellate_for_light({s.triangles[i]}, light, tp), a, b, eps);
          const auto pj = points_on(tessellate_for_light({s.triangles[j]}, light, tp), a, b, eps);
          INFO("triangles " << i << " and " << j);
          if (pi.size() > 2) ++split;  // the edge was split (the ceiling's and walls' edges are wide)
          CHECK(pi == pj);
        }
  CHECK(shared >= 6);  // each wall / box face is two triangles sharing a diagonal
  CHECK(split >= 6);
}

TEST_CASE("no tessellation when max_angle <= 0 -- and edges shorter than min_edge are left alone (counted)") {
  const scene s = cornell();
  tessellation_params off;
  tessellation_stats st;
  const std::vector<triangle> same = tessellate_for_light(s.triangles, vec3(0.0f, 1.9f, 0.0f), off, &st);
  CHECK(same.size() == s.triangles.size());
  CHECK(st.capped == 0);
  tessellation_params coarse;
  coarse.max_angle = tessellation_angle_for_resolution(512);
  coarse.min_edge = 10.0;  // longer than every edge: nothing may be split
  const std::vector<triangle> kept = tessellate_for_light(s.triangles, vec3(0.0f, 1.9f, 0.0f), coarse, &st);
  CHECK(kept.size() == s.triangles.size());
  CHECK(st.capped > 0);
}

TEST_CASE("tessellate_on_all_cores gives the serial output: same triangles in the same order, same counts") {
  const scene s = cornell();
  // Many input triangles (several chunks per thread) of uneven cost, and a light on the floor: the
  // edges through it are split down to min_edge, which must be the whole mesh's, not a chunk's.
  tessellation_params pre;
  pre.max_angle = tessellation_angle_for_resolution(16);
  const std::vector<triangle> input = tessellate_for_light(s.triangles, vec3(0.3f, 1.0f, -0.2f), pre);
  REQUIRE(input.size() > 200);
  const float floor_y = bounds(input).lo.y;
  for (const vec3 light : {vec3(0.0f, 1.9f, 0.0f), vec3(0.1f, floor_y, 0.2f)}) {
    tessellation_params tess;
    tess.max_angle = tessellation_angle_for_resolution(512);
    tessellation_stats serial_stats, parallel_stats;
    const std::vector<triangle> serial = tessellate_for_light(input, light, tess, &serial_stats);
    const std::vector<triangle> parallel = tessellate_on_all_cores(input, light, tess, &parallel_stats);
    REQUIRE(parallel.size() == serial.size());
    CHECK(triangles_differing(parallel, serial) == 0);
    CHECK(parallel_stats.input == serial_stats.input);
    CHECK(parallel_stats.output == serial_stats.output);
    CHECK(parallel_stats.capped == serial_stats.capped);
    if (light.y == floor_y) CHECK(serial_stats.capped > 0);  // min_edge decided those splits
  }
}

namespace {

// The split as tessellate.hpp states it, written plainly: every edge's angle by atan2 at every
// node, no shortcut, nothing remembered. tessellate_for_light must give exactly its output.
std::vector<triangle> plain_split(const std::vector<triangle>& tris, const glm::dvec3& c, const tessellation_params& p,
                                  tessellation_stats& st) {
  struct corner {
    glm::dvec3 p, n;
    glm::dvec2 uv;
  };
  struct node {
    corner c[3];
    int depth;
  };
  const double min_edge = p.min_edge > 0.0 ? p.min_edge : tessellation_min_edge(tris);
  auto angle = [&](const glm::dvec3& a, const glm::dvec3& b) {
    return std::atan2(glm::length(glm::cross(a - c, b - c)), glm::dot(a - c, b - c));
  };
  auto split_angle = [&](const corner& a0, const corner& b0) {
    const bool swap = std::tie(b0.p.x, b0.p.y, b0.p.z) < std::tie(a0.p.x, a0.p.y, a0.p.z);
    const glm::dvec3& a = swap ? b0.p : a0.p;
    const glm::dvec3& b = swap ? a0.p : b0.p;
    if (!(p.max_angle > 0.0) || !(glm::length(a - b) > min_edge)) return -1.0;
    const double ang = angle(a, b);
    return ang > p.max_angle ? ang : -1.0;
  };
  std::vector<triangle> out;
  st = tessellation_stats{};
  st.input = tris.size();
  for (const triangle& t : tris) {
    std::vector<node> stack{node{{corner{glm::dvec3(t.p[0]), glm::dvec3(t.n[0]), glm::dvec2(t.uv[0])},
                                  corner{glm::dvec3(t.p[1]), glm::dvec3(t.n[1]), glm::dvec2(t.uv[1])},
                                  corner{glm::dvec3(t.p[2]), glm::dvec3(t.n[2]), glm::dvec2(t.uv[2])}},
                                 0}};
    while (!stack.empty()) {
      const node q = stack.back();
      stack.pop_back();
      int e = -1;
      double widest = -1.0;
      for (int k = 0; k < 3; ++k) {
        const double a = split_angle(q.c[k], q.c[(k + 1) % 3]);
        if (a > widest) {
          widest = a;
          e = k;
        }
      }
      if (e < 0 || q.depth >= p.max_depth) {
        bool over = false;
        for (int k = 0; k < 3 && p.max_angle > 0.0; ++k) over = over || angle(q.c[k].p, q.c[(k + 1) % 3].p) > p.max_angle;
        st.capped += over ? 1u : 0u;
        triangle s;
        s.material = t.material;
        for (std::size_t k = 0; k < 3; ++k) {
          const double ln = glm::length(q.c[k].n);
          s.p[k] = vec3(q.c[k].p);
          s.n[k] = ln > 0.0 ? vec3(q.c[k].n / ln) : t.n[k];
          s.uv[k] = vec2(q.c[k].uv);
        }
        out.push_back(s);
        continue;
      }
      const corner &a = q.c[e], &b = q.c[(e + 1) % 3], &o = q.c[(e + 2) % 3];
      const corner m{(a.p + b.p) * 0.5, (a.n + b.n) * 0.5, (a.uv + b.uv) * 0.5};
      stack.push_back(node{{a, m, o}, q.depth + 1});
      stack.push_back(node{{m, b, o}, q.depth + 1});
    }
  }
  st.output = out.size();
  return out;
}

}  // namespace

TEST_CASE("tessellate_for_light gives the plain split's output: every triangle, every count, capped ones too") {
  const scene s = cornell();
  const float floor_y = bounds(s.triangles).lo.y;
  struct config {
    vec3 light;
    int R;
    int max_depth;
  };
  // Near the ceiling, mid-room, on the floor (edges through the light split down to min_edge:
  // capped), and a depth cap that stops splits early (capped).
  for (const config& k : {config{vec3(0.0f, 1.9f, 0.0f), 512, 48}, config{vec3(0.2f, 1.0f, -0.3f), 64, 48},
                          config{vec3(0.1f, floor_y, 0.2f), 128, 48}, config{vec3(0.0f, 1.9f, 0.0f), 512, 5}}) {
    INFO("light y " << k.light.y << ", R " << k.R << ", max_depth " << k.max_depth);
    tessellation_params tp;
    tp.max_angle = tessellation_angle_for_resolution(k.R);
    tp.max_depth = k.max_depth;
    tessellation_stats fast_st, plain_st;
    const std::vector<triangle> fast = tessellate_for_light(s.triangles, k.light, tp, &fast_st);
    const std::vector<triangle> plain = plain_split(s.triangles, glm::dvec3(k.light), tp, plain_st);
    REQUIRE(fast.size() == plain.size());
    CHECK(triangles_differing(fast, plain) == 0);
    CHECK(fast_st.input == plain_st.input);
    CHECK(fast_st.output == plain_st.output);
    CHECK(fast_st.capped == plain_st.capped);
    if (k.light.y == floor_y || k.max_depth < 48) CHECK(plain_st.capped > 0);
  }
}

TEST_CASE("edge_angle_test decides as atan2 does: near the threshold, across magnitudes, on special values") {
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), expo(-30.0, 30.0);
  auto random_dir = [&] {
    glm::dvec3 d;
    do d = glm::dvec3(unit(rng), unit(rng), unit(rng));
    while (!(glm::length(d) > 1e-3));
    return glm::normalize(d);
  };
  for (const double theta : {1e-4, tessellation_angle_for_resolution(4096), tessellation_angle_for_resolution(512),
                             tessellation_angle_for_resolution(8), 1.2, 1.4999, 1.5, 2.0, 0.0, -1.0, nan, inf}) {
    const edge_angle_test test(theta);
    std::size_t cases = 0, differ = 0, shortcut = 0, below = 0, below_shortcut = 0;
    auto check = [&](const glm::dvec3& u, const glm::dvec3& v) {
      const bool expected = std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v)) > theta;
      differ += test.exceeds(u, v) != expected ? 1u : 0u;
      const bool clear = test.clearly_within(glm::length(glm::cross(u, v)), glm::dot(u, v));
      shortcut += clear ? 1u : 0u;
      ++cases;
      return clear;
    };
    for (int k = 0; k < 20000; ++k) {
      // A pair at theta (1 + eps) in a random plane, lengths over 60 decades, and a random pair.
      const glm::dvec3 a = random_dir(), b = glm::normalize(glm::cross(a, random_dir()));
      static const double eps[] = {-1e-6, -1e-8, -2e-9, -1e-9, -5e-10, -1e-12, -1e-15, 0.0,
                                   1e-15, 1e-12, 5e-10, 1e-9, 2e-9, 1e-8, 1e-6};
      const double phi = (std::isfinite(theta) ? theta : 1.0) * (1.0 + eps[k % 15]);
      const double la = std::pow(10.0, expo(rng)), lb = std::pow(10.0, expo(rng));
      const bool clear = check(la * a, lb * (std::cos(phi) * a + std::sin(phi) * b));
      if (eps[k % 15] <= -2e-9) {  // at least 2e-9 below the angle: the shortcut's to decide
        ++below;
        below_shortcut += clear ? 1u : 0u;
      }
      check(la * random_dir(), lb * random_dir());
    }
    for (const glm::dvec3& u : {glm::dvec3(0.0), glm::dvec3(1.0, 0.0, 0.0), glm::dvec3(-1.0, 0.0, 0.0),
                                glm::dvec3(nan, 0.0, 0.0), glm::dvec3(inf, 0.0, 0.0), glm::dvec3(inf, inf, 0.0),
                                glm::dvec3(-inf, 1.0, 0.0), glm::dvec3(1e-300, 0.0, 1e-300), glm::dvec3(1e300, 1e300, 1e300)})
      for (const glm::dvec3& v : {glm::dvec3(0.0), glm::dvec3(1.0, 1e-9, 0.0), glm::dvec3(-1.0, 0.0, 0.0),
                                  glm::dvec3(0.0, 1.0, 0.0), glm::dvec3(0.0, nan, 0.0), glm::dvec3(inf, 1.0, 0.0),
                                  glm::dvec3(1.0, inf, 0.0), glm::dvec3(1e-300, 1e-310, 0.0), glm::dvec3(1e300, 1e299, 0.0)}) {
        check(u, v);
        check(v, u);
      }
    INFO("max_angle " << theta << ": " << cases << " edges, " << shortcut << " decided without atan2");
    CHECK(differ == 0);
    // The shortcut decides every edge 2e-9 or more below the angle where it applies, none elsewhere.
    if (theta > 0.0 && theta < 1.5)
      CHECK(below_shortcut == below);
    else
      CHECK(shortcut == 0);
  }
}
