// SPDX-License-Identifier: MIT
// CPU/GPU parity of the triangle voxel grid: the GPU construction (voxelize.comp modes 0, 1, 2 and
// prefix_sum.comp, driven by support/headless_gl/voxelize_gpu.cpp) against voxelize_triangles,
// and the GLSL queries (triangle_voxel_query.glsl) against the C++ ones (T = float) on the same
// uploaded grid.
// Bounds:
// - prefix_sum.comp: exact (integers).
// - construction: the GPU converts and tests in float where the C++ uses double (as for the
//   occupancy, parity_visibility_test), so a (voxel, triangle) pair may differ only where the
//   double SAT is within float rounding of flipping: each differing pair must lie within 2e-5
//   voxel of the margin shell (flip margin by bisection), and there may be a handful. Every other
//   voxel lists the same triangles (as sets: the GPU's order is the atomics').
// - queries: bit for bit where division and sqrt are correctly rounded (software renderers; this
//   machine): visible, hit, triangle, t and point all equal; with the brick level
//   (VPLKIT_VOXEL_BRICKS, voxel_bricks.glsl) and without it against the C++ with its bricks. Elsewhere an answer may differ only
//   at a near-tie (an end within 1e-4 voxel of the end tolerance, a crossing within 1e-4 voxel of
//   a grown edge), counted and printed.
#include "parity_harness.hpp"
#include "parity_fma_model.hpp"
#include "parity_forward_error.hpp"

#include <headless_gl/compute.hpp>
#include <headless_gl/voxelize_gpu.hpp>

#include <vplkit/visibility/triangle_box_overlap.hpp>
#include <vplkit/visibility/triangle_voxel_query.hpp>
#include <vplkit/visibility/voxelize.hpp>
#include <vplkit/visibility/voxelize_triangles.hpp>

#include <triangle_scene_reference.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace {

using vplkit::ivec3;
using v3f = glm::vec3;
using v3d = glm::dvec3;

struct float4 {
  float x, y, z, w;
};
float4 f4(v3f v, float w = 0.0f) { return {v.x, v.y, v.z, w}; }

struct mesh {
  std::vector<v3f> p;
  std::vector<std::uint32_t> idx;
  void tri(v3d a, v3d b, v3d c) {
    const auto s = std::uint32_t(p.size());
    for (v3d q : {a, b, c}) p.push_back(v3f(q));
    idx.insert(idx.end(), {s, s + 1, s + 2});
  }
  void quad(v3d a, v3d b, v3d c, v3d d) {
    const auto s = std::uint32_t(p.size());
    for (v3d q : {a, b, c, d}) p.push_back(v3f(q));
    idx.insert(idx.end(), {s, s + 1, s + 2, s, s + 2, s + 3});
  }
  // A box of half size h about c, rotated by `a` about z then `b` about x.
  void box(v3d c, v3d h, double a, double b) {
    auto r = [&](v3d q) {
      q = v3d(std::cos(a) * q.x - std::sin(a) * q.y, std::sin(a) * q.x + std::cos(a) * q.y, q.z);
      return c + v3d(q.x, std::cos(b) * q.y - std::sin(b) * q.z, std::sin(b) * q.y + std::cos(b) * q.z);
    };
    v3d v[8];
    for (int k = 0; k < 8; ++k) v[k] = r(v3d(k & 1 ? h.x : -h.x, k & 2 ? h.y : -h.y, k & 4 ? h.z : -h.z));
    quad(v[0], v[2], v[3], v[1]);
    quad(v[4], v[5], v[7], v[6]);
    quad(v[0], v[1], v[5], v[4]);
    quad(v[2], v[6], v[7], v[3]);
    quad(v[0], v[4], v[6], v[2]);
    quad(v[1], v[3], v[7], v[5]);
  }
};

mesh random_mesh(std::uint32_t seed, int n, double lo, double hi) {
  std::mt19937 g(seed);
  std::uniform_real_distribution<double> u(lo, hi), s(-1.0, 1.0);
  mesh m;
  for (int i = 0; i < n; ++i) {
    const double size = i % 10 == 0 ? 0.5 * (hi - lo) : (i % 3 == 0 ? 0.01 : 0.08) * (hi - lo);
    const v3d c(u(g), u(g), u(g));
    v3d q[3];
    for (v3d& x : q) x = c + size * v3d(s(g), s(g), s(g));
    if (i % 37 == 0) q[2] = q[1];  // degenerate
    m.tri(q[0], q[1], q[2]);
  }
  return m;
}

// The room of the renderer's cornell (floor, ceiling, walls) with two rotated blocks.
mesh room_mesh() {
  mesh m;
  m.quad(v3d(-1, 0, -1), v3d(1, 0, -1), v3d(1, 0, 3), v3d(-1, 0, 3));
  m.quad(v3d(-1, 2, -1), v3d(-1, 2, 3), v3d(1, 2, 3), v3d(1, 2, -1));
  m.quad(v3d(-1, 0, -1), v3d(-1, 2, -1), v3d(1, 2, -1), v3d(1, 0, -1));
  m.quad(v3d(-1, 0, 3), v3d(1, 0, 3), v3d(1, 2, 3), v3d(-1, 2, 3));
  m.quad(v3d(-1, 0, -1), v3d(-1, 0, 3), v3d(-1, 2, 3), v3d(-1, 2, -1));
  m.quad(v3d(1, 0, -1), v3d(1, 2, -1), v3d(1, 2, 3), v3d(1, 0, 3));
  m.box(v3d(0.35, 0.3, 0.25), v3d(0.3, 0.3, 0.3), -0.3, 0.0);
  m.box(v3d(-0.35, 0.6, -0.4), v3d(0.3, 0.6, 0.3), 0.3, 0.0);
  return m;
}

vplkit::gl::gpu_voxelize_input input_of(const mesh& m, v3f bmin, v3f bmax, ivec3 res) {
  vplkit::gl::gpu_voxelize_input in;
  in.bounds_min = bmin;
  in.bounds_max = bmax;
  in.resolution = res;
  in.positions = &m.p;
  in.indices = &m.idx;
  in.margin_voxels = float(vplkit::voxelize_default_margin);
  return in;
}

// The smallest margin (voxels, up to cap) at which the double SAT marks voxel c for triangle t.
double flip_margin(v3f bmin_f, v3f bmax_f, ivec3 res, const mesh& m, std::size_t t, ivec3 c, double cap) {
  const v3d bmin(bmin_f), size = (v3d(bmax_f) - bmin) / v3d(res);
  v3d v[3];
  for (int k = 0; k < 3; ++k) v[k] = (v3d(m.p[m.idx[3 * t + std::size_t(k)]]) - bmin) / size;
  const v3d centre = v3d(c) + v3d(0.5);
  if (!vplkit::triangle_box_overlap(centre, v3d(0.5 + cap), v[0], v[1], v[2])) return cap + 1.0;
  double lo = 0.0, hi = cap;
  if (vplkit::triangle_box_overlap(centre, v3d(0.5), v[0], v[1], v[2])) return 0.0;
  while (hi - lo > 1e-9) {
    const double mid = 0.5 * (lo + hi);
    (vplkit::triangle_box_overlap(centre, v3d(0.5 + mid), v[0], v[1], v[2]) ? hi : lo) = mid;
  }
  return hi;
}

std::vector<std::uint32_t> list_of(const vplkit::triangle_voxel_view<float>& v, ivec3 c) {
  const std::int64_t r = vplkit::voxel_occupied_index(v.grid, v.rank, c);
  if (r < 0) return {};
  std::vector<std::uint32_t> l(v.entries + v.offsets[r], v.entries + v.offsets[r + 1]);
  std::sort(l.begin(), l.end());
  return l;
}

void check_construction(const mesh& m, v3f bmin, v3f bmax, ivec3 res, const std::string& what,
                        std::size_t max_pairs) {
  vplkit::parity::context();
  const auto cpu = vplkit::voxelize_triangles(bmin, bmax, res, m.p.data(), m.p.size(), m.idx.data(), m.idx.size());
  double ms = 0.0;
  const auto gpu = vplkit::gl::voxelize_triangles_on_gpu(input_of(m, bmin, bmax, res), &ms);  // validated on adoption
  const auto cv = cpu.view(), gv = gpu.view();
  const double margin = vplkit::voxelize_default_margin;
  std::size_t differing = 0, far = 0, same_voxels = 0;
  double worst = 0.0;
  for (int z = 0; z < res.z; ++z)
    for (int y = 0; y < res.y; ++y)
      for (int x = 0; x < res.x; ++x) {
        const ivec3 c(x, y, z);
        const auto a = list_of(cv, c), b = list_of(gv, c);
        if (a == b) {
          ++same_voxels;
          continue;
        }
        std::vector<std::uint32_t> diff;
        std::set_symmetric_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(diff));
        REQUIRE(std::adjacent_find(b.begin(), b.end()) == b.end());  // no triangle listed twice
        for (std::uint32_t t : diff) {
          ++differing;
          const double fm = flip_margin(bmin, bmax, res, m, t, c, 0.01);
          worst = std::max(worst, std::abs(fm - margin));
          if (std::abs(fm - margin) > 2e-5) {
            ++far;
            UNSCOPED_INFO("voxel (" << x << ", " << y << ", " << z << ") triangle " << t << ": flip margin " << fm);
          }
        }
      }
  std::cout << "  triangle voxels " << what << ": " << cpu.entries().size() << " entries on the CPU, "
            << gpu.entries().size() << " on the GPU (" << ms << " ms); differing (voxel, triangle) pairs: " << differing
            << " (bound " << max_pairs << "), worst |flip margin - margin| " << worst << " voxel (bound 2e-05)\n";
  CHECK(far == 0);
  CHECK(differing <= max_pairs);
  CHECK(cpu.entries().size() > 0);
  CHECK(gpu.triangles().size() == cpu.triangles().size());
  CHECK(std::memcmp(gpu.triangles().data(), cpu.triangles().data(),
                    cpu.triangles().size() * sizeof(vplkit::voxel_triangle<float>)) == 0);
}

// ---- queries ------------------------------------------------------------------------------------

struct query {  // std430 { vec4 x_mode; vec4 y_tmax; vec4 params; }
  float4 x_mode;  // xyz: x; w: 0 default tolerance overloads, 1 explicit
  float4 y_tmax;  // xyz: y; w: t_max of the first hit (x towards y)
  float4 params;  // x: end tolerance (voxels)
};
struct query_out {  // std430, 8 scalars
  std::uint32_t visible, hit, triangle;
  float t, px, py, pz, pad;
};
static_assert(sizeof(query_out) == 32, "std430 layout");

// With bricks: VPLKIT_VOXEL_BRICKS defined first and the brick words at binding 8.
const std::string query_kernel_body = R"(
#include "vplkit/visibility/triangle_voxel_query.glsl"
struct query { vec4 x_mode; vec4 y_tmax; vec4 params; };
struct query_out { uint visible; uint hit; uint triangle; float t; float px; float py; float pz; float pad; };
layout(std430, binding = 0) readonly buffer Queries { query q[]; };
layout(std430, binding = 1) writeonly buffer Out { query_out result[]; };
layout(std430, binding = 2) readonly buffer Words { uint words[]; };
layout(std430, binding = 3) readonly buffer Grid { vec4 gmin; vec4 gmax; ivec4 gres; };
layout(std430, binding = 4) readonly buffer Rank { uint rank_words[]; };
layout(std430, binding = 5) readonly buffer Offsets { uint offsets[]; };
layout(std430, binding = 6) readonly buffer Entries { uint entries[]; };
layout(std430, binding = 7) readonly buffer Triangles { vec4 triangles[]; };
uint vplkit_load_voxel_word(uint i) { return words[i]; }
#ifdef VPLKIT_VOXEL_BRICKS
layout(std430, binding = 8) readonly buffer Bricks { uint bricks[]; };
uint vplkit_load_voxel_brick_word(uint i) { return bricks[i]; }
#endif
uint vplkit_load_voxel_rank(uint i) { return rank_words[i]; }
uint vplkit_load_voxel_offset(uint i) { return offsets[i]; }
uint vplkit_load_voxel_entry(uint i) { return entries[i]; }
vec4 vplkit_load_voxel_triangle(uint i) { return triangles[i]; }
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= VPLKIT_PARITY_COUNT) return;
  vplkit_voxel_grid g = vplkit_voxel_grid(gmin.xyz, gmax.xyz, gres.xyz);
  query k = q[i];
  vec3 x = k.x_mode.xyz, y = k.y_tmax.xyz;
  bool explicit_tol = k.x_mode.w != 0.0;
  bool v = explicit_tol ? vplkit_triangle_voxel_visible(g, x, y, k.params.x) : vplkit_triangle_voxel_visible(g, x, y);
  vplkit_triangle_voxel_hit h = explicit_tol ? vplkit_triangle_voxel_first_hit(g, x, y - x, k.y_tmax.w, k.params.x)
                                             : vplkit_triangle_voxel_first_hit(g, x, y - x, k.y_tmax.w);
  result[i] = query_out(v ? 1u : 0u, h.hit ? 1u : 0u, h.triangle, h.t, h.point.x, h.point.y, h.point.z, 0.0);
}
)";

// Where the first hits of the two sides differ (hit or not, or which triangle), are both right up
// to rounding? Judged in double (triangle_scene_reference.hpp) with the rules of
// triangle_voxel_first_hit moved by delta: the end rule's tolerance and the edge slack each way,
// and a triangle counts as first when it crosses within delta of the first crossing. A hit/miss
// difference is a tie when the loosened rules hit within t_max + delta and the tightened ones
// miss within t_max - delta; a triangle difference when both triangles cross, under the loosened
// rules, within delta of the loosened first crossing.
bool first_hit_near_tie(const std::vector<vplkit_test::ref_triangle>& tris, const v3d& x, const v3d& y, double t_max,
                        double end_tol, double grow, double delta, const query_out& a, const query_out& b) {
  if (a.hit == b.hit && (a.hit == 0 || a.triangle == b.triangle)) return true;
  const v3d d = glm::normalize(y - x);
  auto crossing = [&](std::size_t t, double tol, double g) {
    v3d n;
    double c;
    if (t >= tris.size() || !vplkit_test::ref_plane(tris[t], n, c)) return std::numeric_limits<double>::infinity();
    const double d0 = glm::dot(n, x) - c, den = glm::dot(n, d);
    if (!(std::abs(d0) > tol) || den == 0.0) return std::numeric_limits<double>::infinity();
    const double s = -d0 / den;
    return s > 0.0 && vplkit_test::ref_inside(tris[t], n, x + s * d, g) ? s : std::numeric_limits<double>::infinity();
  };
  const double loose = vplkit_test::first_hit(tris, x, d, end_tol - delta, grow + delta);
  if (a.hit != b.hit) {
    const double tight = vplkit_test::first_hit(tris, x, d, end_tol + delta, std::max(0.0, grow - delta));
    return loose <= t_max + delta && !(tight <= t_max - delta);
  }
  return crossing(a.triangle, end_tol - delta, grow + delta) <= loose + delta &&
         crossing(b.triangle, end_tol - delta, grow + delta) <= loose + delta;
}

query_out cpu_query(const vplkit::triangle_voxel_view<float>& v, const query& k) {
  const v3f x(k.x_mode.x, k.x_mode.y, k.x_mode.z), y(k.y_tmax.x, k.y_tmax.y, k.y_tmax.z);
  const bool explicit_tol = k.x_mode.w != 0.0f;
  const float tol = explicit_tol ? k.params.x : float(vplkit::triangle_voxel_default_end_tolerance);
  const bool vis = vplkit::triangle_voxel_visible(v, x, y, tol);
  const auto h = vplkit::triangle_voxel_first_hit(v, x, y - x, k.y_tmax.w, tol);
  return {vis ? 1u : 0u, h.hit ? 1u : 0u, h.triangle, h.t, h.point.x, h.point.y, h.point.z, 0.0f};
}

void check_queries(const mesh& m, v3f bmin, v3f bmax, ivec3 res, std::uint32_t seed, const std::string& what_grid,
                   bool bricks) {
  const std::string what = what_grid + (bricks ? ", with bricks" : ", without bricks");
  const auto grid = vplkit::voxelize_triangles(bmin, bmax, res, m.p.data(), m.p.size(), m.idx.data(), m.idx.size());
  const auto v = grid.view();
  const auto tris = vplkit_test::ref_triangles(m.p, m.idx);
  std::mt19937 g(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::uniform_int_distribution<std::size_t> pick(0, tris.size() - 1);
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<query> qs;
  for (int i = 0; i < 40000; ++i) {
    auto point = [&](int kind) {
      if (kind == 0) return v3f(v3d(bmin) + v3d(u(g), u(g), u(g)) * v3d(bmax - bmin));
      return v3f(vplkit_test::point_on(tris[pick(g)], g));
    };
    const v3f x = point(i % 5 == 0 ? 0 : 1), y = point(i % 7 == 0 ? 0 : 1);
    const float mode = i % 3 == 0 ? 1.0f : 0.0f;
    const float tol = float(u(g) * 0.2);
    const float t_max = i % 4 == 0 ? float(u(g)) * glm::length(y - x) : inf;
    qs.push_back({f4(x, mode), f4(y, t_max), {tol, 0, 0, 0}});
  }
  // Hard cases: x == y, non-finite ends, zero direction, negative t_max, ends on the junction edges.
  const v3f c = 0.5f * (bmin + bmax);
  qs.push_back({f4(c), f4(c, inf), {0, 0, 0, 0}});
  qs.push_back({f4(v3f(nan, 0, 0)), f4(c, inf), {0, 0, 0, 0}});
  qs.push_back({f4(c), f4(v3f(inf, 0, 0), inf), {0, 0, 0, 0}});
  qs.push_back({f4(c), f4(c + v3f(1, 0, 0), -1.0f), {0, 0, 0, 0}});
  for (std::size_t t = 0; t < tris.size(); ++t)
    for (int k = 0; k < 3; ++k)
      qs.push_back({f4(v3f(tris[t].v[k])), f4(v3f(tris[(t + 7) % tris.size()].v[(k + 1) % 3]), inf), {0, 0, 0, 0}});

  std::vector<float4> tri_rows(4 * grid.triangles().size());
  std::memcpy(tri_rows.data(), grid.triangles().data(), tri_rows.size() * sizeof(float4));
  struct grid_params {
    float4 bmin, bmax;
    std::int32_t res[4];
  } gp{f4(bmin), f4(bmax), {res.x, res.y, res.z, 0}};
  std::vector<std::uint32_t> offsets = grid.offsets(), entries = grid.entries();
  if (entries.empty()) entries.push_back(0u);
  REQUIRE(v.bricks != nullptr);  // the C++ side always jumps over empty bricks
  const auto gpu = vplkit::parity::run_compute<query_out>(
      (bricks ? "#define VPLKIT_VOXEL_BRICKS\n" : "") + query_kernel_body, {64, 1, 1},
      {vplkit::parity::input(0, qs), vplkit::parity::input(2, grid.occupancy().words()),
       vplkit::parity::input(3, std::vector<grid_params>{gp}), vplkit::parity::input(4, grid.rank()),
       vplkit::parity::input(5, offsets), vplkit::parity::input(6, entries), vplkit::parity::input(7, tri_rows),
       vplkit::parity::input(8, grid.bricks())},
      1, qs.size());
  // Bit for bit where the device rounds like the reference (llvmpipe against the plain C++).
  const bool exact = vplkit::gl::is_software_renderer() && !vplkit_test::reference_contracts;
  const double L = double(grid.occupancy().voxel_length());
  std::size_t differ = 0, ties = 0, visible = 0, hits = 0;
  vplkit::parity::series<float> floats;  // t and the point, where both sides hit the same triangle
  std::vector<double> float_bound;
  std::vector<std::size_t> float_query;
  for (std::size_t i = 0; i < qs.size(); ++i) {
    const query_out a = gpu[i], b = cpu_query(v, qs[i]);
    visible += b.visible;
    hits += b.hit;
    const bool same_answer = a.visible == b.visible && a.hit == b.hit && a.triangle == b.triangle;
    const bool same = same_answer && std::memcmp(&a.t, &b.t, 4) == 0 && std::memcmp(&a.px, &b.px, 12) == 0;
    if (same) continue;
    if (same_answer && !exact) {
      // The same triangle: t = -d0 / den and the point origin + t d differ only by rounding.
      // Bound each from the operation chain of triangle_voxel_first_hit (parity_forward_error.hpp):
      // d0 = n . origin - offset, den = n . d with d the unit direction (dda_unit_direction).
      const v3f x(qs[i].x_mode.x, qs[i].x_mode.y, qs[i].x_mode.z), y(qs[i].y_tmax.x, qs[i].y_tmax.y, qs[i].y_tmax.z);
      std::vector<double> bounds(4, 0.0);
      if (b.hit) {
        using vplkit_test::fe;
        using vplkit_test::fe3;
        const auto& tri = v.triangles[b.triangle];
        const fe3 n = vplkit_test::fe3_of(tri.plane.normal), o = vplkit_test::fe3_of(x);
        const v3f dir = y - x;  // one rounding, the same on both sides
        const fe3 d = vplkit_test::fe_unit_vector(vplkit_test::fe3_of(dir));
        const fe d0 = vplkit_test::fe_dot(n, o) - fe(double(tri.plane.offset));
        const fe den = vplkit_test::fe_dot(n, d);
        const fe t = fe(0.0) - d0 / den;
        bounds[0] = 2 * t.e;
        for (int k = 0; k < 3; ++k) bounds[std::size_t(k) + 1] = 2 * (o[k] + t * d[k]).e;
      }
      const float ga[4] = {a.t, a.px, a.py, a.pz}, ca[4] = {b.t, b.px, b.py, b.pz};
      for (int k = 0; k < 4; ++k) {
        floats.add(ga[k], ca[k]);
        float_bound.push_back(bounds[std::size_t(k)]);
        float_query.push_back(i);
      }
      continue;
    }
    ++differ;
    const v3d x(qs[i].x_mode.x, qs[i].x_mode.y, qs[i].x_mode.z), y(qs[i].y_tmax.x, qs[i].y_tmax.y, qs[i].y_tmax.z);
    const double tol = (qs[i].x_mode.w != 0.0f ? double(qs[i].params.x) : vplkit::triangle_voxel_default_end_tolerance) * L;
    const double slack = vplkit::triangle_voxel_edge_slack * L, delta = 1e-4 * L;
    const bool tie = (a.visible == b.visible || vplkit_test::segment_near_tie(tris, x, y, tol, slack, delta)) &&
                     first_hit_near_tie(tris, x, y, double(qs[i].y_tmax.w), tol, slack, delta, a, b);
    ties += tie;
    INFO(what << " query " << i << ": gpu visible " << a.visible << " hit " << a.hit << " tri " << a.triangle << " t "
              << vplkit::parity::show(a.t) << " | cpu visible " << b.visible << " hit " << b.hit << " tri "
              << b.triangle << " t " << vplkit::parity::show(b.t));
    CHECK((!exact && tie));
  }
  if (!exact) {
    VPLKIT_CHECK_PARITY(vplkit_test::compare_within_bounds(
        floats, float_bound,
        [&](std::size_t k) {
          const query& q = qs[float_query[k]];
          return "query " + std::to_string(float_query[k]) + " x " +
                 vplkit::parity::show3(v3f(q.x_mode.x, q.x_mode.y, q.x_mode.z)) + " y " +
                 vplkit::parity::show3(v3f(q.y_tmax.x, q.y_tmax.y, q.y_tmax.z));
        },
        what + ": t, point where the triangle is the same"));
  }
  std::cout << "  triangle voxel queries " << what << ": " << qs.size() << " pairs (" << visible << " visible, " << hits
            << " first hits), " << differ << " differ (" << ties << " near-ties; "
            << (exact ? "bit-identical required on this software renderer" : "near-ties allowed") << ")\n";
  CHECK(visible > qs.size() / 10);
  CHECK(visible < qs.size() * 9 / 10);
}

}  // namespace

TEST_CASE("prefix_sum.comp: exclusive sums and bit-count rank equal the C++") {
  vplkit::parity::context();
  std::mt19937 g(17);
  for (std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(255), std::size_t(16384), std::size_t(16385),
                        std::size_t(100003)}) {
    std::vector<std::uint32_t> in(n);
    for (auto& w : in) w = g() & (n % 2 ? 0xFFFFFFFFu : 0x3FFu);
    if (in.empty()) in.push_back(0u);  // a non-empty buffer; count stays n
    // Through the support driver's own path: rank of words (bit count) and offsets (values + total).
    const std::vector<std::uint32_t> rank_cpu = vplkit::voxel_occupancy_rank(in.data(), n);
    std::vector<std::uint32_t> sums_cpu(n + 1, 0u);
    std::uint64_t total = 0;
    for (std::size_t i = 0; i < n; ++i) {
      sums_cpu[i] = std::uint32_t(total);
      total += in[i] & 0x3FFu;
    }
    sums_cpu[n] = std::uint32_t(total);
    std::vector<std::uint32_t> small(in.size());
    for (std::size_t i = 0; i < in.size(); ++i) small[i] = in[i] & 0x3FFu;
    const auto rank_gpu = vplkit::gl::prefix_sum_on_gpu(in, n, true, false);
    const auto sums_gpu = vplkit::gl::prefix_sum_on_gpu(small, n, false, true);
    INFO("n = " << n);
    REQUIRE(std::vector<std::uint32_t>(rank_gpu.begin(), rank_gpu.begin() + std::ptrdiff_t(n)) == rank_cpu);
    REQUIRE(sums_gpu == sums_cpu);
  }
}

TEST_CASE("voxelize.comp modes 1 and 2: triangle lists equal voxelize_triangles") {
  check_construction(random_mesh(41, 2000, -1.0, 2.0), v3f(-1.3f, -0.9f, -1.1f), v3f(2.2f, 2.4f, 2.0f),
                     ivec3(40, 36, 44), "2000 random triangles, 40x36x44", 16);
  const mesh room = room_mesh();
  const auto b = vplkit::fit_voxel_bounds(room.p.data(), room.p.size());
  check_construction(room, b.min, b.max, ivec3(64), "room + blocks, 64^3", 4);
  check_construction(room, b.min, b.max, ivec3(128), "room + blocks, 128^3", 4);
}

TEST_CASE("triangle_voxel_query.glsl: visibility and first hits equal the C++") {
  const mesh room = room_mesh();
  const auto b = vplkit::fit_voxel_bounds(room.p.data(), room.p.size());
  for (bool bricks : {false, true}) {
    check_queries(room, b.min, b.max, ivec3(48), 5, "room + blocks, 48^3", bricks);
    check_queries(random_mesh(43, 300, 0.0, 1.0), v3f(-0.1f, -0.2f, -0.05f), v3f(1.1f, 1.05f, 1.2f), ivec3(30, 26, 33),
                  6, "300 random triangles, 30x26x33", bricks);
  }
}
