// SPDX-License-Identifier: MIT
// CPU/GPU parity of glsl/vplkit/visibility/*.glsl and the kernel voxelize.comp with
// include/vplkit/visibility/*.hpp (T = float): triangle/box overlap, conservative voxelisation,
// the 3D DDA (first hit, trace point), surface ray origins and point-to-point visibility.
//
// Why exact answers are expected, and where they may legitimately differ:
// - triangle_box_overlap uses only + - * abs and comparisons, written out in glm's order and
//   `precise` in GLSL. GLSL 4.30 (4.7.1) makes + - * correctly rounded, so the GPU answer is the
//   C++ float answer on every conforming implementation, near-tangent cases included. Required
//   exact everywhere.
// - The DDA and the visibility tests also divide and take square roots. With correctly rounded
//   division and sqrt (llvmpipe; GPUs with IEEE-exact div/sqrt) the march is the C++ march bit
//   for bit, t included: required exact on software renderers. GLSL itself allows 2.5 ulp
//   division and 3 ulp sqrt; on such GPUs t moves within the forward error bound of its plane
//   crossing (hundreds of ulps where it cancels near 0; parity_forward_error.hpp, also used for
//   the [fma] build, whose reference contracts a*b+c) and a voxel can differ only at a
//   near-tie: a ray within eps = 1e-4 voxel of an occupied voxel's edge or corner, or whose t_max
//   lies within eps of an entry distance. There, a difference is accepted only if the ray is such
//   a tie (checked by brute force: closed boxes grown and shrunk by eps disagree), and counted.
// - voxelize.comp works in float where the C++ converts to voxel coordinates and tests in double.
//   A voxel can then differ only if its SAT distance to the mesh lies within float rounding of the
//   margin (1e-4 voxel). The test measures the differing voxels, requires each to lie within
//   delta = 2e-5 voxel of the margin shell (flip margin found by bisection in double), and bounds
//   their number.
#include <bvh_test_scenes.hpp>
#include <parity_fma_model.hpp>
#include <parity_forward_error.hpp>
#include <parity_harness.hpp>
#include <uncontracted_reference.hpp>
#include <voxel_cells.hpp>

#include <vplkit/visibility/dda.hpp>
#include <vplkit/visibility/voxel_bricks.hpp>
#include <vplkit/visibility/triangle_box_overlap.hpp>
#include <vplkit/visibility/voxel_grid.hpp>
#include <vplkit/visibility/voxel_visible.hpp>
#include <vplkit/visibility/voxelize.hpp>
#include <vplkit/visibility/voxelize_params.h>

#include <glm/mat3x3.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iostream>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

using namespace vplkit::parity;
using vplkit::ivec3;
using vplkit::vec3;
using vplkit_test::flt_inf;
using vplkit_test::flt_max;
using vplkit_test::flt_min;
using vplkit_test::flt_nan;
using vplkit_test::random_source;
using vplkit_test::rotation;
using vplkit_test::v3d;
using vplkit_test::v3f;
using dmat3 = glm::mat<3, 3, double>;

namespace {

// Software renderers (llvmpipe, softpipe) divide and take square roots correctly rounded; with the
// plain reference (not the [fma] build, which contracts a*b+c) they round every value alike.
bool ieee_div_sqrt() { return software_renderer() && !vplkit_test::reference_contracts; }

// The forward error bound (parity_forward_error.hpp) of a DDA entry distance t of voxel v, both
// sides: t is a plane crossing (bounds_min[a] + k * size[a] - origin[a]) / d[a] with size =
// (bounds_max - bounds_min) / resolution and d the unit direction (dda_unit_direction); the grid's
// own faces (k = 0 or n) give the same value with fewer roundings. Of the three axes, the one whose
// crossing lies nearest t is the plane the ray entered through. 0 where t is 0 on the plane side.
struct dda_float_bounds {
  double t = 0;
  double point[3] = {0, 0, 0};
};
dda_float_bounds dda_forward_error(const vplkit::voxel_grid<float>& g, v3f o, v3f dir, ivec3 v, float t) {
  using vplkit_test::fe;
  dda_float_bounds out;
  const vplkit_test::fe3 d = vplkit_test::fe_unit_vector(vplkit_test::fe3_of(dir));
  const v3f bmin = g.bounds_min(), bmax = g.bounds_max();
  const ivec3 res = g.resolution();
  fe best(0.0, 0.0);
  double best_gap = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    if (!(std::fabs(d[a].v) >= 1.17549435e-38)) continue;
    const fe size = (fe(bmax[a]) - fe(bmin[a])) / fe(double(res[a]));
    const int k = d[a].v > 0 ? v[a] : v[a] + 1;
    const fe ta = (fe(bmin[a]) + fe(double(k)) * size - fe(o[a])) / d[a];
    const double gap = std::fabs(ta.v - double(t));
    if (gap < best_gap) {
      best_gap = gap;
      best = ta;
    }
  }
  if (!std::isfinite(best_gap)) return out;
  out.t = 2 * best.e;
  for (int k = 0; k < 3; ++k) out.point[k] = 2 * (fe(o[k]) + best * d[k]).e;
  return out;
}

// ---- the grids the C++ side builds, uploaded as they are ---------------------------------------

struct grid_params {  // std430 { vec4 bmin; vec4 bmax; ivec4 res; }
  float4 bmin, bmax;
  int4 res;
};
grid_params params_of(const vplkit::voxel_grid<float>& g) {
  const ivec3 r = g.resolution();
  return {f4(g.bounds_min()), f4(g.bounds_max()), {r.x, r.y, r.z, 0}};
}

// A kernel over grid g (words at binding 2, bounds and resolution at 3): `source` (includes,
// types), then the grid accessors, the caller's queries (binding 0), its output and body.
kernel_call grid_kernel(const vplkit::voxel_grid<float>& g, const std::string& source, std::vector<ssbo> queries,
                        const std::string& output_glsl, const std::string& body) {
  queries.insert(queries.end(), {input(2, g.words()), input(3, std::vector<grid_params>{params_of(g)})});
  return per_item(source + R"(
layout(std430, binding = 2) readonly buffer Words { uint words[]; };
layout(std430, binding = 3) readonly buffer Grid { vec4 gmin; vec4 gmax; ivec4 gres; };
uint vplkit_load_voxel_word(uint i) { return words[i]; }
vplkit_voxel_grid grid() { return vplkit_voxel_grid(gmin.xyz, gmax.xyz, gres.xyz); }
)",
                  std::move(queries), output_glsl, body);
}

// Brute-force first hit of o + t d (d unit), t in [0, t_max], over every occupied voxel with its
// closed box grown by `grow` voxels (negative: shrunk), in double.
struct brute_hit {
  bool hit;
  double t;
  ivec3 voxel;
};
brute_hit brute_first_hit(const vplkit::voxel_grid<float>& g, const std::vector<ivec3>& occupied, v3d o, v3d d,
                          double t_max, double grow) {
  const v3d bmin(g.bounds_min()), size(g.voxel_size());
  brute_hit best{false, std::numeric_limits<double>::infinity(), ivec3(-1)};
  for (const ivec3& v : occupied) {
    const v3d lo = bmin + v3d(v) * size - grow * size, hi = bmin + v3d(v + 1) * size + grow * size;
    double t0 = 0.0, t1 = t_max;
    bool ok = true;
    for (int a = 0; a < 3 && ok; ++a) {
      if (d[a] == 0.0) {
        ok = o[a] >= lo[a] && o[a] <= hi[a];
        continue;
      }
      double ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
      ok = t0 <= t1;
    }
    if (ok && t0 < best.t) best = {true, t0, v};
  }
  return best;
}

// A ray is a near-tie when the first hit with every occupied box grown by eps voxels and the one
// with every box shrunk by eps differ (in hit/miss or voxel): rounding of a few ulp can then change
// the DDA's answer. Non-finite or zero-length rays are never ties (both sides must miss).
bool dda_near_tie(const vplkit::voxel_grid<float>& g, const std::vector<ivec3>& occupied, v3f o, v3f dir,
                  float t_max, double eps = 1e-4) {
  v3f d(0.0f);
  if (!vplkit::dda_unit_direction(dir, d) || !vplkit::detail::voxel_vec3_finite(o) || !(t_max >= 0.0f)) return false;
  const brute_hit grown = brute_first_hit(g, occupied, v3d(o), v3d(d), double(t_max), eps);
  const brute_hit shrunk = brute_first_hit(g, occupied, v3d(o), v3d(d), double(t_max), -eps);
  return grown.hit != shrunk.hit || grown.voxel != shrunk.voxel;
}

// ---- DDA kernel ---------------------------------------------------------------------------------

struct dda_ray {  // std430 { vec4 origin_tmax; vec4 dir; }
  float4 origin_tmax;
  float4 dir;
};
struct dda_out {  // 13 scalars, std430 stride 52
  std::uint32_t hit;
  float t;
  std::int32_t x, y, z;
  std::uint32_t trace_hit;
  float trace_t;
  std::int32_t tx, ty, tz;
  float px, py, pz;
};
static_assert(sizeof(dda_out) == 52, "std430 layout of dda_out");

std::vector<dda_out> gpu_dda(const vplkit::voxel_grid<float>& g, const std::vector<dda_ray>& rays) {
  return run_compute<dda_out>(grid_kernel(g, R"(
#include "vplkit/visibility/dda.glsl"
struct dda_ray { vec4 origin_tmax; vec4 dir; };
struct dda_out { uint hit; float t; int x, y, z; uint trace_hit; float trace_t; int tx, ty, tz;
                 float px, py, pz; };
)",
                                          {input(0, rays, "dda_ray rays")}, "dda_out result", R"(
  vec3 o = rays[i].origin_tmax.xyz;
  float t_max = rays[i].origin_tmax.w;
  vec3 d = rays[i].dir.xyz;
  // t_max = +inf goes through the overloads without t_max (the C++ default argument).
  bool no_limit = floatBitsToUint(t_max) == 0x7F800000u;
  vplkit_dda_hit h = no_limit ? vplkit_dda_first_hit(grid(), o, d) : vplkit_dda_first_hit(grid(), o, d, t_max);
  vplkit_dda_trace_result r = no_limit ? vplkit_dda_trace_hit_point(grid(), o, d)
                                       : vplkit_dda_trace_hit_point(grid(), o, d, t_max);
  result[i] = dda_out(h.hit ? 1u : 0u, h.t, h.voxel.x, h.voxel.y, h.voxel.z, r.hit ? 1u : 0u, r.t,
                      r.voxel.x, r.voxel.y, r.voxel.z, r.point.x, r.point.y, r.point.z);)"),
                              rays.size());
}

dda_out cpu_dda(const vplkit::voxel_grid<float>& g, const dda_ray& r) {
  const v3f o(r.origin_tmax.x, r.origin_tmax.y, r.origin_tmax.z), d(r.dir.x, r.dir.y, r.dir.z);
  const float t_max = r.origin_tmax.w;
  const auto h = vplkit::dda_first_hit(g.view(), o, d, t_max);
  const auto tr = vplkit::dda_trace_hit_point(g.view(), o, d, t_max);
  return {h.hit ? 1u : 0u, h.t, h.voxel.x, h.voxel.y, h.voxel.z, tr.hit ? 1u : 0u, tr.t,
          tr.voxel.x, tr.voxel.y, tr.voxel.z, tr.point.x, tr.point.y, tr.point.z};
}

// t: a few ulp of division error per crossing on GPUs with GLSL-minimum division (2.5 ulp); 4 ulps
// or 1e-6 voxel (t near 0, where ulps shrink but the plane - origin difference does not). The
// trace point adds one multiply-add per component: 8 ulps or 2e-6 voxel lengths times the
// coordinate scale. Measured on llvmpipe: 0 (bit-exact).
struct dda_summary {
  std::size_t rays = 0, hits = 0, tie_differences = 0;
};

void check_dda(const vplkit::voxel_grid<float>& g, const std::vector<dda_ray>& rays, const std::string& what,
               dda_summary* summary = nullptr) {
  const auto gpu = gpu_dda(g, rays);
  std::vector<dda_out> cpu;
  cpu.reserve(rays.size());
  for (const auto& r : rays) cpu.push_back(cpu_dda(g, r));
  const std::vector<ivec3> occupied = vplkit_test::occupied_voxels(g);
  auto ray_text = [&](std::size_t i) {
    const auto& r = rays[i];
    return "origin " + show3(v3f(r.origin_tmax.x, r.origin_tmax.y, r.origin_tmax.z)) + " dir " +
           show3(v3f(r.dir.x, r.dir.y, r.dir.z)) + " t_max " + show(r.origin_tmax.w) + " | cpu hit " +
           std::to_string(cpu[i].hit) + " voxel " + showi3(ivec3(cpu[i].x, cpu[i].y, cpu[i].z)) + " t " +
           show(cpu[i].t) + " | gpu hit " + std::to_string(gpu[i].hit) + " voxel " +
           showi3(ivec3(gpu[i].x, gpu[i].y, gpu[i].z)) + " t " + show(gpu[i].t);
  };

  // Integer results: exact, except (on GPUs without correctly rounded div/sqrt) at near-ties.
  auto ints = [](const dda_out& o) {
    return std::vector<std::int32_t>{std::int32_t(o.hit), o.x, o.y, o.z, std::int32_t(o.trace_hit), o.tx, o.ty, o.tz};
  };
  std::vector<std::int32_t> gpu_ints, cpu_ints;
  std::vector<bool> same(rays.size(), true);
  std::size_t hits = 0, tie_diffs = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    std::vector<std::int32_t> gk = ints(gpu[i]);
    const std::vector<std::int32_t> ck = ints(cpu[i]);
    hits += cpu[i].hit;
    if (gk != ck) {
      same[i] = false;
      const auto& r = rays[i];
      if (!ieee_div_sqrt() && dda_near_tie(g, occupied, v3f(r.origin_tmax.x, r.origin_tmax.y, r.origin_tmax.z),
                                           v3f(r.dir.x, r.dir.y, r.dir.z), r.origin_tmax.w)) {
        ++tie_diffs;
        gk = ck;  // a legitimate difference at a near-tie: counted, not failed
      }
    }
    gpu_ints.insert(gpu_ints.end(), gk.begin(), gk.end());
    cpu_ints.insert(cpu_ints.end(), ck.begin(), ck.end());
  }
  VPLKIT_CHECK_PARITY(compare_exact(gpu_ints, cpu_ints, [&](std::size_t k) { return ray_text(k / 8); },
                                    what + ": hit and voxel (first_hit, trace)"));
  std::cout << "  " << what << ": " << rays.size() << " rays, " << hits << " hits, "
            << (ieee_div_sqrt() ? "IEEE div/sqrt: ties must match too"
                                : std::to_string(tie_diffs) + " differences at near-ties (allowed)")
            << "\n";
  if (summary) {
    summary->rays += rays.size();
    summary->hits += hits;
    summary->tie_differences += tie_diffs;
  }

  // Floats where both sides name the same voxel.
  std::vector<float> gt, ct, gp, cp;
  std::vector<double> t_bounds, p_bounds;
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (!same[i]) continue;
    idx.push_back(i);
    const dda_out& c = cpu[i];
    const dda_float_bounds fb =
        c.hit ? dda_forward_error(g, v3f(rays[i].origin_tmax.x, rays[i].origin_tmax.y, rays[i].origin_tmax.z),
                                  v3f(rays[i].dir.x, rays[i].dir.y, rays[i].dir.z), ivec3(c.x, c.y, c.z), c.t)
              : dda_float_bounds{};
    t_bounds.insert(t_bounds.end(), {fb.t, fb.t});
    p_bounds.insert(p_bounds.end(), {fb.point[0], fb.point[1], fb.point[2]});
    gt.push_back(gpu[i].t);
    ct.push_back(cpu[i].t);
    gt.push_back(gpu[i].trace_t);
    ct.push_back(cpu[i].trace_t);
    gp.insert(gp.end(), {gpu[i].px, gpu[i].py, gpu[i].pz});
    cp.insert(cp.end(), {cpu[i].px, cpu[i].py, cpu[i].pz});
  }
  // Bit for bit where the device rounds like the reference; elsewhere within the forward error
  // bound of the crossing (dda_forward_error; H200: t moved by up to 611 ulps where the origin lies
  // near the entry plane, so that the difference cancels).
  if (ieee_div_sqrt()) {
    VPLKIT_CHECK_PARITY(compare_floats(gt, ct, within_ulps(0), [&](std::size_t k) { return ray_text(idx[k / 2]); },
                                       what + ": t (first_hit, trace)"));
    VPLKIT_CHECK_PARITY(compare_floats(gp, cp, within_ulps(0), [&](std::size_t k) { return ray_text(idx[k / 3]); },
                                       what + ": trace point"));
  } else {
    VPLKIT_CHECK_PARITY(vplkit_test::compare_within_bounds(
        series<float>{gt, ct}, t_bounds, [&](std::size_t k) { return ray_text(idx[k / 2]); },
        what + ": t (first_hit, trace)"));
    VPLKIT_CHECK_PARITY(vplkit_test::compare_within_bounds(
        series<float>{gp, cp}, p_bounds, [&](std::size_t k) { return ray_text(idx[k / 3]); }, what + ": trace point"));
  }
}

// A random grid: resolution 1..40 per axis, bounds anywhere in [-10, 10] with extents 0.5..20,
// occupancy 1..20 %.
vplkit::voxel_grid<float> random_grid(random_source& rnd) {
  ivec3 res(0);
  v3f bmin(0.0f), bmax(0.0f);  // every component is set below; GCC -O3 cannot see it
  for (int a = 0; a < 3; ++a) {
    res[a] = rnd.unit() < 0.1 ? rnd.integer(1, 3) : rnd.integer(4, 40);
    bmin[a] = float(rnd.uniform(-10.0, 10.0));
    bmax[a] = bmin[a] + float(rnd.uniform(0.5, 20.0));
  }
  vplkit::voxel_grid<float> g(bmin, bmax, res);
  const double density = rnd.uniform(0.01, 0.2);
  for (int z = 0; z < res.z; ++z)
    for (int y = 0; y < res.y; ++y)
      for (int x = 0; x < res.x; ++x)
        if (rnd.unit() < density) g.set(ivec3(x, y, z));
  return g;
}

std::vector<dda_ray> random_rays(random_source& rnd, const vplkit::voxel_grid<float>& g, int n) {
  std::vector<dda_ray> rays;
  const v3f bmin = g.bounds_min(), bmax = g.bounds_max();
  const double diag = double(glm::length(bmax - bmin));
  for (int i = 0; i < n; ++i) {
    const double pad = (i % 2 == 1) ? 0.6 : 0.0;  // half the origins in a shell around the box
    v3f o;
    for (int a = 0; a < 3; ++a) {
      const double lo = bmin[a], ext = double(bmax[a]) - lo;
      o[a] = float(lo - pad * ext + rnd.unit() * (1.0 + 2.0 * pad) * ext);
    }
    v3f d = v3f(rnd.direction()) * float(std::pow(10.0, rnd.uniform(-3.0, 3.0)));  // any length
    if (i % 17 == 0) d[rnd.integer(0, 2)] = 0.0f;  // rays in an axis plane
    if (i % 23 == 0) {                             // rays along an axis
      const int a = rnd.integer(0, 2);
      d = v3f(0.0f);
      d[a] = rnd.unit() < 0.5 ? -1.0f : 1.0f;
    }
    const float t_max = (i % 3 == 0) ? float(rnd.uniform(0.0, 1.5 * diag)) : flt_inf;
    rays.push_back({f4(o, t_max), f4(d)});
  }
  return rays;
}

// ---- voxel_visible kernel -----------------------------------------------------------------------

struct visible_case {  // std430 { vec4 x_offset; vec4 nx_mode; vec4 y_tolerance; vec4 ny; }
  float4 x_offset;     // xyz: x, w: offset_voxels
  float4 nx_mode;      // xyz: n_x, w: mode (0 one-sided, 1 two-sided, 2/3 the same with defaults)
  float4 y_tolerance;  // xyz: y, w: tolerance_voxels
  float4 ny;
};

const std::string visible_source = R"(
#include "vplkit/visibility/voxel_visible.glsl"
struct visible_case { vec4 x_offset; vec4 nx_mode; vec4 y_tolerance; vec4 ny; };
)";
const std::string visible_body = R"(
  visible_case c = cases[i];
  int mode = int(c.nx_mode.w);
  bool v;
  if (mode == 0) v = vplkit_voxel_visible(grid(), c.x_offset.xyz, c.nx_mode.xyz, c.y_tolerance.xyz,
                                          c.x_offset.w, c.y_tolerance.w);
  else if (mode == 1) v = vplkit_voxel_visible_two_sided(grid(), c.x_offset.xyz, c.nx_mode.xyz,
                                                         c.y_tolerance.xyz, c.ny.xyz, c.x_offset.w, c.y_tolerance.w);
  else if (mode == 2) v = vplkit_voxel_visible(grid(), c.x_offset.xyz, c.nx_mode.xyz, c.y_tolerance.xyz);
  else v = vplkit_voxel_visible_two_sided(grid(), c.x_offset.xyz, c.nx_mode.xyz, c.y_tolerance.xyz, c.ny.xyz);
  result[i] = v ? 1u : 0u;)";

bool cpu_visible(const vplkit::voxel_grid<float>& g, const visible_case& c) {
  const v3f x(c.x_offset.x, c.x_offset.y, c.x_offset.z), nx(c.nx_mode.x, c.nx_mode.y, c.nx_mode.z);
  const v3f y(c.y_tolerance.x, c.y_tolerance.y, c.y_tolerance.z), ny(c.ny.x, c.ny.y, c.ny.z);
  switch (int(c.nx_mode.w)) {
    case 0: return vplkit::voxel_visible(g.view(), x, nx, y, c.x_offset.w, c.y_tolerance.w);
    case 1: return vplkit::voxel_visible_two_sided(g.view(), x, nx, y, ny, c.x_offset.w, c.y_tolerance.w);
    case 2: return vplkit::voxel_visible(g.view(), x, nx, y);
    default: return vplkit::voxel_visible_two_sided(g.view(), x, nx, y, ny);
  }
}

// The segment the C++ test marches, and whether its answer sits within `band` (world units) of
// flipping: the first occupied voxel's entry distance (marching without a limit) within band of
// t_max.
bool visible_near_boundary(const vplkit::voxel_grid<float>& g, const visible_case& c, double band) {
  const int mode = int(c.nx_mode.w);
  const bool two = mode == 1 || mode == 3;
  const float offset = mode >= 2 ? float(vplkit::voxel_surface_offset_default) : c.x_offset.w;
  const float tol = mode >= 2 ? float(two ? vplkit::voxel_visible_two_sided_default_tolerance
                                          : vplkit::voxel_visible_default_tolerance)
                              : c.y_tolerance.w;
  const v3f x(c.x_offset.x, c.x_offset.y, c.x_offset.z), nx(c.nx_mode.x, c.nx_mode.y, c.nx_mode.z);
  const v3f y(c.y_tolerance.x, c.y_tolerance.y, c.y_tolerance.z), ny(c.ny.x, c.ny.y, c.ny.z);
  if (!vplkit::detail::voxel_vec3_finite(x) || !vplkit::detail::voxel_vec3_finite(y)) return false;
  const v3f o = vplkit::surface_ray_origin(g.view(), x, nx, offset);
  const v3f target = two ? vplkit::surface_ray_origin(g.view(), y, ny, offset) : y;
  const double t_max = double(glm::length(target - o)) - double(tol) * double(g.voxel_length());
  if (std::abs(t_max) <= band) return true;
  if (t_max <= 0.0) return false;
  const auto h = vplkit::dda_first_hit(g.view(), o, target - o);
  return h.hit && std::abs(double(h.t) - t_max) <= band;
}

// ---- meshes -------------------------------------------------------------------------------------

using mesh = vplkit_test::tri_mesh;

// ---- voxelize.comp ------------------------------------------------------------------------------

std::vector<std::uint32_t> gpu_voxelize(const vplkit::voxel_grid<float>& like, const mesh& m, float margin) {
  const auto& prog = pack_kernel("vplkit/visibility/voxelize.comp",
                                 "#define VPLKIT_VOXELIZE_BINDING_POSITIONS 4\n"
                                 "#define VPLKIT_VOXELIZE_BINDING_INDICES 5\n"
                                 "#define VPLKIT_VOXELIZE_BINDING_WORDS 6\n"
                                 "#define VPLKIT_VOXELIZE_BINDING_PARAMS 1\n"
                                 "#define VPLKIT_VOXELIZE_LOCAL_SIZE 64\n");
  std::vector<float4> pos;
  for (const v3f& p : m.positions) pos.push_back(f4(p, 1.0f));
  const vplkit::gpu::voxelize_params params = vplkit_test::voxelize_block(like, m.indices.size() / 3, margin);
  const auto pb = vplkit::gl::buffer::from_vector(pos);
  const auto ib = vplkit::gl::buffer::from_vector(m.indices);
  const auto wb = vplkit::gl::buffer::filled(like.word_count() * 4, 0);
  const auto ub = vplkit_test::uniform_buffer(params);
  // One work group per triangle, spread over y past 65535.
  vplkit_test::dispatch(prog, vplkit_test::spread_groups(m.indices.size() / 3),
                        {vplkit_test::storage_at(4, pb), vplkit_test::storage_at(5, ib), vplkit_test::storage_at(6, wb),
                         vplkit_test::uniform_at(1, ub)});
  return wb.read<std::uint32_t>();
}

// Compares the GPU grid with the C++ voxelize() grid. Every differing voxel must lie within `delta`
// voxel of the margin shell, and there may be at most max_diff of them.
void check_voxelize(const vplkit::voxel_grid<float>& shape, const mesh& m, const std::string& what,
                    std::size_t max_diff, double delta = 2e-5) {
  const double margin = vplkit::voxelize_default_margin;
  vplkit::voxel_grid<float> cpu(shape.bounds_min(), shape.bounds_max(), shape.resolution());
  vplkit::voxelize(cpu, m.positions.data(), m.positions.size(), m.indices.data(), m.indices.size(), margin);
  const std::vector<std::uint32_t> gpu_words = gpu_voxelize(shape, m, float(margin));
  const vplkit::voxel_grid<float> gpu(shape.bounds_min(), shape.bounds_max(), shape.resolution(), gpu_words);
  REQUIRE(gpu_words.size() == cpu.word_count());
  CHECK(gpu_words == gpu.words());  // no bit past the last voxel was set
  std::size_t only_gpu = 0, only_cpu = 0, far = 0;
  double worst = 0.0;
  const ivec3 r = shape.resolution();
  for (int z = 0; z < r.z; ++z)
    for (int y = 0; y < r.y; ++y)
      for (int x = 0; x < r.x; ++x) {
        const ivec3 c(x, y, z);
        if (gpu.test(c) == cpu.test(c)) continue;
        (gpu.test(c) ? only_gpu : only_cpu) += 1;
        const double fm = vplkit_test::voxel_flip_margin(shape, m, c, 0.01);
        worst = std::max(worst, std::abs(fm - margin));
        if (std::abs(fm - margin) > delta) {
          ++far;
          UNSCOPED_INFO("voxel " << showi3(c) << (gpu.test(c) ? " only on the GPU" : " only on the CPU")
                                 << ", flip margin " << fm << " voxel");
        }
      }
  std::cout << "  voxelize " << what << ": " << cpu.count() << " voxels on the CPU, " << gpu.count()
            << " on the GPU; differing: " << only_gpu << " only GPU, " << only_cpu
            << " only CPU (bound " << max_diff << "), worst |flip margin - margin| " << worst
            << " voxel (bound " << delta << ")\n";
  CHECK(far == 0);
  CHECK(only_gpu + only_cpu <= max_diff);
  CHECK(cpu.count() > 0);
}

}  // namespace

// ==== triangle_box_overlap =========================================================================

namespace {

struct tb_case {  // std430 { vec4 center; vec4 half_size; vec4 a; vec4 b; vec4 c; }
  float4 center, half_size, a, b, c;
};


// Runs the cases on both sides; exact. Also reports how many are near-tangent: the float answer
// differs from the same test in double on the same (float) inputs, i.e. rounding decided them.
void check_triangle_box(const std::vector<tb_case>& cases, const std::string& what) {
  const auto gpu = run_compute<std::uint32_t>(
      per_item(R"(
#include "vplkit/visibility/triangle_box_overlap.glsl"
struct tb_case { vec4 center; vec4 half_size; vec4 a; vec4 b; vec4 c; };
)",
               {input(0, cases, "tb_case cases")}, "uint result", R"(
  tb_case k = cases[i];
  result[i] = vplkit_triangle_box_overlap(k.center.xyz, k.half_size.xyz, k.a.xyz, k.b.xyz, k.c.xyz) ? 1u : 0u;)"),
      cases.size());
  std::vector<std::uint32_t> cpu;
  std::size_t overlaps = 0, near_tangent = 0;
  for (const auto& k : cases) {
    // The GLSL is `precise`: the reference rounds every product, also in the [fma] program.
    const bool f = vplkit_test::uncontracted_triangle_box_overlap(xyz(k.center), xyz(k.half_size), xyz(k.a),
                                                                  xyz(k.b), xyz(k.c));
    const bool d = vplkit::triangle_box_overlap(v3d(xyz(k.center)), v3d(xyz(k.half_size)), v3d(xyz(k.a)),
                                                v3d(xyz(k.b)), v3d(xyz(k.c)));
    cpu.push_back(f ? 1u : 0u);
    overlaps += f;
    near_tangent += f != d;
  }
  VPLKIT_CHECK_PARITY(compare_exact(
      gpu, cpu,
      [&](std::size_t i) {
        const auto& k = cases[i];
        return "centre " + show3(xyz(k.center)) + " half " + show3(xyz(k.half_size)) + " a " + show3(xyz(k.a)) +
               " b " + show3(xyz(k.b)) + " c " + show3(xyz(k.c));
      },
      what));
  std::cout << "  " << what << ": " << cases.size() << " cases, " << overlaps << " overlap, " << near_tangent
            << " decided by float rounding (float != double answer), all required exact\n";
}

}  // namespace

TEST_CASE("uncontracted reference: its translation unit rounds every product, also in the [fma] program") {
  // a * b = 1 + 2^-11 + 2^-24 exactly; rounded it is 1 + 2^-11 (a tie, to even), so a * b + c with
  // c = -(1 + 2^-11) is 0 when the product is rounded and 2^-24 when it is fused. Without this, an
  // [fma] program whose reference lost -ffp-contract=off would compare with a contracting reference
  // and fail the exact cases below only where contraction happens to flip one.
  volatile float a = 1.0f + 0x1p-12f;
  volatile float b = 1.0f + 0x1p-12f;
  volatile float c = -(1.0f + 0x1p-11f);
  const float r = vplkit_test::uncontracted_multiply_add(a, b, c);
  INFO("a * b + c = " << show(r) << " (2^-24: contracted)");
  CHECK(r == 0.0f);
}

TEST_CASE("triangle_box_overlap: 2 x 10^5 random and degenerate triangles, exact") {
  random_source rnd(7);
  std::vector<tb_case> cases;
  for (int i = 0; i < 200000; ++i) {
    // Box: centre in [-1, 1]^3, half sizes 0.01..1 (flat boxes and zero size too). Triangle around
    // the box at a random scale, so that overlap and separation are both common.
    const v3f centre(float(rnd.uniform(-1, 1)), float(rnd.uniform(-1, 1)), float(rnd.uniform(-1, 1)));
    v3f half(float(rnd.uniform(0.01, 1)), float(rnd.uniform(0.01, 1)), float(rnd.uniform(0.01, 1)));
    if (i % 50 == 0) half[rnd.integer(0, 2)] = 0.0f;
    if (i % 97 == 0) half = v3f(0.0f);
    const double scale = std::pow(10.0, rnd.uniform(-2.0, 1.0));
    const v3f base = centre + v3f(rnd.direction()) * float(rnd.uniform(0.0, 2.0));
    v3f p[3];
    for (v3f& q : p) q = base + v3f(rnd.direction()) * float(scale * rnd.uniform(0.0, 1.5));
    switch (i % 20) {
      case 0: p[2] = p[1]; break;                                                   // segment
      case 1: p[1] = p[2] = p[0]; break;                                            // point
      case 2: p[2] = p[0] + (p[1] - p[0]) * float(rnd.uniform(-1.0, 2.0)); break;   // collinear
      case 3: {  // two vertices share a coordinate
        const int a = rnd.integer(0, 2);
        p[1][a] = p[0][a];
        break;
      }
      case 4: {  // axis-aligned triangle (normal along an axis)
        const int a = rnd.integer(0, 2);
        p[1][a] = p[2][a] = p[0][a];
        break;
      }
      default: break;
    }
    cases.push_back({f4(centre), f4(half), f4(p[0]), f4(p[1]), f4(p[2])});
  }
  check_triangle_box(cases, "random triangles vs random boxes");
}

TEST_CASE("triangle_box_overlap: exact touching cases and near-tangent cases (+-1 ulp)") {
  // Touching (closed sets): dyadic coordinates, so every product and sum is exact on both sides.
  // Unit box at the origin, half 0.5.
  std::vector<tb_case> cases;
  const float4 c0 = f4(v3f(0.0f)), h0 = f4(v3f(0.5f));
  auto add = [&](v3f a, v3f b, v3f c) { cases.push_back({c0, h0, f4(a), f4(b), f4(c)}); };
  // vertex on a face / edge / corner; edge along a box edge; triangle in a face plane; triangle
  // touching only along an edge axis (the cross-product axes decide).
  add(v3f(0.5f, 0, 0), v3f(1, 0.25f, 0), v3f(1, -0.25f, 0.25f));
  add(v3f(0.5f, 0.5f, 0), v3f(1, 1, 0), v3f(1, 0.5f, 0.5f));
  add(v3f(0.5f, 0.5f, 0.5f), v3f(1, 1, 1), v3f(1, 0.5f, 1));
  add(v3f(0.5f, 0.5f, -1), v3f(0.5f, 0.5f, 1), v3f(1, 1, 0));
  add(v3f(-1, -1, 0.5f), v3f(1, -1, 0.5f), v3f(0, 1, 0.5f));
  add(v3f(0, 1, 0), v3f(1, 0, 0), v3f(1, 1, 1));        // plane x + y = 1 touches the edge (0.5, 0.5, z)
  add(v3f(0, 1, 0), v3f(1, 0, 0), v3f(1, 1, 0.25f));    // the same, tilted
  add(v3f(0.75f, 0.75f, 0), v3f(1, 0.5f, 0), v3f(0.75f, 0.75f, 1));  // edge x + y = 1.5: no touch
  add(v3f(2, 0, 0), v3f(0, 2, 0), v3f(0, 0, 2));        // plane x + y + z = 2 misses (corner sum 1.5)
  add(v3f(1.5f, 0, 0), v3f(0, 1.5f, 0), v3f(0, 0, 1.5f));  // x + y + z = 1.5 touches the corner
  const std::size_t exact_count = cases.size();
  // The same configurations moved by +-1 ulp in each coordinate: rounding decides some of them; the
  // GPU must still agree exactly (same correctly rounded + - *, precise).
  for (std::size_t i = 0; i < exact_count; ++i) {
    for (int s = 0; s < 12; ++s) {
      tb_case k = cases[i];
      float* f = &k.a.x;
      for (int j = 0; j < 12; ++j) {
        if (j % 4 == 3) continue;  // w
        const int dir = ((s + j) % 3) - 1;
        if (dir != 0) f[j] = std::nextafter(f[j], dir > 0 ? flt_inf : -flt_inf);
      }
      cases.push_back(k);
    }
  }
  // Random near-tangent cases: a triangle whose plane is put exactly on the box corner along its
  // normal (in double), then rounded to float.
  random_source rnd(11);
  for (int i = 0; i < 20000; ++i) {
    const v3d n = v3d(v3f(rnd.direction()));
    const v3d h(rnd.uniform(0.1, 1), rnd.uniform(0.1, 1), rnd.uniform(0.1, 1));
    const double r = h.x * std::abs(n.x) + h.y * std::abs(n.y) + h.z * std::abs(n.z);
    const v3d p0 = n * r;  // on the supporting plane of the box along n
    v3d t1 = glm::cross(n, v3d(0.3, 0.5, 0.8));
    t1 /= glm::length(t1);
    const v3d t2 = glm::cross(n, t1);
    const double s = rnd.uniform(0.5, 3.0);
    const v3d a = p0 + s * (rnd.uniform(-1, 1) * t1 + rnd.uniform(-1, 1) * t2);
    const v3d b = p0 + s * (rnd.uniform(-1, 1) * t1 + rnd.uniform(-1, 1) * t2);
    const v3d c = p0 + s * (rnd.uniform(-1, 1) * t1 + rnd.uniform(-1, 1) * t2);
    cases.push_back({c0, f4(v3f(h)), f4(v3f(a)), f4(v3f(b)), f4(v3f(c))});
  }
  // Check the dyadic touching cases overlap (closed sets) on the CPU first.
  for (std::size_t i = 0; i < exact_count; ++i) {
    const auto& k = cases[i];
    const bool expect = !(i == 7 || i == 8);
    INFO("touching case " << i);
    CHECK(vplkit_test::uncontracted_triangle_box_overlap(xyz(k.center), xyz(k.half_size), xyz(k.a), xyz(k.b),
                                                         xyz(k.c)) == expect);
  }
  check_triangle_box(cases, "touching and near-tangent cases");
}

// ==== voxelize.comp ================================================================================

TEST_CASE("voxelize.comp: random triangles (tiny to grid-sized, slivers, degenerate, partly outside)") {
  random_source rnd(21);
  // Non-cubic voxels, bounds not at the origin, sizes that are not powers of two.
  const vplkit::voxel_grid<float> shape(v3f(-1.3f, 0.2f, 2.0f), v3f(2.1f, 3.0f, 4.5f), ivec3(48, 40, 36));
  mesh m;
  for (int i = 0; i < 3000; ++i) {
    const double s = i % 10 == 0 ? 3.0 : (i % 3 == 0 ? 0.02 : 0.25);
    const v3d base(rnd.uniform(-1.6, 2.4), rnd.uniform(-0.1, 3.3), rnd.uniform(1.7, 4.8));
    v3f p[3];
    for (v3f& q : p) q = v3f(base + s * v3d(rnd.uniform(-1, 1), rnd.uniform(-1, 1), rnd.uniform(-1, 1)));
    if (i % 37 == 0) p[2] = p[1];                                              // segment
    if (i % 41 == 0) p[1] = p[2] = p[0];                                       // point
    if (i % 43 == 0) p[2] = p[0] + (p[1] - p[0]) * float(rnd.uniform(0, 1));   // collinear
    if (i % 47 == 0) p[2] = p[0] + (p[1] - p[0]) * 0.5f + v3f(1e-6f, 0, 0);    // sliver
    m.tri(p[0], p[1], p[2]);
  }
  check_voxelize(shape, m, "3000 random triangles, 48x40x36", 8);
}

TEST_CASE("voxelize.comp: closed rotated boxes and an inward room, shared vertices") {
  {
    const vplkit::voxel_grid<float> shape(v3f(-1.0f), v3f(1.0f), ivec3(96));
    mesh m;
    m.solid_box(v3d(0.03, -0.02, 0.05), v3d(0.71, 0.53, 0.62), rotation(0.4, 0.7, 1.1));
    m.solid_box(v3d(0.0, 0.0, 0.0), v3d(0.2, 0.3, 0.1), rotation(-0.3, 0.2, 2.5));
    m.solid_box(v3d(0.1, 0.6, -0.5), v3d(0.9, 0.02, 0.04), rotation(0.0, 0.0, 0.0));
    check_voxelize(shape, m, "rotated boxes, 96^3", 8);
  }
  {
    mesh m;
    m.solid_box(v3d(0.5, 0.5, 0.5), v3d(0.5), dmat3(1.0), true);
    m.solid_box(v3d(0.4, 0.2, 0.6), v3d(0.15, 0.2, 0.1), rotation(0.0, 0.5, 0.0));
    const auto b = vplkit::fit_voxel_bounds(m.positions.data(), m.positions.size());
    const vplkit::voxel_grid<float> shape(b.min, b.max, ivec3(64));
    check_voxelize(shape, m, "room + occluder, fitted bounds, 64^3", 8);
  }
}

TEST_CASE("voxelize.comp: axis-aligned triangles on voxel faces and edges (exact inputs)") {
  // Voxel size 0.25 (dyadic), so planes k * 0.25 are exact voxel planes on both sides and every
  // coordinate converts exactly: no rounding anywhere, and the grids must be equal.
  const vplkit::voxel_grid<float> shape(v3f(-4.0f, 0.0f, 8.0f), v3f(4.0f, 4.0f, 16.0f), ivec3(32, 16, 32));
  mesh m;
  random_source rnd(31);
  for (int i = 0; i < 400; ++i) {
    const int a = rnd.integer(0, 2);
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    const v3f lo = shape.bounds_min();
    auto lattice = [&](int axis) {  // quarter-voxel steps, up to one voxel outside the grid
      return lo[axis] + float(rnd.integer(-4, 4 * shape.resolution()[axis] + 4)) * 0.0625f;
    };
    v3f p[3];
    const float plane = lo[a] + float(rnd.integer(0, shape.resolution()[a])) * 0.25f;
    for (v3f& q : p) {
      q[a] = plane;
      q[b] = lattice(b);
      q[c] = lattice(c);
    }
    if (i % 3 == 0) {  // edges along voxel edges: snap to whole voxels
      for (v3f& q : p) {
        q[b] = std::round(q[b] * 4.0f) / 4.0f;
        q[c] = std::round(q[c] * 4.0f) / 4.0f;
      }
    }
    m.tri(p[0], p[1], p[2]);
  }
  // A box whose faces lie on voxel planes, and a single quad on the grid's max face.
  m.solid_box(v3d(0.0, 2.0, 12.0), v3d(1.5, 1.0, 2.25), dmat3(1.0));
  m.quad(v3f(-4, 4, 8), v3f(4, 4, 8), v3f(4, 4, 16), v3f(-4, 4, 16));
  check_voxelize(shape, m, "axis-aligned triangles on voxel planes", 0);
}

// ==== DDA ==========================================================================================

TEST_CASE("dda: 10^5 random rays in random grids (inside and outside, any length, finite t_max)") {
  random_source rnd(41);
  dda_summary s;
  for (int k = 0; k < 5; ++k) {
    const auto g = random_grid(rnd);
    const auto rays = random_rays(rnd, g, 20000);
    check_dda(g, rays,
              "random grid " + std::to_string(k) + " " + showi3(g.resolution()) + ", " +
                  std::to_string(g.count()) + " occupied",
              &s);
  }
  std::cout << "  dda random total: " << s.rays << " rays, " << s.hits << " hits, " << s.tie_differences
            << " near-tie differences\n";
  CHECK(s.rays >= 100000);
  CHECK(s.hits > s.rays / 10);
}

namespace {

// The lattice grid of the hard cases: voxel sizes 0.5 x 0.25 x 0.25 (dyadic), a scattered 8 %.
vplkit::voxel_grid<float> lattice_grid(std::uint32_t seed, double density) {
  vplkit::voxel_grid<float> g(v3f(-4.0f, 0.0f, 8.0f), v3f(4.0f, 4.0f, 16.0f), ivec3(16, 16, 32));
  random_source rnd(seed);
  for (int z = 0; z < 32; ++z)
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x)
        if (rnd.unit() < density) g.set(ivec3(x, y, z));
  return g;
}

}  // namespace

TEST_CASE("dda: lattice rays along voxel planes and through edges and corners (ties)") {
  const auto g = lattice_grid(51, 0.08);
  random_source rnd(52);
  std::vector<dda_ray> rays;
  const v3f size = g.voxel_size(), bmin = g.bounds_min();
  for (int i = 0; i < 20000; ++i) {
    v3f o, d;
    for (int a = 0; a < 3; ++a) o[a] = bmin[a] + float(rnd.integer(-4, 2 * g.resolution()[a] + 4)) * 0.5f * size[a];
    do
      for (int a = 0; a < 3; ++a) d[a] = float(rnd.integer(-2, 2)) * size[a];
    while (d == v3f(0.0f));
    const float t_max = i % 3 == 0 ? float(rnd.integer(0, 60)) * 0.25f : flt_inf;
    rays.push_back({f4(o, t_max), f4(d)});
  }
  // How many of them are near-ties (informational: shows the set exercises the tie rule).
  const auto occupied = vplkit_test::occupied_voxels(g);
  std::size_t ties = 0;
  for (std::size_t i = 0; i < rays.size(); i += 10)
    ties += dda_near_tie(g, occupied, v3f(rays[i].origin_tmax.x, rays[i].origin_tmax.y, rays[i].origin_tmax.z),
                         v3f(rays[i].dir.x, rays[i].dir.y, rays[i].dir.z), rays[i].origin_tmax.w);
  std::cout << "  lattice rays: " << ties << " of " << (rays.size() + 9) / 10 << " sampled are near-ties\n";
  CHECK(ties > 0);
  check_dda(g, rays, "lattice rays");
}

namespace {

// The walk's state after `steps` dda_walk_next calls and then one dda_walk_leave_brick (jump), and
// after stepping on out of the same brick (step): std430, 2 x 8 scalars.
struct walk_state {
  std::uint32_t running;
  std::int32_t x, y, z;
  float t, nx, ny, nz;
};
struct brick_out {
  walk_state jump, step;
};
static_assert(sizeof(brick_out) == 64, "std430 layout of brick_out");

walk_state state_of(const vplkit::dda_walk<float>& w) {
  if (!w.running) return {0u, 0, 0, 0, 0.0f, 0.0f, 0.0f, 0.0f};
  return {1u, w.voxel.x, w.voxel.y, w.voxel.z, w.t, w.t_next.x, w.t_next.y, w.t_next.z};
}

// The C++ walk of the GLSL's `precise` crossings: rounded products, also in the [fma] program.
brick_out cpu_leave_brick(const vplkit::voxel_grid<float>& g, const dda_ray& r, int steps) {
  const vplkit_test::uncontracted_brick_exit e = vplkit_test::uncontracted_leave_brick(
      g, v3f(r.origin_tmax.x, r.origin_tmax.y, r.origin_tmax.z), v3f(r.dir.x, r.dir.y, r.dir.z), r.origin_tmax.w,
      steps);
  return {state_of(e.jump), state_of(e.step)};
}

bool same_state(const walk_state& a, const walk_state& b) { return std::memcmp(&a, &b, sizeof(walk_state)) == 0; }

// Equal values: llvmpipe's walk may carry t = -0 where the C++ has +0 (a crossing at an origin on a
// plane, max() for the select), which no comparison tells apart.
bool equal_state(const walk_state& a, const walk_state& b) {
  return a.running == b.running && a.x == b.x && a.y == b.y && a.z == b.z && a.t == b.t && a.nx == b.nx &&
         a.ny == b.ny && a.nz == b.nz;
}

std::string show_state(const walk_state& s) {
  if (s.running == 0u) return "ended";
  return "voxel " + showi3(ivec3(s.x, s.y, s.z)) + " t " + show(s.t) + " t_next " + show3(v3f(s.nx, s.ny, s.nz));
}

}  // namespace

TEST_CASE("voxel_bricks: leaving a brick in one move, lattice and random rays (ties, partial bricks)") {
  // The GLSL jump must equal the GLSL steps on any device (the exactness of the skipping), and the
  // C++ bit for bit where division is correctly rounded (software renderers).
  const auto g = lattice_grid(71, 0.0);
  random_source rnd(72);
  std::vector<dda_ray> rays;
  std::vector<std::int32_t> steps;
  const v3f size = g.voxel_size(), bmin = g.bounds_min();
  for (int i = 0; i < 20000; ++i) {
    v3f o, d;
    if (i % 2 == 0) {  // lattice: exact ties
      for (int a = 0; a < 3; ++a) o[a] = bmin[a] + float(rnd.integer(-4, 2 * g.resolution()[a] + 4)) * 0.5f * size[a];
      do
        for (int a = 0; a < 3; ++a) d[a] = float(rnd.integer(-2, 2)) * size[a];
      while (d == v3f(0.0f));
    } else {
      for (int a = 0; a < 3; ++a) o[a] = bmin[a] + float(rnd.unit() * 1.2 - 0.1) * float(g.resolution()[a]) * size[a];
      for (int a = 0; a < 3; ++a) d[a] = float(rnd.unit() * 2.0 - 1.0);
      if (i % 5 == 1) d.y = 0.0f;
    }
    const float t_max = i % 3 == 0 ? float(rnd.integer(0, 60)) * 0.25f : flt_inf;
    rays.push_back({f4(o, t_max), f4(d)});
    steps.push_back(std::int32_t(rnd.integer(0, 40)));
  }
  const auto gpu = run_compute<brick_out>(grid_kernel(g, R"(
#include "vplkit/visibility/voxel_bricks.glsl"
struct dda_ray { vec4 origin_tmax; vec4 dir; };
struct walk_state { uint running; int x, y, z; float t, nx, ny, nz; };
struct brick_out { walk_state jump; walk_state step; };
walk_state state_of(vplkit_dda_walk w) {
  if (!w.running) return walk_state(0u, 0, 0, 0, 0.0, 0.0, 0.0, 0.0);
  return walk_state(1u, w.voxel.x, w.voxel.y, w.voxel.z, w.t, w.t_next.x, w.t_next.y, w.t_next.z);
}
)",
                                                      {input(0, rays, "dda_ray rays"), input(4, steps, "int steps")},
                                                      "brick_out result", R"(
  vplkit_dda_walk w = vplkit_dda_walk_begin(grid(), rays[i].origin_tmax.xyz, rays[i].dir.xyz, rays[i].origin_tmax.w);
  for (int k = 0; k < steps[i] && w.running; ++k) vplkit_dda_walk_next(grid(), w);
  vplkit_dda_walk jump = w;
  vplkit_dda_walk stepped = w;
  if (jump.running) vplkit_dda_walk_leave_brick(grid(), jump);
  ivec3 b = w.voxel / vplkit_voxel_brick_edge;
  for (int k = 0; k < 64 && stepped.running && stepped.voxel / vplkit_voxel_brick_edge == b; ++k)
    vplkit_dda_walk_next(grid(), stepped);
  result[i] = brick_out(state_of(jump), state_of(stepped));)"),
                                          rays.size());
  const bool exact = vplkit::gl::is_software_renderer();
  std::size_t jumps = 0, ended = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const brick_out c = cpu_leave_brick(g, rays[i], steps[i]);
    INFO("ray " << i << ": origin " << show3(v3f(rays[i].origin_tmax.x, rays[i].origin_tmax.y, rays[i].origin_tmax.z))
                << " dir " << show3(v3f(rays[i].dir.x, rays[i].dir.y, rays[i].dir.z)) << " t_max "
                << show(rays[i].origin_tmax.w) << " steps " << steps[i] << " | gpu " << show_state(gpu[i].jump)
                << " | cpu " << show_state(c.jump));
    REQUIRE(same_state(c.jump, c.step));
    REQUIRE(same_state(gpu[i].jump, gpu[i].step));
    if (exact) REQUIRE(equal_state(gpu[i].jump, c.jump));
    jumps += c.jump.running;
    ended += c.jump.running ? 0u : 1u;
  }
  std::cout << "  brick exits: " << rays.size() << " walks, " << jumps << " continue in the next brick, " << ended
            << " end (" << (exact ? "bit-identical to the C++ required on this software renderer" : "own steps only")
            << ")\n";
  CHECK(jumps > rays.size() / 10);
  CHECK(ended > rays.size() / 10);
}

TEST_CASE("dda: hard cases (axis-parallel, outside hit/miss, zero length, boundaries, corners, far)") {
  auto g = lattice_grid(61, 0.05);
  // A known row and a corner voxel for the axis-parallel and diagonal cases.
  for (int x = 3; x < 6; ++x) g.set(ivec3(x, 7, 9));
  g.set(ivec3(0, 0, 0));
  g.set(ivec3(15, 15, 31));
  const v3f size = g.voxel_size(), bmin = g.bounds_min(), bmax = g.bounds_max();
  auto centre = [&](ivec3 v) { return g.voxel_center(v); };
  std::vector<dda_ray> rays;
  auto add = [&](v3f o, v3f d, float t_max = flt_inf) { rays.push_back({f4(o, t_max), f4(d)}); };

  // Axis-parallel rays, each axis, both directions: from voxel centres inside, from outside before
  // the grid (hitting), beside the grid (missing), with scaled directions.
  for (int a = 0; a < 3; ++a) {
    for (float sgn : {1.0f, -1.0f}) {
      for (float scale : {1.0f, 1e-3f, 1e3f}) {
        v3f d(0.0f);
        d[a] = sgn * scale;
        for (ivec3 v : {ivec3(4, 7, 9), ivec3(0, 7, 9), ivec3(8, 8, 16), ivec3(15, 15, 31), ivec3(0, 0, 0)}) {
          add(centre(v), d);
          v3f o = centre(v);
          o[a] = sgn > 0 ? bmin[a] - 3.0f : bmax[a] + 3.0f;  // outside, pointing in
          add(o, d);
          add(o, d, 2.9f);  // stopped before the grid
          add(o, d, 3.0f);  // exactly at the grid face
          v3f beside = o;
          beside[(a + 1) % 3] = bmax[(a + 1) % 3] + 0.5f * size[(a + 1) % 3];  // parallel, outside the slab
          add(beside, d);
          v3f face = o;
          face[(a + 1) % 3] = bmax[(a + 1) % 3];  // parallel, on the grid's max face
          add(face, d);
          add(o, -d);  // pointing away
        }
      }
    }
  }
  // Outside hitting: through the grid's corners, oblique from far away; missing: beyond a corner.
  add(bmin - v3f(1.0f), v3f(1.0f));
  add(bmax + v3f(1.0f), v3f(-1.0f));
  add(v3f(-7000.0f, 2.1f, 12.3f), v3f(7000.0f, 0.01f, -0.02f));
  add(v3f(-1e30f, 2.0f, 12.0f), v3f(1.0f, 0.0f, 0.0f));
  add(v3f(-1e30f, 1e30f, 12.0f), v3f(1.0f, -1.0f, 0.0f));
  add(v3f(bmin.x - 1.0f, bmin.y - 1.0f, 12.0f), v3f(1.0f, 1.0f, 0.0f));   // grid edge exactly
  add(v3f(bmin.x - 1.0f, bmin.y - 1.01f, 12.0f), v3f(1.0f, 1.0f, 0.0f));  // just beside it
  add(bmax + v3f(1.0f), v3f(1.0f, 1.0f, 1.0f));                            // away from the corner
  // Zero length and non-finite input: every one misses on both sides.
  const v3f inside = centre(ivec3(4, 7, 9));
  for (v3f d : {v3f(0.0f), v3f(-0.0f), v3f(1e-39f, 0.0f, 0.0f), v3f(0.0f, -1e-40f, 1e-45f),
                v3f(flt_nan, 1.0f, 0.0f), v3f(flt_inf, 0.0f, 0.0f), v3f(1.0f, -flt_inf, 1.0f)})
    add(inside, d);
  add(inside, v3f(flt_min, 0.0f, 0.0f));  // the smallest direction that counts
  add(inside, v3f(flt_max, flt_max, flt_max));
  add(v3f(flt_nan, 2.0f, 12.0f), v3f(1.0f, 0.0f, 0.0f));
  add(v3f(flt_inf, 2.0f, 12.0f), v3f(-1.0f, 0.0f, 0.0f));
  add(inside, v3f(1.0f, 0.0f, 0.0f), -1.0f);
  add(inside, v3f(1.0f, 0.0f, 0.0f), flt_nan);
  add(inside, v3f(1.0f, 0.0f, 0.0f), 0.0f);
  // Along voxel boundaries: in a plane, along an edge line, oblique in a plane, on the min/max faces.
  const v3f corner = bmin + v3f(3.0f, 7.0f, 9.0f) * size;  // corner of voxel (3, 7, 9)
  add(corner - v3f(1.0f, 0.0f, 0.0f), v3f(1.0f, 0.0f, 0.0f));
  add(corner - v3f(0.0f, 0.0f, 1.0f), v3f(0.0f, 0.0f, 1.0f));
  add(corner - v3f(1.0f, 0.0f, 1.0f), v3f(1.0f, 0.0f, 1.0f));
  add(corner - v3f(1.0f, 0.5f, 0.0f), v3f(1.0f, 0.5f, 0.0f));
  add(v3f(bmin.x, bmin.y, 12.0f), v3f(1.0f, 0.0f, 0.0f));
  add(v3f(bmax.x, bmax.y, 12.0f), v3f(-1.0f, 0.0f, 0.0f));
  add(v3f(bmin.x, 2.0f, bmax.z), v3f(1.0f, 0.0f, 0.0f));
  // Exactly through voxel corners: the main diagonal (in voxel units) both ways, and an
  // 8-connected diagonal wall crossed at its shared corners.
  add(bmin, size);
  add(bmax, -size);
  add(bmin - size, size);
  for (int k = 0; k < 12; ++k) g.set(ivec3(k, 11 - k, 20));
  add(bmin + v3f(0.0f, 0.0f, 20.5f) * size + v3f(0.0f, 0.0f, 0.0f), v3f(size.x, size.y, 0.0f));
  add(bmin + v3f(2.0f, 2.0f, 20.5f) * size, v3f(size.x, size.y, 0.0f));
  add(bmin + v3f(0.0f, 12.0f, 20.0f) * size, v3f(size.x, -size.y, 0.0f));
  check_dda(g, rays, "hard cases (" + std::to_string(rays.size()) + " rays)");
  // Zero-length and non-finite inputs miss on the GPU too (covered by the exact comparison above,
  // stated here for the reader): the CPU answers are misses.
  const auto cpu_nan = vplkit::dda_first_hit(g.view(), inside, v3f(flt_nan, 1.0f, 0.0f));
  CHECK_FALSE(cpu_nan.hit);
}

// ==== voxel grid helpers, surface_ray_origin and voxel_visible ====================================

TEST_CASE("voxel grid helpers: world_to_voxel (far, NaN), voxel_test, voxel_center, exact") {
  const auto g = lattice_grid(71, 0.3);
  random_source rnd(72);
  std::vector<float4> pts;
  for (int i = 0; i < 20000; ++i) {
    v3f p;
    for (int a = 0; a < 3; ++a)
      p[a] = float(rnd.uniform(double(g.bounds_min()[a]) - 2.0, double(g.bounds_max()[a]) + 2.0));
    if (i % 7 == 0) p = g.voxel_to_world(v3f(float(rnd.integer(-1, 17)), float(rnd.integer(-1, 17)),
                                             float(rnd.integer(-1, 33))));  // exactly on planes
    pts.push_back(f4(p));
  }
  for (v3f p : {v3f(1e30f, -1e30f, 0.0f), v3f(flt_nan, 0.0f, flt_inf), v3f(-flt_inf, 3e9f, -3e9f)})
    pts.push_back(f4(p));
  const auto gpu = run_compute<int4>(grid_kernel(g, R"(#include "vplkit/visibility/voxel_grid.glsl")",
                                                 {input(0, pts, "vec4 p")}, "ivec4 result", R"(
  ivec3 v = vplkit_world_to_voxel(grid(), p[i].xyz);
  result[i] = ivec4(v, vplkit_voxel_test(grid(), v) ? 1 : 0);)"),
                                     pts.size());
  series<std::int32_t> voxels;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const ivec3 v = g.world_to_voxel(xyz(pts[i]));
    for (int k = 0; k < 3; ++k) voxels.add(gpu[i][k], v[k]);
    voxels.add(gpu[i].w, g.test(v) ? 1 : 0);
  }
  VPLKIT_CHECK_PARITY(compare_exact(voxels, [&](std::size_t k) { return "p = " + show3(xyz(pts[k / 4])); },
                                    "world_to_voxel and voxel_test"));

  // Float helpers on a grid with non-dyadic, non-cubic voxels: continuous coordinate, voxel
  // centre and back to world, voxel length; and the word count. All are single correctly rounded
  // operations per component (sub, div; add, mul): exact on IEEE implementations. Bound: 2 ulps
  // of the result, or 1e-6 of the coordinate scale (GLSL division may be off by 2.5 ulp).
  const vplkit::voxel_grid<float> h(v3f(-3.1f, 0.7f, 10.2f), v3f(4.3f, 5.9f, 19.9f), ivec3(23, 17, 31));
  // Three outputs: the coordinate and voxel length; the centre and word count; back to world and
  // the flat index (the integers as float bits).
  std::vector<float4> hp(pts.begin(), pts.begin() + 20000);
  kernel_call call = grid_kernel(h, R"(#include "vplkit/visibility/voxel_grid.glsl")", {input(0, hp, "vec4 p")},
                                 "vec4 coord_length", R"(
  vec3 c = vplkit_world_to_voxel_coord(grid(), p[i].xyz);
  ivec3 v = clamp(vplkit_world_to_voxel(grid(), p[i].xyz), ivec3(-2), grid().resolution + 2);
  coord_length[i] = vec4(c, vplkit_voxel_length(grid()));
  centre_words[i] = vec4(vplkit_voxel_center(grid(), v), uintBitsToFloat(vplkit_voxel_word_count(gres.xyz)));
  world_index[i] = vec4(vplkit_voxel_to_world(grid(), c), uintBitsToFloat(vplkit_voxel_flat_index(gres.xyz, v)));)");
  call.more_outputs = {output_of<float4>(4, "vec4 centre_words"), output_of<float4>(5, "vec4 world_index")};
  const kernel_outputs out = run_kernel(call, hp.size(), sizeof(float4));
  const std::vector<float4> hg[3] = {out.get<float4>(1), out.get<float4>(4), out.get<float4>(5)};
  series<float> floats;
  series<std::uint32_t> integers;
  for (std::size_t i = 0; i < hp.size(); ++i) {
    const v3f p = xyz(hp[i]);
    const v3f c = h.world_to_voxel_coord(p);
    const ivec3 v = glm::clamp(h.world_to_voxel(p), ivec3(-2), h.resolution() + 2);
    const v3f centre = h.voxel_center(v), back = h.voxel_to_world(c);
    for (int k = 0; k < 3; ++k) floats.add(hg[0][i][k], c[k]);
    floats.add(hg[0][i].w, h.voxel_length());
    for (int k = 0; k < 3; ++k) floats.add(hg[1][i][k], centre[k]);
    for (int k = 0; k < 3; ++k) floats.add(hg[2][i][k], back[k]);
    integers.add(bits_of(hg[1][i].w), h.word_count());
    integers.add(bits_of(hg[2][i].w), vplkit::voxel_flat_index(h.resolution(), v));
  }
  VPLKIT_CHECK_PARITY(compare_floats(floats, within_ulps(2) | within_abs(1e-6 * 20.0),
                                     [&](std::size_t k) { return "p = " + show3(xyz(hp[k / 10])); },
                                     "world_to_voxel_coord, voxel_length, voxel_center, voxel_to_world"));
  VPLKIT_CHECK_PARITY(compare_exact(integers, [&](std::size_t k) { return "p = " + show3(xyz(hp[k / 2])); },
                                    "voxel_word_count, voxel_flat_index"));
}

TEST_CASE("voxel_visible and voxel_visible_two_sided: 1.2 x 10^5 point pairs in a voxelised room") {
  // A room (inward box) with two occluders, voxelised by the C++ at 48^3; points on the surfaces
  // with their normals, so the offsets and the tolerance matter.
  mesh m;
  m.solid_box(v3d(0.5, 0.5, 0.5), v3d(0.5), dmat3(1.0), true);
  m.solid_box(v3d(0.35, 0.3, 0.5), v3d(0.12, 0.3, 0.2), rotation(0.0, 0.6, 0.0));
  m.solid_box(v3d(0.7, 0.55, 0.3), v3d(0.05, 0.25, 0.15), rotation(0.3, 0.1, 0.2));
  const auto b = vplkit::fit_voxel_bounds(m.positions.data(), m.positions.size());
  vplkit::voxel_grid<float> g(b.min, b.max, ivec3(48));
  vplkit::voxelize(g, m.positions.data(), m.positions.size(), m.indices.data(), m.indices.size());

  random_source rnd(81);
  auto surface_point = [&](v3f& p, v3f& n) {
    const std::size_t t = std::size_t(rnd.integer(0, int(m.indices.size() / 3) - 1));
    const v3f a = m.positions[m.indices[3 * t]], bb = m.positions[m.indices[3 * t + 1]],
              c = m.positions[m.indices[3 * t + 2]];
    double u = rnd.unit(), v = rnd.unit();
    if (u + v > 1.0) {
      u = 1.0 - u;
      v = 1.0 - v;
    }
    p = a + float(u) * (bb - a) + float(v) * (c - a);
    n = glm::cross(bb - a, c - a) * float(rnd.uniform(0.1, 10.0));  // any length
  };
  std::vector<visible_case> cases;
  for (int i = 0; i < 120000; ++i) {
    v3f x, nx, y, ny;
    surface_point(x, nx);
    surface_point(y, ny);
    if (i % 10 == 0) y = v3f(float(rnd.uniform(0.05, 0.95)), float(rnd.uniform(0.05, 0.95)),
                             float(rnd.uniform(0.05, 0.95)));  // a point in the air
    const int mode = i % 4;
    const float offset = float(rnd.uniform(0.0, 3.0)), tol = float(rnd.uniform(0.0, 3.0));
    cases.push_back({f4(x, offset), f4(nx, float(mode)), f4(y, tol), f4(ny)});
  }
  // Hard cases: x == y, zero / non-finite normals, non-finite points, negative tolerance.
  const v3f p0(0.2f, 0.0f, 0.3f), up(0.0f, 1.0f, 0.0f);
  for (int mode = 0; mode < 4; ++mode) {
    const float fm = float(mode);
    cases.push_back({f4(p0, 1.75f), f4(up, fm), f4(p0, 2.0f), f4(up)});
    cases.push_back({f4(p0, 1.75f), f4(v3f(0.0f), fm), f4(v3f(0.8f, 0.0f, 0.7f), 0.0f), f4(v3f(0.0f))});
    cases.push_back({f4(p0, 1.75f), f4(v3f(flt_nan), fm), f4(v3f(0.8f, 0.9f, 0.7f), 0.0f), f4(v3f(flt_inf))});
    cases.push_back({f4(v3f(flt_nan, 0.0f, 0.0f), 1.75f), f4(up, fm), f4(v3f(0.8f, 0.9f, 0.7f), 0.0f), f4(up)});
    cases.push_back({f4(p0, 1.75f), f4(up, fm), f4(v3f(0.8f, flt_inf, 0.7f), 0.0f), f4(up)});
    cases.push_back({f4(p0, 1.75f), f4(up, fm), f4(v3f(0.8f, 0.9f, 0.7f), -5.0f), f4(-up)});
    cases.push_back({f4(p0, 0.0f), f4(up, fm), f4(v3f(0.2f, 1.0f, 0.3f), 0.0f), f4(-up)});  // floor to ceiling
  }

  const auto gpu = run_compute<std::uint32_t>(
      grid_kernel(g, visible_source, {input(0, cases, "visible_case cases")}, "uint result", visible_body), cases.size());
  const double band = 1e-3 * double(g.voxel_length());
  std::vector<std::uint32_t> cpu, gpu_away, cpu_away;
  std::size_t visible = 0, near = 0, near_diff = 0;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const bool c = cpu_visible(g, cases[i]);
    cpu.push_back(c ? 1u : 0u);
    visible += c;
    if (visible_near_boundary(g, cases[i], band)) {
      ++near;
      near_diff += gpu[i] != cpu.back();
      continue;
    }
    gpu_away.push_back(gpu[i]);
    cpu_away.push_back(cpu.back());
  }
  auto describe = [&](std::size_t i) {
    const auto& c = cases[i];
    return "x " + show3(xyz(c.x_offset)) + " n_x " + show3(xyz(c.nx_mode)) + " y " + show3(xyz(c.y_tolerance)) +
           " n_y " + show3(xyz(c.ny)) + " offset " + show(c.x_offset.w) + " tolerance " + show(c.y_tolerance.w) +
           " mode " + std::to_string(int(c.nx_mode.w));
  };
  std::cout << "  voxel_visible: " << cases.size() << " pairs, " << visible << " visible; " << near
            << " within " << band << " (1e-3 voxel) of the tolerance boundary, " << near_diff
            << " of them differ\n";
  if (ieee_div_sqrt()) {
    // Correctly rounded division and sqrt: every pair, near the boundary too.
    VPLKIT_CHECK_PARITY(compare_exact(gpu, cpu, describe, "voxel_visible (all pairs, IEEE div/sqrt)"));
  } else {
    // Elsewhere: exact away from the boundary; near it, differences are counted (printed above).
    VPLKIT_CHECK_PARITY(compare_exact(gpu_away, cpu_away, {}, "voxel_visible (pairs away from the boundary)"));
  }
  CHECK(visible > cases.size() / 10);
  CHECK(visible < cases.size() * 9 / 10);

  // surface_ray_origin on its own: x + offset * L * unit(n), floats.
  std::vector<float4> in;
  for (std::size_t i = 0; i < 20000; ++i) in.push_back(cases[i].x_offset), in.push_back(cases[i].nx_mode);
  const auto go = run_compute<float4>(grid_kernel(g, R"(#include "vplkit/visibility/voxel_visible.glsl")",
                                                 {input(0, in, "vec4 v")}, "vec4 result", R"(
  vec4 x = v[2u * i];
  vec4 n = v[2u * i + 1u];
  result[i] = vec4((i % 2u) == 0u ? vplkit_surface_ray_origin(grid(), x.xyz, n.xyz, x.w)
                                  : vplkit_surface_ray_origin(grid(), x.xyz, n.xyz), 0.0);)"),
                                      in.size() / 2);
  series<float> origin;
  for (std::size_t i = 0; i < go.size(); ++i) {
    const v3f x = xyz(in[2 * i]), n = xyz(in[2 * i + 1]);
    const v3f o = i % 2 == 0 ? vplkit::surface_ray_origin(g.view(), x, n, in[2 * i].w)
                             : vplkit::surface_ray_origin(g.view(), x, n);
    for (int k = 0; k < 3; ++k) origin.add(go[i][k], o[k]);
  }
  // The unit normal has sqrt and division: a few ulp on GLSL-minimum GPUs; 4 ulps of the point or
  // 1e-6 of the room size. Measured on llvmpipe: 0.
  VPLKIT_CHECK_PARITY(compare_floats(origin, within_ulps(4) | within_abs(1e-6),
                                     [&](std::size_t k) { return describe(k / 3); }, "surface_ray_origin"));
}
