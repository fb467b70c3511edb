// SPDX-License-Identifier: MIT
// CPU/GPU parity of glsl/vplkit/visibility/bvh_*.glsl with include/vplkit/visibility/bvh_*.hpp
// (T = float): the std430 layout of nodes and triangles, closest hit and occlusion, the
// visibility callables, and their use as the estimators' user visibility / tracer.
//
// Why exact answers are expected, and where they may legitimately differ:
// - The layout is bytes: every field read back by the GPU must equal the C++ array, bit for bit.
// - The traversal and both geometric tests use + - * / and comparisons only, written in the C++
//   order and `precise` (no FMA contraction). Where division is correctly rounded (llvmpipe,
//   software renderers) every value is the C++ value bit for bit: hit, triangle, t, u, v, the
//   position, the normal (sqrt: correctly rounded there too), and the visit order, so even ties
//   between triangles at the same t are broken the same way. Required exactly on software
//   renderers.
// - GLSL allows 2.5 ulp division and 3 ulp sqrt. On such GPUs t, u, v move by a few ulp and a
//   triangle can differ only where two answers are both right: the ray passes within 1e-5 of the
//   scene's size of an edge, or two triangles are hit within that distance of each other (judged
//   by the independent double reference of bvh_test_scenes.hpp). There, differences are counted
//   and accepted; floats are compared where the triangle is the same, within the forward error
//   bound of Woop's chain on both sides (parity_forward_error.hpp: a nearly parallel ray turns the
//   shear division's 2.5 ulp into thousands of ulps of u and v). The [fma] build (a reference that
//   contracts a*b+c) is judged the same way.
// - llvmpipe ends every loop of an invocation after 65535 iterations in all; one query spends
//   (nodes visited + triangles tested) of them. The test measures the largest count on the C++
//   side and requires it below the budget, so a truncated traversal cannot go unnoticed.
#include <parity_fma_model.hpp>
#include <parity_forward_error.hpp>
#include <parity_harness.hpp>

#include <bvh_gpu_model.hpp>
#include <bvh_test_scenes.hpp>

#include <vplkit/visibility/bvh_build.hpp>
#include <vplkit/visibility/bvh_traverse.hpp>
#include <vplkit/visibility/bvh_visibility.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

using namespace vplkit::parity;
using vplkit_test::flt_inf;
using vplkit_test::flt_nan;
using vplkit_test::random_source;
using vplkit_test::tri_mesh;
using vplkit_test::v3d;
using vplkit_test::v3f;

namespace {

// The GPU side of a hierarchy: its two arrays (a one-element dummy when empty: Mesa wants the
// accessors defined, and a buffer bound) and the node count.
struct gpu_bvh {
  std::vector<vplkit::bvh_node<float>> nodes;
  std::vector<vplkit::bvh_triangle<float>> triangles;
  std::vector<std::uint32_t> params;  // node_count
  explicit gpu_bvh(const vplkit::bvh<float>& b)
      : nodes(b.nodes()), triangles(b.triangles()), params{std::uint32_t(b.node_count())} {
    if (nodes.empty()) nodes.push_back({v3f(0.0f), 0u, v3f(0.0f), 0u});
    if (triangles.empty()) triangles.push_back({v3f(0.0f), 0u, v3f(0.0f), 0u, v3f(0.0f), 0u});
  }
  std::vector<ssbo> bindings() const { return {input(2, nodes), input(3, triangles), input(4, params)}; }
};

const char* bvh_block = R"(
layout(std430, binding = 2) readonly buffer BvhNodes { vplkit_bvh_node bvh_nodes[]; };
layout(std430, binding = 3) readonly buffer BvhTriangles { vplkit_bvh_triangle bvh_triangles[]; };
layout(std430, binding = 4) readonly buffer BvhParams { uint bvh_node_count; };
vplkit_bvh_node vplkit_load_bvh_node(uint i) { return bvh_nodes[i]; }
vplkit_bvh_triangle vplkit_load_bvh_triangle(uint i) { return bvh_triangles[i]; }
vplkit_bvh scene_bvh() { return vplkit_bvh(bvh_node_count); }
)";

vplkit::bvh<float> build(const tri_mesh& m) {
  return vplkit::build_bvh(m.positions.data(), m.positions.size(), m.indices.data(), m.indices.size());
}

// ---- forward error bounds (parity_forward_error.hpp) -------------------------------------------
// Off llvmpipe (a GPU that divides in 2.5 ulp, or the [fma] reference that contracts) t, u, v are
// ill-conditioned where the ray is nearly parallel to the triangle or passes near an edge: the
// shear factors d[kx] / d[kz] carry the division's error into every edge function, and an edge
// function that cancels turns it into thousands of ulps of u or v (H200: 10242 ulps of u). The
// bound follows Woop et al.'s chain in bvh_ray_triangle operation by operation.

bool exact_device() { return software_renderer() && !vplkit_test::reference_contracts; }

using vplkit_test::fe;
using vplkit_test::fe3;

struct woop_fe {
  fe t, u, v, w;
};

woop_fe woop_forward_error(const fe3& o, const fe3& d, v3f v0, v3f v1, v3f v2) {
  const double adx = std::fabs(d[0].v), ady = std::fabs(d[1].v), adz = std::fabs(d[2].v);
  const int kz = adx >= ady ? (adx >= adz ? 0 : 2) : (ady >= adz ? 1 : 2);
  const int kx = kz + 1 == 3 ? 0 : kz + 1, ky = kx + 1 == 3 ? 0 : kx + 1;  // winding does not change a bound
  auto rel = [&](v3f v) { return fe3{{fe(v.x) - o[0], fe(v.y) - o[1], fe(v.z) - o[2]}}; };
  const fe3 a = rel(v0), b = rel(v1), c = rel(v2);
  const fe sx = d[kx] / d[kz], sy = d[ky] / d[kz], sz = fe(1.0) / d[kz];
  const fe ax = a[kx] - sx * a[kz], ay = a[ky] - sy * a[kz];
  const fe bx = b[kx] - sx * b[kz], by = b[ky] - sy * b[kz];
  const fe cx = c[kx] - sx * c[kz], cy = c[ky] - sy * c[kz];
  const fe eu = cx * by - cy * bx, ev = ax * cy - ay * cx, ew = bx * ay - by * ax;
  const fe det = eu + ev + ew;
  const fe tn = eu * (sz * a[kz]) + ev * (sz * b[kz]) + ew * (sz * c[kz]);
  return {tn / det, ev / det, ew / det, eu / det};
}

// w v0 + u v1 + v v2 (bvh_closest_hit's position), component k.
fe position_forward_error(const woop_fe& h, v3f v0, v3f v1, v3f v2, int k) {
  return h.w * fe(v0[k]) + h.u * fe(v1[k]) + h.v * fe(v2[k]);
}

// The unit geometric normal of bvh_closest_hit: cross(v1 - v0, v2 - v0) through bvh_unit_vector.
fe3 normal_forward_error(v3f v0, v3f v1, v3f v2) {
  const fe3 e1{{fe(v1.x) - fe(v0.x), fe(v1.y) - fe(v0.y), fe(v1.z) - fe(v0.z)}};
  const fe3 e2{{fe(v2.x) - fe(v0.x), fe(v2.y) - fe(v0.y), fe(v2.z) - fe(v0.z)}};
  return vplkit_test::fe_unit_vector(fe3{{e1[1] * e2[2] - e2[1] * e1[2], e1[2] * e2[0] - e2[2] * e1[0],
                                          e1[0] * e2[1] - e2[0] * e1[1]}});
}

// bvh_surface_offset: offset_relative * (largest extent of the root box) + 2^-15 * (largest |coordinate|).
fe surface_offset_fe(const vplkit::bvh<float>& b, float offset_relative) {
  if (b.node_count() == 0) return fe(0.0);
  const v3f lo = b.nodes()[0].bounds_min, hi = b.nodes()[0].bounds_max;
  fe d(0.0), m(0.0);
  for (int k = 0; k < 3; ++k) {
    d = vplkit_test::fe_max(d, fe(hi[k]) - fe(lo[k]));
    m = vplkit_test::fe_max(m, fe(std::fmax(std::fabs(lo[k]), std::fabs(hi[k]))));
  }
  return fe(offset_relative) * d + fe(vplkit::bvh_offset_coordinate_scale) * m;
}

// bvh_offset_point: x + offset * bvh_unit_vector(n).
fe3 offset_point_fe(v3f x, v3f n, const fe& offset) {
  const fe3 u = vplkit_test::fe_unit_vector(vplkit_test::fe3_of(n));
  return {{fe(x.x) + offset * u[0], fe(x.y) + offset * u[1], fe(x.z) + offset * u[2]}};
}

// The bound on the position bvh_trace(x, n_x, y - x, offset_relative) reports, both sides (0 on a
// miss): Woop's chain on the ray from the offset point, whose own error enters as input error.
std::array<double, 3> traced_position_bound(const vplkit::bvh<float>& b, const std::vector<std::size_t>& slot_of_id,
                                            v3f x, v3f nx, v3f y, float offset_relative) {
  std::array<double, 3> bound{0, 0, 0};
  const v3f o = vplkit::bvh_offset_point(x, nx, vplkit::bvh_surface_offset(b.view(), offset_relative));
  if (!std::isfinite(o.x) || !std::isfinite(o.y) || !std::isfinite(o.z)) return bound;
  const vplkit::bvh_hit<float> h = vplkit::bvh_closest_hit(b.view(), o, y - x);
  if (!h.hit) return bound;
  const vplkit::bvh_triangle<float>& tri = b.triangles()[slot_of_id[h.triangle]];
  const fe3 o_fe = offset_point_fe(x, nx, surface_offset_fe(b, offset_relative));
  const fe3 d{{fe(y.x) - fe(x.x), fe(y.y) - fe(x.y), fe(y.z) - fe(x.z)}};
  const woop_fe w = woop_forward_error(o_fe, d, tri.v0, tri.v1, tri.v2);
  for (int k = 0; k < 3; ++k) bound[std::size_t(k)] = 2 * position_forward_error(w, tri.v0, tri.v1, tri.v2, k).e;
  return bound;
}

std::vector<std::size_t> slots_of_ids(const vplkit::bvh<float>& b) {
  std::vector<std::size_t> slot_of_id(b.triangles().size());
  for (std::size_t k = 0; k < b.triangles().size(); ++k) slot_of_id[b.triangles()[k].id] = k;
  return slot_of_id;
}

// The direction as make_bvh_ray keeps it (components below FLT_MIN are 0 on both sides).
fe3 ray_direction_fe(v3f d) {
  fe3 out;
  for (int k = 0; k < 3; ++k) out[k] = fe(std::fabs(d[k]) < 1.17549435e-38f ? 0.0 : double(d[k]));
  return out;
}

// ---- closest hit and occlusion ------------------------------------------------------------------

struct ray_case {  // std430 { vec4 o_tmin; vec4 d_tmax; }; t_min < 0 in w: use the default overloads
  float4 o_tmin;
  float4 d_tmax;
};

struct hit_result {  // std430 { uvec4 hit_triangle_occluded; vec4 t_u_v; vec4 position; vec4 normal; }
  std::uint32_t hit, triangle, occluded, pad;
  float t, u, v, pad2;
  float4 position, normal;
};

const std::string hit_source = std::string(R"(
#include "vplkit/visibility/bvh_traverse.glsl"
struct ray_case { vec4 o_tmin; vec4 d_tmax; };
struct hit_result { uvec4 hit_triangle_occluded; vec4 t_u_v; vec4 position; vec4 normal; };
)") + bvh_block;

const std::string hit_body = R"(
  ray_case r = rays[i];
  vplkit_bvh_hit h;
  bool occ;
  if (r.o_tmin.w < 0.0) {
    h = vplkit_bvh_closest_hit(scene_bvh(), r.o_tmin.xyz, r.d_tmax.xyz);
    occ = vplkit_bvh_occluded(scene_bvh(), r.o_tmin.xyz, r.d_tmax.xyz);
  } else {
    h = vplkit_bvh_closest_hit(scene_bvh(), r.o_tmin.xyz, r.d_tmax.xyz, r.o_tmin.w, r.d_tmax.w);
    occ = vplkit_bvh_occluded(scene_bvh(), r.o_tmin.xyz, r.d_tmax.xyz, r.o_tmin.w, r.d_tmax.w);
  }
  result[i] = hit_result(uvec4(h.hit ? 1u : 0u, h.triangle, occ ? 1u : 0u, 0u), vec4(h.t, h.u, h.v, 0.0),
                         vec4(h.position, 0.0), vec4(h.normal, 0.0));)";

hit_result cpu_hit(const vplkit::bvh<float>& b, const ray_case& r, vplkit::bvh_traversal_counts* counts) {
  const v3f o = xyz(r.o_tmin), d = xyz(r.d_tmax);
  vplkit::bvh_hit<float> h;
  bool occ;
  if (r.o_tmin.w < 0.0f) {
    h = vplkit::bvh_closest_hit(b.view(), o, d);
    occ = vplkit::bvh_occluded(b.view(), o, d);
  } else {
    h = vplkit::bvh_closest_hit(b.view(), o, d, r.o_tmin.w, r.d_tmax.w, counts);
    vplkit::bvh_traversal_counts occ_counts;
    occ = vplkit::bvh_occluded(b.view(), o, d, r.o_tmin.w, r.d_tmax.w, &occ_counts);
  }
  return {h.hit ? 1u : 0u, h.triangle, occ ? 1u : 0u, 0u, h.t, h.u, h.v, 0.0f, f4(h.position), f4(h.normal)};
}

// Random rays in and around [lo, hi] (see parity_visibility_test for the pattern): any length,
// some along an axis or in an axis plane, a third with a finite t_max, some with t_min > 0, a
// fifth through the default overloads.
std::vector<ray_case> random_rays(random_source& rnd, int n, v3d lo, v3d hi) {
  std::vector<ray_case> rays;
  const v3d pad = 0.3 * (hi - lo);
  const double diag = glm::length(hi - lo);
  for (int i = 0; i < n; ++i) {
    const v3f o = rnd.point_in(lo - pad, hi + pad);
    v3f d(rnd.direction() * std::pow(10.0, rnd.uniform(-3.0, 3.0)));
    if (i % 17 == 0) d[rnd.integer(0, 2)] = 0.0f;
    if (i % 23 == 0) {
      const int a = rnd.integer(0, 2);
      d = v3f(0.0f);
      d[a] = rnd.unit() < 0.5 ? -1.0f : 1.0f;
    }
    const double len = std::sqrt(glm::dot(v3d(d), v3d(d)));
    float t_min = i % 7 == 0 ? float(rnd.uniform(0.0, 0.5) * diag / len) : 0.0f;
    const float t_max = i % 3 == 0 ? float(rnd.uniform(0.0, 1.5) * diag / len) : flt_inf;
    if (i % 5 == 0) t_min = -1.0f;  // the overloads without a range
    rays.push_back({f4(o, t_min), f4(d, t_max)});
  }
  return rays;
}

// Rays from inside a closed mesh aimed exactly at its vertices and edge midpoints: ties.
std::vector<ray_case> aimed_rays(random_source& rnd, const tri_mesh& m, int n, v3d lo, v3d hi) {
  std::vector<ray_case> rays;
  for (int i = 0; i < n; ++i) {
    const v3f o = rnd.point_in(lo, hi);
    const std::size_t t = std::size_t(rnd.integer(0, int(m.triangle_count()) - 1));
    const int k = rnd.integer(0, 2);
    const v3f target = i % 2 == 0 ? m.vertex(t, k) : 0.5f * (m.vertex(t, k) + m.vertex(t, (k + 1) % 3));
    rays.push_back({f4(o, 0.0f), f4(target - o, flt_inf)});
  }
  return rays;
}

std::vector<ray_case> hard_rays() {
  std::vector<ray_case> r;
  const v3f o(0.1f, 0.2f, 0.3f), d(0.3f, -0.5f, 0.8f);
  for (v3f bad : {v3f(flt_nan, 0, 0), v3f(0, flt_inf, 0), v3f(0, 0, -flt_inf)}) {
    r.push_back({f4(bad, 0.0f), f4(d, flt_inf)});
    r.push_back({f4(o, 0.0f), f4(bad, flt_inf)});
  }
  for (v3f z : {v3f(0.0f), v3f(-0.0f), v3f(0, 0, 1e-40f), v3f(1e-40f, 0, 1), v3f(1e-38f, 1e-39f, -1)})
    r.push_back({f4(o, 0.0f), f4(z, flt_inf)});
  for (float t_max : {flt_nan, -1.0f, 0.0f, 1e-30f, 3.4e38f}) r.push_back({f4(o, 0.0f), f4(d, t_max)});
  for (float t_min : {flt_nan, 1e30f, 0.25f}) r.push_back({f4(o, t_min), f4(d, flt_inf)});
  // Huge and tiny directions (t scales inversely).
  r.push_back({f4(o, 0.0f), f4(d * 1e30f, flt_inf)});
  r.push_back({f4(o, 0.0f), f4(d * 1e-30f, flt_inf)});
  return r;
}

struct parity_counts {
  std::size_t rays = 0, hits = 0, triangle_differ = 0, tie_differ = 0;
  std::uint32_t max_budget = 0;  // nodes + triangles of one query, the largest
};

// Returns what the GPU answered.
std::vector<hit_result> check_hits(const tri_mesh& m, const vplkit::bvh<float>& b, const std::vector<ray_case>& rays,
                                   const char* what, parity_counts& pc) {
  const gpu_bvh g(b);
  auto inputs = g.bindings();
  inputs.push_back(input(0, rays, "ray_case rays"));
  const auto gpu = run_compute<hit_result>(per_item(hit_source, inputs, "hit_result result", hit_body), rays.size());
  std::vector<hit_result> cpu;
  for (const ray_case& r : rays) {
    vplkit::bvh_traversal_counts c;
    cpu.push_back(cpu_hit(b, r, &c));
    pc.max_budget = std::max(pc.max_budget, c.nodes + c.triangles);
  }
  REQUIRE(pc.max_budget < 65535u);  // else llvmpipe would have cut a traversal short
  auto describe = [&](std::size_t i) {
    return "o " + show3(xyz(rays[i].o_tmin)) + " d " + show3(xyz(rays[i].d_tmax)) + " t_min " + show(rays[i].o_tmin.w) +
           " t_max " + show(rays[i].d_tmax.w);
  };
  series<std::uint32_t> answers;
  series<float> floats;
  std::vector<std::size_t> float_ray;
  std::vector<double> float_bounds;  // per float: the forward error bound of both sides
  const std::vector<std::size_t> slot_of_id = slots_of_ids(b);
  const double scale = m.triangle_count() ? vplkit_test::mesh_scale(m) : 1.0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const hit_result &a = gpu[i], &c = cpu[i];
    ++pc.rays;
    pc.hits += c.hit;
    if (!exact_device() && (a.hit != c.hit || a.triangle != c.triangle)) {
      // Both must be right: judged by the double reference (ties and edges).
      ++pc.triangle_differ;
      const auto ref = vplkit_test::reference_closest(m, xyz(rays[i].o_tmin), xyz(rays[i].d_tmax),
                                                      std::max(0.0f, rays[i].o_tmin.w), rays[i].d_tmax.w, 1e-5, scale);
      if (ref.acceptable(a.hit != 0, int(a.triangle)) && ref.acceptable(c.hit != 0, int(c.triangle))) {
        ++pc.tie_differ;
        continue;
      }
    }
    answers.add(a.hit, c.hit);
    answers.add(a.triangle, c.triangle);
    answers.add(a.occluded, c.occluded);
    if (a.hit != c.hit || a.triangle != c.triangle) continue;
    floats.add(a.t, c.t);
    floats.add(a.u, c.u);
    floats.add(a.v, c.v);
    for (int k = 0; k < 3; ++k) floats.add(a.position[k], c.position[k]);
    for (int k = 0; k < 3; ++k) floats.add(a.normal[k], c.normal[k]);
    for (int k = 0; k < 9; ++k) float_ray.push_back(i);
    if (c.hit) {
      const vplkit::bvh_triangle<float>& tri = b.triangles()[slot_of_id[c.triangle]];
      const woop_fe h = woop_forward_error(vplkit_test::fe3_of(xyz(rays[i].o_tmin)),
                                           ray_direction_fe(xyz(rays[i].d_tmax)), tri.v0, tri.v1, tri.v2);
      const fe3 n = normal_forward_error(tri.v0, tri.v1, tri.v2);
      for (const fe& x : {h.t, h.u, h.v, position_forward_error(h, tri.v0, tri.v1, tri.v2, 0),
                          position_forward_error(h, tri.v0, tri.v1, tri.v2, 1),
                          position_forward_error(h, tri.v0, tri.v1, tri.v2, 2), n[0], n[1], n[2]})
        float_bounds.push_back(2 * x.e);  // two conforming evaluations
    } else {
      for (int k = 0; k < 9; ++k) float_bounds.push_back(0.0);  // a miss: all zero on both sides
    }
  }
  VPLKIT_CHECK_PARITY(compare_exact(answers, [&](std::size_t k) { return describe(k / 3); },
                                    std::string(what) + ": hit, triangle, occluded"));
  // Software renderers against the plain reference: bit for bit. Elsewhere (a GPU, or the [fma]
  // reference): each float within the forward error bound of Woop's chain on both sides.
  const auto describe_float = [&](std::size_t k) { return describe(float_ray[k]); };
  if (exact_device())
    VPLKIT_CHECK_PARITY(compare_floats(floats, within_ulps(0), describe_float,
                                       std::string(what) + ": t, u, v, position, normal"));
  else
    VPLKIT_CHECK_PARITY(vplkit_test::compare_within_bounds(floats, float_bounds, describe_float,
                                                           std::string(what) + ": t, u, v, position, normal"));
  return gpu;
}

// ---- huge divisors (bvh_ray.hpp, "Huge values") -------------------------------------------------
// Rays from inside the room [-half, half]^3 aimed at triangle centroids (no edge or tie
// ambiguity), their direction scaled so that its largest component lies in (2^126, FLT_MAX];
// every seventh with a smaller component made denormal or zero; a third with t_max = 1 (the target).
std::vector<ray_case> huge_direction_rays(random_source& rnd, const tri_mesh& m, int n, double half) {
  std::vector<ray_case> rays;
  const double two_126 = std::ldexp(1.0, 126);
  for (int i = 0; i < n; ++i) {
    const v3f o(rnd.point_in(v3d(-0.5 * half), v3d(0.5 * half)));
    const std::size_t t = std::size_t(rnd.integer(0, int(m.triangle_count()) - 1));
    const v3f target = (m.vertex(t, 0) + m.vertex(t, 1) + m.vertex(t, 2)) / 3.0f;
    v3d dir = v3d(target) - v3d(o);
    const double dm = std::fmax(std::fabs(dir.x), std::fmax(std::fabs(dir.y), std::fabs(dir.z)));
    dir *= rnd.uniform(two_126 * 1.0000002, double(std::numeric_limits<float>::max())) / dm;
    v3f d(dir);
    if (i % 7 == 0) {
      const int k = rnd.integer(0, 2);
      if (std::fabs(d[k]) < float(two_126)) d[k] = i % 2 ? 1e-40f : 0.0f;
    }
    rays.push_back({f4(o, i % 3 == 0 ? 0.0f : -1.0f), f4(d, i % 3 == 0 ? 1.0f : flt_inf)});
  }
  return rays;
}

// The directions and normals of the unit-vector cases: largest component above 2^126, at it, with
// denormal, zero and normal components beside it.
std::vector<v3f> huge_vectors() {
  const float big = std::numeric_limits<float>::max(), two_126 = std::ldexp(1.0f, 126),
              two_127 = std::ldexp(1.0f, 127), above = std::nextafter(two_126, big);
  return {v3f(big, big, big),           v3f(-big, 0.0f, 0.0f),          v3f(0.0f, 0.0f, big),
          v3f(two_127, -two_126, 3.0f), v3f(above, 1.0f, 0.0f),         v3f(two_126, two_126, -two_126),
          v3f(big, 1e-40f, -1.17549435e-38f), v3f(1.5f * two_127, 1e-45f, 1e20f), v3f(3e38f, -3e38f, 1e38f),
          v3f(1e-40f, -two_127, 0.0f),  v3f(-1e38f, 2e38f, -0.5f * big)};
}

}  // namespace

TEST_CASE("bvh layout: the GPU reads every field of every node and triangle as the C++ wrote it") {
  random_source rnd(201);
  const tri_mesh m = vplkit_test::random_soup(rnd, 3000, 1e-3, 0.3);
  const auto b = build(m);
  const gpu_bvh g(b);
  const std::size_t count = std::max(b.node_count(), b.triangle_count());
  // Five uvec4 per item: the main output holds count elements of 5 * 16 bytes.
  const auto gpu = run_kernel(per_item(std::string(R"(#include "vplkit/visibility/bvh_layout.glsl")") + bvh_block,
                                       g.bindings(), "uvec4 result", R"(
  // Node i (if any): 2 uvec4; triangle i (if any): 3 uvec4; 5 per invocation.
  if (i < bvh_node_count) {
    vplkit_bvh_node n = vplkit_load_bvh_node(i);
    result[5u * i] = uvec4(floatBitsToUint(n.bounds_min), n.first);
    result[5u * i + 1u] = uvec4(floatBitsToUint(n.bounds_max), n.count);
  } else {
    result[5u * i] = uvec4(0u);
    result[5u * i + 1u] = uvec4(0u);
  }
  vplkit_bvh_triangle t = vplkit_load_bvh_triangle(min(i, uint(bvh_triangles.length()) - 1u));
  result[5u * i + 2u] = uvec4(floatBitsToUint(t.v0), t.id);
  result[5u * i + 3u] = uvec4(floatBitsToUint(t.v1), t.unused1);
  result[5u * i + 4u] = uvec4(floatBitsToUint(t.v2), t.unused2);)"),
                              count, 5 * 16)
                       .get<std::uint32_t>(1);
  std::vector<std::uint32_t> cpu(count * 20, 0u);
  for (std::size_t i = 0; i < count; ++i) {
    if (i < b.node_count()) std::memcpy(&cpu[20 * i], &b.nodes()[i], 32);
    std::memcpy(&cpu[20 * i + 8], &b.triangles()[std::min(i, b.triangle_count() - 1)], 48);
  }
  VPLKIT_CHECK_PARITY(compare_exact(gpu, cpu, [&](std::size_t k) { return "word " + std::to_string(k % 20) + " of element " + std::to_string(k / 20); },
                                    "bvh_node (32 bytes) and bvh_triangle (48 bytes) through std430"));
}

TEST_CASE("bvh closest hit and occlusion: random soups, a closed room, empty and one-triangle scenes, hard rays") {
  random_source rnd(203);
  parity_counts pc;
  {
    const tri_mesh m = vplkit_test::random_soup(rnd, 2000, 1e-3, 0.2);
    auto rays = random_rays(rnd, 12000, v3d(0.0), v3d(1.0));
    const auto hard = hard_rays();
    rays.insert(rays.end(), hard.begin(), hard.end());
    check_hits(m, build(m), rays, "random soup", pc);
  }
  {
    const tri_mesh m = vplkit_test::closed_room();
    auto rays = aimed_rays(rnd, m, 8000, v3d(-0.98), v3d(0.98));
    const auto more = random_rays(rnd, 4000, v3d(-1.0), v3d(1.0));
    rays.insert(rays.end(), more.begin(), more.end());
    check_hits(m, build(m), rays, "closed room (aimed at vertices and edges)", pc);
  }
  {
    tri_mesh m = vplkit_test::random_soup(rnd, 500, 1e-2, 0.3);  // scaled by 2^40: far from 1, exact
    for (v3f& p : m.positions) p *= 1099511627776.0f;
    auto rays = random_rays(rnd, 3000, v3d(0.0), v3d(1099511627776.0));
    check_hits(m, build(m), rays, "soup scaled by 2^40", pc);
  }
  {
    const tri_mesh empty;
    check_hits(empty, build(empty), random_rays(rnd, 200, v3d(0.0), v3d(1.0)), "empty", pc);
    tri_mesh one;
    one.tri(v3f(0, 0, 1), v3f(1, 0, 1), v3f(0, 1, 1));
    check_hits(one, build(one), random_rays(rnd, 2000, v3d(0.0), v3d(1.0)), "one triangle", pc);
  }
  std::cout << "  bvh closest hit: " << pc.rays << " rays, " << pc.hits << " hits; triangle differs on " << pc.triangle_differ
            << " (" << pc.tie_differ << " of them ties); largest loop budget of one query " << pc.max_budget
            << " iterations (llvmpipe allows 65535)\n";
  CHECK(pc.hits > pc.rays / 5);
}

TEST_CASE("bvh visibility callables: visible, trace, offsets, the callable structs") {
  const tri_mesh m = vplkit_test::closed_room();
  const auto b = build(m);
  const gpu_bvh g(b);
  random_source rnd(207);
  struct callable_case {  // std430 { vec4 x_mode; vec4 nx_offset; vec4 y; vec4 ny; }
    float4 x_mode, nx_offset, y, ny;
  };
  struct callable_result {  // std430 { uvec4 answer; vec4 position; vec4 offset_point; }
    std::uint32_t answer, pad[3];
    float4 position, offset_point;
  };
  auto surface_point = [&](v3f& p, v3f& n) { vplkit_test::random_surface_point(rnd, m, p, n, 0.1, 10.0); };
  std::vector<callable_case> cases;
  for (int i = 0; i < 12000; ++i) {
    v3f x, nx, y, ny;
    surface_point(x, nx);
    surface_point(y, ny);
    const int mode = i % 6;  // 0-2: visible (explicit, default, struct); 3-5: trace along y - x
    cases.push_back({f4(x, float(mode)), f4(nx, float(rnd.uniform(0.0, 1e-3))), f4(y), f4(ny)});
  }
  const v3f p0(0.2f, -1.0f, 0.3f), up(0, 1, 0);
  for (int mode = 0; mode < 6; ++mode) {  // x == y, zero / NaN normals, non-finite points
    const float fm = float(mode);
    cases.push_back({f4(p0, fm), f4(up, 1e-4f), f4(p0), f4(up)});
    cases.push_back({f4(p0, fm), f4(v3f(0.0f), 1e-4f), f4(v3f(0.5f, 0.9f, 0.1f)), f4(v3f(flt_nan))});
    cases.push_back({f4(v3f(flt_nan, 0, 0), fm), f4(up, 1e-4f), f4(v3f(0.5f)), f4(up)});
    cases.push_back({f4(p0, fm), f4(up, 1e-4f), f4(v3f(0, flt_inf, 0)), f4(up)});
  }
  auto inputs = g.bindings();
  inputs.push_back(input(0, cases, "callable_case cases"));
  const auto gpu = run_compute<callable_result>(per_item(std::string(R"(
#include "vplkit/visibility/bvh_visibility.glsl"
struct callable_case { vec4 x_mode; vec4 nx_offset; vec4 y; vec4 ny; };
struct callable_result { uvec4 answer; vec4 position; vec4 offset_point; };
)") + bvh_block,
                                                         inputs, "callable_result result", R"(
  callable_case c = cases[i];
  int mode = int(c.x_mode.w);
  vec3 x = c.x_mode.xyz, n_x = c.nx_offset.xyz, y = c.y.xyz, n_y = c.ny.xyz;
  float rel = c.nx_offset.w;
  bool answer = false;
  vec3 position = vec3(0.0);
  if (mode == 0) answer = vplkit_bvh_visible(scene_bvh(), x, n_x, y, n_y, rel);
  else if (mode == 1) answer = vplkit_bvh_visible(scene_bvh(), x, n_x, y, n_y);
  else if (mode == 2) {
    vplkit_bvh_visibility v = vplkit_make_bvh_visibility(scene_bvh());
    v.offset_relative = rel;
    answer = vplkit_bvh_visibility_test(v, x, n_x, y, n_y);
  } else {
    vplkit_ray_hit h;
    if (mode == 3) h = vplkit_bvh_trace(scene_bvh(), x, n_x, y - x, rel);
    else if (mode == 4) h = vplkit_bvh_trace(scene_bvh(), x, n_x, y - x);
    else {
      vplkit_bvh_tracer tr = vplkit_make_bvh_tracer(scene_bvh());
      tr.offset_relative = rel;
      h = vplkit_bvh_tracer_trace(tr, x, n_x, y - x);
    }
    answer = h.hit;
    position = h.position;
  }
  vec3 o = vplkit_bvh_offset_point(x, n_x, vplkit_bvh_surface_offset(scene_bvh(), rel));
  result[i] = callable_result(uvec4(answer ? 1u : 0u, 0u, 0u, 0u), vec4(position, 0.0), vec4(o, vplkit_bvh_surface_offset(scene_bvh())));)"),
                                                cases.size());
  series<std::uint32_t> answers;
  series<float> floats;
  std::vector<double> float_bounds;
  const std::vector<std::size_t> slot_of_id = slots_of_ids(b);
  std::size_t visible = 0, hits = 0;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const callable_case& c = cases[i];
    const v3f x = xyz(c.x_mode), nx = xyz(c.nx_offset), y = xyz(c.y), ny = xyz(c.ny);
    const float rel = c.nx_offset.w;
    const int mode = int(c.x_mode.w);
    bool answer = false;
    v3f position(0.0f);
    if (mode == 0) answer = vplkit::bvh_visible(b.view(), x, nx, y, ny, rel);
    else if (mode == 1) answer = vplkit::bvh_visible(b.view(), x, nx, y, ny);
    else if (mode == 2) answer = vplkit::bvh_visibility<float>{b.view(), rel}(x, nx, y, ny);
    else {
      vplkit::ray_hit<float> h;
      if (mode == 3) h = vplkit::bvh_trace(b.view(), x, nx, y - x, rel);
      else if (mode == 4) h = vplkit::bvh_trace(b.view(), x, nx, y - x);
      else h = vplkit::bvh_tracer<float>{b.view(), rel}(x, nx, y - x);
      answer = h.hit;
      position = h.position;
      hits += answer;
    }
    if (mode < 3) visible += answer;
    const v3f o = vplkit::bvh_offset_point(x, nx, vplkit::bvh_surface_offset(b.view(), rel));
    answers.add(gpu[i].answer, answer ? 1u : 0u);
    for (int k = 0; k < 3; ++k) floats.add(gpu[i].position[k], position[k]);
    for (int k = 0; k < 3; ++k) floats.add(gpu[i].offset_point[k], o[k]);
    floats.add(gpu[i].offset_point.w, vplkit::bvh_surface_offset(b.view()));
    // The forward error bounds of both sides (parity_forward_error.hpp): the traced position from
    // Woop's chain on the ray from the offset point (whose own error enters as an input error).
    const fe3 o_fe = offset_point_fe(x, nx, surface_offset_fe(b, rel));
    const auto position_bound = mode >= 3 ? traced_position_bound(b, slot_of_id, x, nx, y, rel) : std::array<double, 3>{};
    for (int k = 0; k < 3; ++k) float_bounds.push_back(position_bound[std::size_t(k)]);
    for (int k = 0; k < 3; ++k) float_bounds.push_back(2 * o_fe[k].e);
    float_bounds.push_back(2 * surface_offset_fe(b, float(vplkit::bvh_offset_relative_default)).e);
  }
  auto describe = [&](std::size_t i) {
    const auto& c = cases[i];
    return "mode " + std::to_string(int(c.x_mode.w)) + " x " + show3(xyz(c.x_mode)) + " n_x " + show3(xyz(c.nx_offset)) +
           " y " + show3(xyz(c.y)) + " n_y " + show3(xyz(c.ny)) + " offset_relative " + show(c.nx_offset.w);
  };
  std::cout << "  callables: " << cases.size() << " cases, " << visible << " visible pairs, " << hits << " traced hits\n";
  // Software renderers: exact. Elsewhere a pair can flip only where the segment passes within
  // rounding of an edge; this test has no exemption for that and is written for the exact case.
  VPLKIT_CHECK_PARITY(compare_exact(answers, describe, "bvh_visible / bvh_trace / the callable structs: answers"));
  if (exact_device())
    VPLKIT_CHECK_PARITY(compare_floats(floats, within_ulps(0), [&](std::size_t k) { return describe(k / 7); },
                                       "traced position, offset point, surface offset"));
  else
    VPLKIT_CHECK_PARITY(vplkit_test::compare_within_bounds(floats, float_bounds,
                                                           [&](std::size_t k) { return describe(k / 7); },
                                                           "traced position, offset point, surface offset"));
  CHECK(visible > cases.size() / 20);
  CHECK(hits > cases.size() / 3);
}

TEST_CASE("bvh callables as the estimators' user visibility and tracer (visibility_callables.glsl)") {
  const tri_mesh m = vplkit_test::closed_room();
  const auto b = build(m);
  const gpu_bvh g(b);
  random_source rnd(211);
  std::vector<float4> in;
  for (int i = 0; i < 3000; ++i) {
    for (int k = 0; k < 2; ++k) {
      const std::size_t t = std::size_t(rnd.integer(0, int(m.triangle_count()) - 1));
      const v3f p = (m.vertex(t, 0) + m.vertex(t, 1) + m.vertex(t, 2)) / 3.0f;
      in.push_back(f4(p));
      in.push_back(f4(glm::cross(m.vertex(t, 1) - m.vertex(t, 0), m.vertex(t, 2) - m.vertex(t, 0))));
    }
  }
  auto inputs = g.bindings();
  inputs.push_back(input(0, in, "vec4 v"));
  const auto gpu = run_compute<float4>(per_item(std::string(R"(
#define VPLKIT_USER_VISIBILITY
#define VPLKIT_USER_TRACER
#include "vplkit/visibility/bvh_visibility.glsl"
#include "vplkit/visibility/visibility_callables.glsl"
)") + bvh_block + R"(
uint vplkit_load_voxel_word(uint word_index) { return 0u; }  // no voxel grid in this shader
bool vplkit_user_visible(vec3 x, vec3 n_x, vec3 y, vec3 n_y) { return vplkit_bvh_visible(scene_bvh(), x, n_x, y, n_y); }
vplkit_ray_hit vplkit_user_trace(vec3 x, vec3 n_x, vec3 dir) { return vplkit_bvh_trace(scene_bvh(), x, n_x, dir); }
)",
                                                inputs, "vec4 result", R"(
  vec3 x = v[4u * i].xyz, n_x = v[4u * i + 1u].xyz, y = v[4u * i + 2u].xyz, n_y = v[4u * i + 3u].xyz;
  vplkit_visibility vis = vplkit_make_always_visible();
  vis.kind = vplkit_visibility_user;
  vplkit_voxel_tracer tr = vplkit_make_voxel_tracer(vplkit_voxel_grid(vec3(0.0), vec3(1.0), ivec3(1)));
  tr.user = true;
  vplkit_ray_hit h = vplkit_voxel_tracer_trace(tr, x, n_x, y - x);
  result[i] = vec4(h.position, (vplkit_visibility_test(vis, x, n_x, y, n_y) ? 1.0 : 0.0) + (h.hit ? 2.0 : 0.0));)"),
                                       in.size() / 4);
  std::vector<float> gf, cf;
  std::vector<double> bounds;  // forward error bounds of both sides (parity_forward_error.hpp)
  const std::vector<std::size_t> slot_of_id = slots_of_ids(b);
  for (std::size_t i = 0; i < gpu.size(); ++i) {
    const v3f x = xyz(in[4 * i]), nx = xyz(in[4 * i + 1]), y = xyz(in[4 * i + 2]), ny = xyz(in[4 * i + 3]);
    const bool vis = vplkit::bvh_visibility<float>{b.view()}(x, nx, y, ny);
    const auto h = vplkit::bvh_tracer<float>{b.view()}(x, nx, y - x);
    gf.insert(gf.end(), {gpu[i].x, gpu[i].y, gpu[i].z, gpu[i].w});
    cf.insert(cf.end(), {h.position.x, h.position.y, h.position.z, (vis ? 1.0f : 0.0f) + (h.hit ? 2.0f : 0.0f)});
    const auto pb = traced_position_bound(b, slot_of_id, x, nx, y, float(vplkit::bvh_offset_relative_default));
    bounds.insert(bounds.end(), {pb[0], pb[1], pb[2], 0.0});
  }
  if (exact_device())
    VPLKIT_CHECK_PARITY(compare_floats(gf, cf, within_ulps(0), {}, "user visibility / tracer hooks: position, visible + 2 hit"));
  else
    VPLKIT_CHECK_PARITY(vplkit_test::compare_within_bounds(series<float>{gf, cf}, bounds, {},
                                                           "user visibility / tracer hooks: position, visible + 2 hit"));
}

TEST_CASE("bvh huge divisors: directions and normals from 2^126 to FLT_MAX, denormal and mixed components, det above 2^126") {
  // GLSL bounds x / y only for |y| <= 2^126; NVIDIA divides as x * (1 / y) with the reciprocal
  // flushed to 0 above, which turned such values into misses and NaN. The GPU is compared with the
  // C++ as everywhere in this file, and the C++ run under the CPU model of that division
  // (gpu_model_float.hpp, reciprocal_division_scope) is compared with the GPU: without the scaling
  // of bvh_ray.hpp the model misses every ray below and its unit vectors are NaN.
  random_source rnd(2126);
  parity_counts pc;
  series<std::uint32_t> model_answers;
  series<float> model_t;
  std::vector<double> model_t_bound;  // per ray: the forward error bound of t on both sides
  std::vector<std::string> model_rays;
  const auto against_model = [&](const vplkit::bvh<float>& b, const std::vector<ray_case>& rays,
                                 const std::vector<hit_result>& gpu) {
    const std::vector<std::size_t> slot_of_id = slots_of_ids(b);
    const vplkit_test::gpu_model_bvh mb(b);
    const vplkit_test::reciprocal_division_scope nvidia;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const auto o = vplkit_test::to_gpu_model(xyz(rays[i].o_tmin)), d = vplkit_test::to_gpu_model(xyz(rays[i].d_tmax));
      const bool ranged = rays[i].o_tmin.w >= 0.0f;
      const vplkit_test::gpu_float t_min(ranged ? rays[i].o_tmin.w : 0.0f), t_max(ranged ? rays[i].d_tmax.w : flt_inf);
      const auto h = vplkit::bvh_closest_hit(mb.view(), o, d, t_min, t_max);
      const bool occ = vplkit::bvh_occluded(mb.view(), o, d, t_min, t_max);
      model_answers.add(gpu[i].hit, h.hit ? 1u : 0u);
      model_answers.add(gpu[i].triangle, h.triangle);
      model_answers.add(gpu[i].occluded, occ ? 1u : 0u);
      model_t.add(gpu[i].t, float(h.t));
      double t_bound = 0.0;  // a miss: t is 0 on both sides
      if (h.hit && h.triangle < slot_of_id.size()) {
        const vplkit::bvh_triangle<float>& tri = b.triangles()[slot_of_id[h.triangle]];
        t_bound = 2 * woop_forward_error(vplkit_test::fe3_of(xyz(rays[i].o_tmin)),
                                         ray_direction_fe(xyz(rays[i].d_tmax)), tri.v0, tri.v1, tri.v2)
                          .t.e;
      }
      model_t_bound.push_back(t_bound);
      model_rays.push_back("o " + show3(xyz(rays[i].o_tmin)) + " d " + show3(xyz(rays[i].d_tmax)));
    }
  };
  {
    // Half extent 2^20: inside the triangle test's range (bvh_ray.hpp: edge functions are
    // quadratic in the coordinates), with t = distance / |dir| around 2^-107, still normal.
    tri_mesh m;
    m.box(v3d(0.0), v3d(std::ldexp(1.0, 20)), glm::dmat3(1.0), 3, true);
    const auto b = build(m);
    const auto rays = huge_direction_rays(rnd, m, 3000, std::ldexp(1.0, 20));
    const auto gpu = check_hits(m, b, rays, "room of half extent 2^20, directions above 2^126", pc);
    against_model(b, rays, gpu);
  }
  {
    // Vertices (-S, -S, 1), (S, -S, 1), (0, S, 1), S = 1.5 * 2^62: det = -9 * 2^124 for rays along
    // +z (t = 1, u = 1/4, v = 1/2 exactly from the origin), and of that size for the tilted ones.
    const float s = 1.5f * std::ldexp(1.0f, 62);
    tri_mesh m;
    m.tri(v3f(-s, -s, 1.0f), v3f(s, -s, 1.0f), v3f(0.0f, s, 1.0f));
    std::vector<ray_case> rays = {{f4(v3f(0.0f), 0.0f), f4(v3f(0.0f, 0.0f, 1.0f), flt_inf)},
                                  {f4(v3f(0.0f, 0.0f, -std::ldexp(1.0f, 100)), -1.0f), f4(v3f(0.0f, 0.0f, std::ldexp(1.0f, 127)), flt_inf)}};
    for (int i = 0; i < 200; ++i) {
      const v3f o(float(rnd.uniform(-0.3, 0.3) * s), float(rnd.uniform(-0.3, 0.3) * s), float(rnd.uniform(-4.0, 0.5)));
      v3f d(float(rnd.uniform(-0.1, 0.1) * s), float(rnd.uniform(-0.1, 0.1) * s), 1.0f);
      if (i % 2) {  // largest component in (2^126, 2^128) too
        const float dm = std::fmax(std::fabs(d.x), std::fmax(std::fabs(d.y), std::fabs(d.z)));
        d *= float(rnd.uniform(1.0000002, 3.99) * std::ldexp(1.0, 126) / double(dm));
      }
      rays.push_back({f4(o, i % 3 == 0 ? 0.0f : -1.0f), f4(d, i % 3 == 0 ? 10.0f : flt_inf)});
    }
    const auto b = build(m);
    const auto gpu = check_hits(m, b, rays, "one triangle with det above 2^126", pc);
    CHECK(gpu[0].hit == 1u);
    CHECK(gpu[0].t == 1.0f);
    against_model(b, rays, gpu);
  }
  std::cout << "  huge divisors: " << pc.rays << " rays, " << pc.hits << " hits\n";
  CHECK(pc.hits > pc.rays * 3 / 4);
  // Hits, triangles and occlusion exact (the rays keep clear of edges); t within the forward error
  // bound of Woop's chain on both sides, as in check_hits: a ray nearly parallel to the triangle's
  // plane makes t = (sum of e_i z_i) / det cancel, and the rounding of every step is amplified
  // there (the H200 read 139 ulps, 1.06e-5 relative, for a ray 1e-17 rad off a plane of this case,
  // against a bound of 1e-5 that was not derived from anything).
  VPLKIT_CHECK_PARITY(compare_exact(model_answers, [&](std::size_t k) { return model_rays[k / 3]; },
                                    "GPU vs C++ under NVIDIA's division: hit, triangle, occluded"));
  VPLKIT_CHECK_PARITY(vplkit_test::compare_within_bounds(model_t, model_t_bound,
                                                         [&](std::size_t k) { return model_rays[k]; },
                                                         "GPU vs C++ under NVIDIA's division: t"));

  // Unit vectors (the normal of bvh_offset_point and of a hit): the GPU against the C++, and the
  // C++ under NVIDIA's division against the double reference.
  const std::vector<v3f> vs = huge_vectors();
  std::vector<float4> in;
  for (const v3f& v : vs) in.push_back(f4(v));
  const auto gpu = run_compute<float4>(
      per_item(R"(#include "vplkit/visibility/bvh_ray.glsl")", {input(0, in, "vec4 v")}, "vec4 result",
               "  result[i] = vec4(vplkit_bvh_unit_vector(v[i].xyz), 0.0);"),
      in.size());
  series<float> unit_gpu;
  series<float, double> unit_model;
  for (std::size_t i = 0; i < vs.size(); ++i) {
    const v3f c = vplkit::detail::bvh_unit_vector(vs[i]);
    v3f model;
    {
      const vplkit_test::reciprocal_division_scope nvidia;
      model = vplkit_test::of_gpu_model(vplkit::detail::bvh_unit_vector(vplkit_test::to_gpu_model(vs[i])));
    }
    const v3d d(vs[i]);
    const double m = std::fmax(std::fabs(d.x), std::fmax(std::fabs(d.y), std::fabs(d.z)));
    const v3d ref = (d / m) / std::sqrt(glm::dot(d / m, d / m));
    for (int k = 0; k < 3; ++k) {
      unit_gpu.add(gpu[i][k], c[k]);
      unit_model.add(model[k], ref[k]);
    }
  }
  const auto describe_v = [&](std::size_t k) { return "v = " + show3(vs[k / 3]); };
  // Exact, but for a component below FLT_MIN ((2^126 + ulp, 1, 0) has one), which the [ftz-daz]
  // reference flushes and llvmpipe keeps.
  if (exact_device())
    VPLKIT_CHECK_PARITY(compare_floats(unit_gpu, within_ulps(0) | within_abs(1.17549435e-38), describe_v,
                                       "bvh_unit_vector: GPU vs C++"));
  else  // two divisions and a square root of unit-sized values, on both sides
    VPLKIT_CHECK_PARITY(compare_floats(unit_gpu, within_abs(1e-6), describe_v, "bvh_unit_vector: GPU vs C++"));
  VPLKIT_CHECK_PARITY(compare_floats(unit_model, within_abs(1e-6), describe_v,
                                     "bvh_unit_vector: C++ under NVIDIA's division vs double"));
}
