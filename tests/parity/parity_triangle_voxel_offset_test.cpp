// SPDX-License-Identifier: MIT
// CPU/GPU parity of the triangle voxel grid's offset contract and of the hits' shading normals:
// vplkit_triangle_voxel_visible_offset, vplkit_triangle_voxel_first_hit_offset
// (triangle_voxel_query.glsl) and vplkit_triangle_corner_shading_normal (triangle_corners.glsl)
// against the C++ (T = float) on the same uploaded grid and corners; and the pack's callables
// (visibility_callables.glsl: the offset kind, the offset tracer with corners, its light test)
// against the C++ adaptors.
// Bounds:
// - bit for bit where division and sqrt are correctly rounded (software renderers; this machine):
//   visible, hit, triangle, t, point and the shading normal all equal;
// - elsewhere the moved ends differ by the unit vector's division and square root, so an answer may
//   differ only at a near-tie (a moved end within 1e-4 voxel of a plane, a crossing within 1e-4
//   voxel of a grown edge), counted and printed; t and the point within twice the forward error
//   bound of their operation chain (parity_forward_error.hpp) from the moved origin; the shading
//   normal within 2^-16 per component (two divisions and a square root of a unit-length result).
#include "parity_harness.hpp"
#include "parity_fma_model.hpp"
#include "parity_forward_error.hpp"

#include <headless_gl/compute.hpp>

#include <vplkit/visibility/bvh_visibility.hpp>
#include <vplkit/visibility/triangle_corners.hpp>
#include <vplkit/visibility/triangle_voxel_query.hpp>
#include <vplkit/visibility/visibility_callables.hpp>
#include <vplkit/visibility/voxelize_triangles.hpp>

#include <triangle_scene_reference.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <iostream>
#include <limits>
#include <random>
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

struct query {  // std430 { vec4 x_offset; vec4 nx; vec4 y_tmax; vec4 ny; }
  float4 x_offset;  // xyz: x; w: the offset
  float4 nx;
  float4 y_tmax;    // xyz: y; w: t_max of the first hit (x towards y)
  float4 ny;
};
struct query_out {  // std430, 12 scalars
  std::uint32_t visible, hit, triangle, pad0;
  float t, px, py, pz;
  float sx, sy, sz, pad1;
};
static_assert(sizeof(query_out) == 48, "std430 layout");

const std::string kernel = R"(
#define VPLKIT_VOXEL_BRICKS
#include "vplkit/visibility/triangle_corners.glsl"
#include "vplkit/visibility/triangle_voxel_query.glsl"
struct query { vec4 x_offset; vec4 nx; vec4 y_tmax; vec4 ny; };
struct query_out { uint visible; uint hit; uint triangle; uint pad0; vec4 t_point; vec4 shading; };
layout(std430, binding = 0) readonly buffer Queries { query q[]; };
layout(std430, binding = 1) writeonly buffer Out { query_out result[]; };
layout(std430, binding = 2) readonly buffer Words { uint words[]; };
layout(std430, binding = 3) readonly buffer Grid { vec4 gmin; vec4 gmax; ivec4 gres; };
layout(std430, binding = 4) readonly buffer Rank { uint rank_words[]; };
layout(std430, binding = 5) readonly buffer Offsets { uint offsets[]; };
layout(std430, binding = 6) readonly buffer Entries { uint entries[]; };
layout(std430, binding = 7) readonly buffer Triangles { vec4 triangles[]; };
layout(std430, binding = 8) readonly buffer Bricks { uint bricks[]; };
layout(std430, binding = 9) readonly buffer Corners { vec4 corners[]; };  // position, normal per corner
uint vplkit_load_voxel_word(uint i) { return words[i]; }
uint vplkit_load_voxel_brick_word(uint i) { return bricks[i]; }
uint vplkit_load_voxel_rank(uint i) { return rank_words[i]; }
uint vplkit_load_voxel_offset(uint i) { return offsets[i]; }
uint vplkit_load_voxel_entry(uint i) { return entries[i]; }
vec4 vplkit_load_voxel_triangle(uint i) { return triangles[i]; }
vec3 vplkit_load_triangle_corner_position(uint i) { return corners[2u * i].xyz; }
vec3 vplkit_load_triangle_corner_normal(uint i) { return corners[2u * i + 1u].xyz; }
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= VPLKIT_PARITY_COUNT) return;
  vplkit_voxel_grid g = vplkit_voxel_grid(gmin.xyz, gmax.xyz, gres.xyz);
  query k = q[i];
  vec3 x = k.x_offset.xyz, y = k.y_tmax.xyz;
  float offset = k.x_offset.w;
  bool v = vplkit_triangle_voxel_visible_offset(g, x, k.nx.xyz, y, k.ny.xyz, offset);
  vplkit_triangle_voxel_hit h = vplkit_triangle_voxel_first_hit_offset(g, x, k.nx.xyz, y - x, offset, k.y_tmax.w);
  vec3 s = h.hit ? vplkit_triangle_corner_shading_normal(h.triangle, uint(gres.w), h.point) : vec3(0.0);
  result[i] = query_out(v ? 1u : 0u, h.hit ? 1u : 0u, h.triangle, 0u, vec4(h.t, h.point), vec4(s, 0.0));
}
)";

// The pack's callables (visibility_callables.glsl) under the offset contract, with corners: the
// C++ adaptors' mirror (triangle_voxel_visibility / triangle_voxel_tracer with ends = offset and
// corners; the tracer's light visibility through the former).
const std::string callables_kernel = R"(
#define VPLKIT_VOXEL_BRICKS
#define VPLKIT_TRIANGLE_VOXELS
#define VPLKIT_TRIANGLE_CORNERS
#include "vplkit/visibility/visibility_callables.glsl"
struct query { vec4 x_offset; vec4 nx; vec4 y_tmax; vec4 ny; };
struct query_out { uint visible; uint hit; uint triangle; uint lit; vec4 t_point; vec4 shading; };
layout(std430, binding = 0) readonly buffer Queries { query q[]; };
layout(std430, binding = 1) writeonly buffer Out { query_out result[]; };
layout(std430, binding = 2) readonly buffer Words { uint words[]; };
layout(std430, binding = 3) readonly buffer Grid { vec4 gmin; vec4 gmax; ivec4 gres; };
layout(std430, binding = 4) readonly buffer Rank { uint rank_words[]; };
layout(std430, binding = 5) readonly buffer Offsets { uint offsets[]; };
layout(std430, binding = 6) readonly buffer Entries { uint entries[]; };
layout(std430, binding = 7) readonly buffer Triangles { vec4 triangles[]; };
layout(std430, binding = 8) readonly buffer Bricks { uint bricks[]; };
layout(std430, binding = 9) readonly buffer Corners { vec4 corners[]; };
uint vplkit_load_voxel_word(uint i) { return words[i]; }
uint vplkit_load_voxel_brick_word(uint i) { return bricks[i]; }
uint vplkit_load_voxel_rank(uint i) { return rank_words[i]; }
uint vplkit_load_voxel_offset(uint i) { return offsets[i]; }
uint vplkit_load_voxel_entry(uint i) { return entries[i]; }
vec4 vplkit_load_voxel_triangle(uint i) { return triangles[i]; }
vec4 vplkit_load_voxel_near_plane(uint i) { return vec4(0.0, 0.0, 0.0, 1.0); }
vec3 vplkit_load_triangle_corner_position(uint i) { return corners[2u * i].xyz; }
vec3 vplkit_load_triangle_corner_normal(uint i) { return corners[2u * i + 1u].xyz; }
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= VPLKIT_PARITY_COUNT) return;
  vplkit_voxel_grid g = vplkit_voxel_grid(gmin.xyz, gmax.xyz, gres.xyz);
  query k = q[i];
  vec3 x = k.x_offset.xyz, y = k.y_tmax.xyz;
  vplkit_visibility vis = vplkit_make_triangle_voxel_visibility_offset(g, k.x_offset.w);
  vplkit_voxel_tracer tr = vplkit_tracer_with_corners(vplkit_make_triangle_voxel_tracer_offset(g, k.x_offset.w), uint(gres.w));
  tr = vplkit_tracer_with_light_visibility(tr, vis);
  bool v = vplkit_visibility_test(vis, x, k.nx.xyz, y, k.ny.xyz);
  vplkit_ray_hit h = vplkit_voxel_tracer_trace_within(tr, x, k.nx.xyz, y - x, k.y_tmax.w);
  bool lit = vplkit_voxel_tracer_light_visible(tr, x, k.nx.xyz, y);
  result[i] = query_out(v ? 1u : 0u, h.hit ? 1u : 0u, 0u, lit ? 1u : 0u, vec4(0.0, h.position), vec4(h.shading_normal, 0.0));
}
)";

struct mesh {
  std::vector<v3f> p, n;  // a triangle soup: 3 corners per triangle, with their normals
  std::vector<std::uint32_t> idx;
};

// The parity room (floor, walls, two blocks) and random triangles, as a soup with smooth-ish corner
// normals (the face normal bent by the corner's position).
mesh make_mesh(std::uint32_t seed) {
  mesh m;
  std::mt19937 g(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), s(-1.0, 1.0);
  auto tri = [&](v3d a, v3d b, v3d c) {
    const v3d face = glm::cross(b - a, c - a);
    for (v3d q : {a, b, c}) {
      m.idx.push_back(std::uint32_t(m.p.size()));
      m.p.push_back(v3f(q));
      const double len = glm::length(face);
      m.n.push_back(len > 0.0 ? v3f(face / len + 0.3 * v3d(std::sin(3 * q.y), std::cos(2 * q.z), std::sin(q.x)))
                              : v3f(0.0f));
    }
  };
  auto quad = [&](v3d a, v3d b, v3d c, v3d d) {
    tri(a, b, c);
    tri(a, c, d);
  };
  quad(v3d(-1, 0, -1), v3d(1, 0, -1), v3d(1, 0, 3), v3d(-1, 0, 3));
  quad(v3d(-1, 0, -1), v3d(-1, 2, -1), v3d(1, 2, -1), v3d(1, 0, -1));
  quad(v3d(-1, 0, -1), v3d(-1, 0, 3), v3d(-1, 2, 3), v3d(-1, 2, -1));
  quad(v3d(0, 0, 0.5), v3d(0, 1, 0.5), v3d(0.6, 1, 0.5), v3d(0.6, 0, 0.5));  // a panel standing on the floor
  for (int i = 0; i < 150; ++i) {
    const v3d c(u(g), 1.0 + u(g), 1.0 + 2.0 * u(g));
    const double size = i % 10 == 0 ? 0.6 : 0.1;
    tri(c + size * v3d(s(g), s(g), s(g)), c + size * v3d(s(g), s(g), s(g)), c + size * v3d(s(g), s(g), s(g)));
  }
  return m;
}

// Runs `source` over the queries with the grid (bindings 2-8: words, bounds and resolution with the
// triangle count in w, rank, offsets, entries, triangles, bricks) and the mesh's corners (binding 9:
// position, normal per corner) uploaded; one query_out per query (binding 1).
std::vector<query_out> run_queries(const std::string& source, const vplkit::triangle_voxel_grid<float>& grid,
                                   const mesh& m, const std::vector<query>& qs) {
  std::vector<float4> tri_rows(4 * grid.triangles().size());
  std::memcpy(tri_rows.data(), grid.triangles().data(), tri_rows.size() * sizeof(float4));
  const auto& occ = grid.occupancy();
  struct grid_params {
    float4 bmin, bmax;
    std::int32_t res[4];
  } gp{f4(occ.bounds_min()), f4(occ.bounds_max()),
       {occ.resolution().x, occ.resolution().y, occ.resolution().z, std::int32_t(m.p.size() / 3)}};
  std::vector<float4> corner_rows;
  for (std::size_t i = 0; i < m.p.size(); ++i) {
    corner_rows.push_back(f4(m.p[i]));
    corner_rows.push_back(f4(m.n[i]));
  }
  std::vector<std::uint32_t> entries = grid.entries();
  if (entries.empty()) entries.push_back(0u);
  return vplkit::parity::run_compute<query_out>(
      source, {64, 1, 1},
      {vplkit::parity::input(0, qs), vplkit::parity::input(2, occ.words()),
       vplkit::parity::input(3, std::vector<grid_params>{gp}), vplkit::parity::input(4, grid.rank()),
       vplkit::parity::input(5, grid.offsets()), vplkit::parity::input(6, entries),
       vplkit::parity::input(7, tri_rows), vplkit::parity::input(8, grid.bricks()),
       vplkit::parity::input(9, corner_rows)},
      1, qs.size());
}

}  // namespace

TEST_CASE("triangle_voxel_query.glsl and triangle_corners.glsl: the offset contract and shading normals equal the C++") {
  const mesh m = make_mesh(23);
  const auto b = vplkit::fit_voxel_bounds(m.p.data(), m.p.size());
  const ivec3 res(40);
  const auto grid = vplkit::voxelize_triangles(b.min, b.max, res, m.p.data(), m.p.size(), m.idx.data(), m.idx.size());
  const auto v = grid.view();
  const auto tris = vplkit_test::ref_triangles(m.p, m.idx);
  const std::size_t n_tris = tris.size();
  const vplkit::triangle_corner_view<float> corners{m.p.data(), m.n.data(), n_tris};
  const float offset = vplkit::triangle_voxel_surface_offset(v.grid);
  const double L = double(grid.occupancy().voxel_length());

  std::mt19937 g(29);
  std::uniform_real_distribution<double> u(0.0, 1.0), s(-1.0, 1.0);
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<query> qs;
  auto end = [&](int kind, v3f& p, v3f& n) {
    if (kind == 0) {  // in the air, any normal
      p = v3f(v3d(b.min) + v3d(u(g), u(g), u(g)) * v3d(b.max - b.min));
      n = v3f(s(g), s(g), s(g));
      return;
    }
    const std::size_t t = std::size_t(g() % n_tris);
    p = v3f(vplkit_test::point_on(tris[t], g));
    v3d nn;
    double c;
    n = vplkit_test::ref_plane(tris[t], nn, c) ? v3f(g() % 2 ? nn : -nn) : v3f(0.0f);
  };
  for (int i = 0; i < 30000; ++i) {
    v3f x, nx, y, ny;
    end(i % 5 == 0 ? 0 : 1, x, nx);
    end(i % 7 == 0 ? 0 : 1, y, ny);
    const float off = i % 11 == 0 ? float(u(g)) * 0.05f : offset;
    const float t_max = i % 4 == 0 ? float(u(g)) * glm::length(y - x) : inf;
    qs.push_back({f4(x, off), f4(nx), f4(y, t_max), f4(ny)});
  }
  // Hard cases: x == y, non-finite ends and normals, zero normals, zero offset, negative t_max, ends
  // on the corners of triangles (junction edges).
  const v3f c = 0.5f * (b.min + b.max);
  qs.push_back({f4(c, offset), f4(v3f(0, 1, 0)), f4(c, inf), f4(v3f(0, 1, 0))});
  qs.push_back({f4(v3f(nan, 0, 0), offset), f4(v3f(0, 1, 0)), f4(c, inf), f4(v3f(0, 1, 0))});
  qs.push_back({f4(c, offset), f4(v3f(nan)), f4(c + v3f(0.3f, 0.1f, 0), inf), f4(v3f(inf, 0, 0))});
  qs.push_back({f4(c, offset), f4(v3f(0.0f)), f4(c + v3f(0.3f, 0.1f, 0), -1.0f), f4(v3f(0.0f))});
  qs.push_back({f4(c, 0.0f), f4(v3f(0, 1, 0)), f4(c + v3f(0.3f, -2.0f, 0.1f), inf), f4(v3f(0, 1, 0))});
  for (std::size_t t = 0; t < n_tris; t += 3)
    for (int k = 0; k < 3; ++k)
      qs.push_back({f4(v3f(tris[t].v[k]), offset), f4(m.n[3 * t + std::size_t(k)]),
                    f4(v3f(tris[(t + 7) % n_tris].v[(k + 1) % 3]), inf), f4(v3f(0, 1, 0))});

  const auto gpu = run_queries(kernel, grid, m, qs);

  const bool exact = vplkit::gl::is_software_renderer() && !vplkit_test::reference_contracts;
  std::size_t differ = 0, ties = 0, visible = 0, hits = 0, shaded = 0, float_checks = 0;
  for (std::size_t i = 0; i < qs.size(); ++i) {
    const query& k = qs[i];
    const v3f x(k.x_offset.x, k.x_offset.y, k.x_offset.z), y(k.y_tmax.x, k.y_tmax.y, k.y_tmax.z);
    const v3f nx(k.nx.x, k.nx.y, k.nx.z), ny(k.ny.x, k.ny.y, k.ny.z);
    const float off = k.x_offset.w;
    const bool cv = vplkit::triangle_voxel_visible_offset(v, x, nx, y, ny, off);
    const auto ch = vplkit::triangle_voxel_first_hit_offset(v, x, nx, y - x, off, k.y_tmax.w);
    const v3f cs = ch.hit ? vplkit::triangle_corner_shading_normal(corners, ch.triangle, ch.point) : v3f(0.0f);
    const query_out& a = gpu[i];
    visible += cv ? 1 : 0;
    hits += ch.hit ? 1 : 0;
    shaded += glm::length(cs) > 0.0f ? 1 : 0;
    INFO("query " << i << ": gpu visible " << a.visible << " hit " << a.hit << " tri " << a.triangle << " t "
                  << vplkit::parity::show(a.t) << " | cpu visible " << cv << " hit " << ch.hit << " tri " << ch.triangle
                  << " t " << vplkit::parity::show(ch.t));
    const bool same_answer = a.visible == (cv ? 1u : 0u) && a.hit == (ch.hit ? 1u : 0u) &&
                             (!ch.hit || a.triangle == ch.triangle);
    if (exact) {
      // Bit for bit: the answers, t, the point and the shading normal.
      REQUIRE(same_answer);
      REQUIRE(std::memcmp(&a.t, &ch.t, 4) == 0);
      REQUIRE(std::memcmp(&a.px, &ch.point, 12) == 0);
      REQUIRE(std::memcmp(&a.sx, &cs, 12) == 0);
      continue;
    }
    if (!same_answer) {
      // Only at a near-tie of the moved ends (each side's moved ends differ by the unit vector's
      // division and square root): the visibility answer flips when the tolerances move by delta,
      // and the first hit is ambiguous (another first triangle, or a crossing within delta of t_max).
      ++differ;
      const v3d xo(vplkit::bvh_offset_point(x, nx, off)), yo(vplkit::bvh_offset_point(y, ny, off));
      const double slack = double(vplkit::triangle_voxel_offset_slack(v.grid)), delta = 1e-4 * L;
      const bool vis_ok = a.visible == (cv ? 1u : 0u) || vplkit_test::segment_near_tie(tris, xo, yo, 0.0, slack, delta);
      const v3d dir = glm::normalize(v3d(y) - v3d(x));
      const double lo = vplkit_test::first_hit(tris, xo, dir, delta, std::max(0.0, slack - delta));
      const double hi = vplkit_test::first_hit(tris, xo, dir, 0.0, slack + delta);
      const bool hit_same = a.hit == (ch.hit ? 1u : 0u) && (!ch.hit || a.triangle == ch.triangle);
      const bool hit_ok = hit_same || lo != hi || std::abs(hi - double(k.y_tmax.w)) <= delta;
      ties += vis_ok && hit_ok ? 1 : 0;
      CHECK(vis_ok);
      CHECK(hit_ok);
      continue;
    }
    if (!ch.hit) continue;
    // The same triangle: t from the moved origin o = x + off unit(n_x), the point o + t d.
    using vplkit_test::fe;
    using vplkit_test::fe3;
    const auto& tri = v.triangles[ch.triangle];
    const fe3 unit_n = vplkit_test::fe_unit_vector(vplkit_test::fe3_of(nx));
    fe3 o = vplkit_test::fe3_of(x);
    for (int j = 0; j < 3; ++j) o[j] = o[j] + fe(double(off)) * unit_n[j];
    const fe3 n = vplkit_test::fe3_of(tri.plane.normal);
    const fe3 d = vplkit_test::fe_unit_vector(vplkit_test::fe3_of(y - x));
    const fe d0 = vplkit_test::fe_dot(n, o) - fe(double(tri.plane.offset));
    const fe t = fe(0.0) - d0 / vplkit_test::fe_dot(n, d);
    const float ga[4] = {a.t, a.px, a.py, a.pz}, ca[4] = {ch.t, ch.point.x, ch.point.y, ch.point.z};
    for (int j = 0; j < 4; ++j) {
      const double bound = 2 * (j == 0 ? t.e : (o[j - 1] + t * d[j - 1]).e);
      ++float_checks;
      CHECK(std::abs(double(ga[j]) - double(ca[j])) <= bound);
    }
    const float gs[3] = {a.sx, a.sy, a.sz};
    for (int j = 0; j < 3; ++j) CHECK(std::abs(gs[j] - cs[j]) <= 0x1p-16f);
  }
  std::cout << "  offset contract: " << qs.size() << " queries (" << visible << " visible, " << hits << " first hits, "
            << shaded << " shaded), " << differ << " differ (" << ties << " near-ties), " << float_checks
            << " values within their bounds; "
            << (exact ? "bit-identical required on this software renderer" : "near-ties allowed") << "\n";
  CHECK(visible > qs.size() / 10);
  CHECK(visible < qs.size() * 9 / 10);
  CHECK(hits > qs.size() / 10);
  CHECK(shaded > hits * 9 / 10);
}

TEST_CASE("visibility_callables.glsl: the offset kind, the offset tracer with corners and its light test equal the C++ adaptors") {
  const mesh m = make_mesh(31);
  const auto b = vplkit::fit_voxel_bounds(m.p.data(), m.p.size());
  const ivec3 res(32);
  const auto grid = vplkit::voxelize_triangles(b.min, b.max, res, m.p.data(), m.p.size(), m.idx.data(), m.idx.size());
  const auto v = grid.view();
  const auto tris = vplkit_test::ref_triangles(m.p, m.idx);
  const std::size_t n_tris = tris.size();
  const float offset = vplkit::triangle_voxel_surface_offset(v.grid);
  std::mt19937 g(37);
  std::uniform_real_distribution<double> u(0.0, 1.0), s(-1.0, 1.0);
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<query> qs;
  for (int i = 0; i < 12000; ++i) {
    const std::size_t t0 = std::size_t(g() % n_tris), t1 = std::size_t(g() % n_tris);
    const v3f x(vplkit_test::point_on(tris[t0], g)), y(i % 5 == 0 ? v3f(v3d(b.min) + v3d(u(g), u(g), u(g)) * v3d(b.max - b.min))
                                                                  : v3f(vplkit_test::point_on(tris[t1], g)));
    const v3f nx = m.n[3 * t0] * (g() % 2 ? 1.0f : -1.0f), ny = m.n[3 * t1];
    const float reach = i % 3 == 0 ? float(u(g)) * glm::length(y - x) : inf;
    qs.push_back({f4(x, offset), f4(nx), f4(y, reach), f4(ny)});
  }
  const auto gpu = run_queries(callables_kernel, grid, m, qs);
  vplkit::triangle_voxel_visibility<float> vis{v};
  vis.ends = vplkit::triangle_voxel_ends::offset;
  vis.offset = offset;
  vplkit::triangle_voxel_tracer<float> tr{v};
  tr.ends = vplkit::triangle_voxel_ends::offset;
  tr.offset = offset;
  tr.corners = vplkit::triangle_corner_view<float>{m.p.data(), m.n.data(), n_tris};
  const bool exact = vplkit::gl::is_software_renderer() && !vplkit_test::reference_contracts;
  std::size_t same = 0, visible = 0, hits = 0;
  for (std::size_t i = 0; i < qs.size(); ++i) {
    const query& k = qs[i];
    const v3f x(k.x_offset.x, k.x_offset.y, k.x_offset.z), y(k.y_tmax.x, k.y_tmax.y, k.y_tmax.z);
    const v3f nx(k.nx.x, k.nx.y, k.nx.z), ny(k.ny.x, k.ny.y, k.ny.z);
    const bool cv = vis(x, nx, y, ny);  // the adaptor (triangle_voxel_visible_offset)
    const auto h = tr.trace_within(x, nx, y - x, k.y_tmax.w);
    // The lit test of a hit at x by the light at y: what the C++ backend asks (cpu_visibility.hpp).
    const bool lit = vplkit::triangle_voxel_visible_offset(v, x, nx, y, v3f(0.0f), offset);
    const query_out& a = gpu[i];
    visible += cv ? 1 : 0;
    hits += h.hit ? 1 : 0;
    const bool answers = a.visible == (cv ? 1u : 0u) && a.hit == (h.hit ? 1u : 0u) && a.pad0 == (lit ? 1u : 0u);
    const bool bits = answers && std::memcmp(&a.px, &h.position, 12) == 0 && std::memcmp(&a.sx, &h.shading_normal, 12) == 0;
    INFO("query " << i << ": gpu visible " << a.visible << " hit " << a.hit << " lit " << a.pad0 << " | cpu visible "
                  << cv << " hit " << h.hit << " lit " << lit);
    if (exact) REQUIRE(bits);
    same += answers ? 1 : 0;
    if (!answers || !h.hit) continue;
    // Elsewhere the values move by the functions' rounding (the test case above bounds it from the
    // operation chain); here a loose check that the callables pass them through: the point within
    // 1e-5 of the grid's size plus its coordinates' magnitude, the normal within 2^-16.
    const float tol = 1e-5f * (glm::length(v3f(b.max - b.min)) + glm::length(h.position));
    CHECK(glm::length(v3f(a.px, a.py, a.pz) - h.position) <= tol);
    CHECK(glm::length(v3f(a.sx, a.sy, a.sz) - h.shading_normal) <= 0x1p-16f * 2.0f);
  }
  std::cout << "  offset callables: " << qs.size() << " queries (" << visible << " visible, " << hits << " hits), "
            << same << " with equal answers" << (exact ? " (bit-identical required on this software renderer)" : "") << "\n";
  // Answers may differ only at the functions' near-ties (the test case above): a handful.
  CHECK(same >= qs.size() * 99 / 100);
  CHECK(visible > qs.size() / 20);
  CHECK(hits > qs.size() / 10);
}
