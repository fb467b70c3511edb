// SPDX-License-Identifier: MIT
// CPU/GPU parity of the clamp compensation (docs/math.md, "The clamp's compensation"): glsl/vplkit/estimators/
// clamp_compensation.glsl against include/vplkit/estimators/clamp_compensation.hpp (T = float) on the
// synthetic room of tests/support/synthetic_scene.hpp through parity_estimators_support.hpp (DPRSM
// R = 32, 32^3 voxels), with three tracers on both sides: the paper's voxel tracer (voxel-entry
// points, no normal), the triangle voxel tracer (hits on the triangles with their normals: the
// own-surface shading and the on-plane rule) and the latter with the shadow ray as lit test.
// The gather points: every G-buffer pixel, the scene's named points, points 0.005 to 0.05 from a
// crease, and the hard cases (on a patch point, on a crease's plane, background, NaN).
//
// What must be exact: the stream (clamp_compensation_stream's key, the counter after every
// estimate), the short ray's hit where the whole ray's lies within dmin (bit for bit on the CPU,
// tests/unit), and every direction's decision (no hit, beyond dmin, on the hit's plane, unlit:
// 0; else a value) except near a tie: a direction goes through the GPU's sin/cos, a few ulp off,
// so its hit may cross a voxel or triangle edge, dmin or the plane test differently. The test
// replays every direction on both sides and counts the flipped ones; estimates of gather points
// with a flip are excluded from the value bound, counted and bounded. Values: each direction
// rho_x L_o(y) (1 - d^2 / dmin^2); y carries the direction's error times the distance, which moves
// the weight by about 2 |dy| / dmin where the weight itself vanishes (d = dmin), so a direction's
// bound is relative to its value before the weight, an estimate's to its brightest channel
// (measured worst differences printed; docs/glsl/estimators.md).
#include "parity_estimators_support.hpp"

#include <vplkit/estimators/clamp_compensation.hpp>
#include <vplkit/sampling/cosine_hemisphere.hpp>
#include <vplkit/sampling/orthonormal_basis.hpp>
#include <vplkit/visibility/light_visibility.hpp>
#include <vplkit/visibility/visibility_callables.hpp>
#include <vplkit/visibility/voxelize_triangles.hpp>
#include <vplkit/vpl/dprsm_patch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <set>
#include <string>
#include <vector>

namespace {

using namespace vplkit::parity;
using namespace vplkit::parity::est;

constexpr std::uint32_t seed = 0xc1a3c0u;

// The room's DPRSM, its voxel occupancy and, over the same voxels, its triangle lists.
struct fixture_t {
  scene_fixture scene{32, 32, 24, 24};
  vplkit::triangle_voxel_grid<float> triangles;
  fixture_t() : triangles(build()) {}
  vplkit::triangle_voxel_grid<float> build() const {
    const auto& s = scene.scene;
    const auto b = vplkit::fit_voxel_bounds(s.positions.data(), s.positions.size());
    return vplkit::voxelize_triangles(b.min, b.max, vplkit::ivec3(32), s.positions.data(), s.positions.size(),
                                      s.indices.data(), s.indices.size());
  }
  // rank, offsets, entries, triangles at 11..14 (the occupancy words are the scene's, binding 6).
  std::vector<ssbo> inputs() const {
    std::vector<std::uint32_t> rank = triangles.rank(), offsets = triangles.offsets(), entries = triangles.entries();
    if (entries.empty()) entries.push_back(0);
    // a voxel_triangle<float> is four std430 vec4 as it is
    return {input(11, rank), input(12, offsets), input(13, entries), input(14, triangles.triangles())};
  }
};

const fixture_t& fixture() {
  static const fixture_t* f = new fixture_t();
  return *f;
}

const char* const k_source = R"(
#include "vplkit/estimators/clamp_compensation.glsl"
layout(std430, binding = 11) readonly buffer Rank { uint rank_words[]; };
layout(std430, binding = 12) readonly buffer Offsets { uint offsets[]; };
layout(std430, binding = 13) readonly buffer Entries { uint entries[]; };
layout(std430, binding = 14) readonly buffer Triangles { vec4 triangles[]; };
uint vplkit_load_voxel_rank(uint i) { return rank_words[i]; }
uint vplkit_load_voxel_offset(uint i) { return offsets[i]; }
uint vplkit_load_voxel_entry(uint i) { return entries[i]; }
vec4 vplkit_load_voxel_triangle(uint i) { return triangles[i]; }
struct est_out { vec4 value; uvec4 aux; };
struct ray_check { uint point; float u0; float u1; uint pad; };
// ip.y: 0 the voxel tracer, 1 triangle voxels, 2 triangle voxels with the shadow ray.
vplkit_voxel_tracer make_tracer() {
  if (ip.y == 0) return vplkit_make_voxel_tracer(load_grid());
  vplkit_voxel_tracer t = vplkit_make_triangle_voxel_tracer(load_grid());
  if (ip.y == 2) t = vplkit_tracer_with_light_visibility(t, vplkit_make_triangle_voxel_visibility(load_grid()));
  return t;
}
)";

const char* const k_estimate = R"(
  vplkit_counter_rng rng = vplkit_clamp_compensation_stream(vplkit_make_counter_rng(uint(ip.z), i));
  vec3 s = vplkit_estimate_clamp_compensation(load_point(i), load_view(), rng, ip.w, make_tracer(), fp.x, fp.y, ip2.x);
  result[i] = est_out(vec4(s, 0.0), uvec4(rng.counter, rng.key, 0u, 0u));)";

const char* const k_sample = R"(
  vplkit_gather_point gp = load_point(rays[i].point);
  vplkit_orthonormal_basis frame = vplkit_make_orthonormal_basis(vplkit_gather_point_shading_normal(gp));
  vec3 local = vplkit_sample_cosine_hemisphere(vec2(rays[i].u0, rays[i].u1));
  result[i] = est_out(vec4(vplkit_clamp_compensation_sample(gp, load_view(), frame, local, make_tracer(), fp.x, fp.y, ip2.x), 0.0),
                      uvec4(0u));)";

struct est_out {
  float4 value;
  std::uint32_t counter, key, pad0, pad1;
};
struct ray_check {
  std::uint32_t point;
  float u0, u1;
  std::uint32_t pad;
};

std::vector<named_point> gather_points() {
  const fixture_t& f = fixture();
  const auto& gb = f.scene.gbuffer;
  std::vector<named_point> pts;
  for (std::size_t i = 0; i < gb.position.size(); ++i)
    pts.push_back({"pixel " + std::to_string(i), {gb.position[i], gb.normal[i], gb.albedo[i]}});
  for (const auto& g : f.scene.scene.gather_points()) pts.push_back({g.name, g.gp});
  const v3f up(0, 1, 0), grey(0.7f);
  for (const float d : {0.005f, 0.02f, 0.05f}) {
    pts.push_back({"floor " + show(d) + " from red", {v3f(-2.0f + d, 0.0f, 0.3f), up, grey}});
    pts.push_back({"red " + show(d) + " above floor", {v3f(-2.0f, d, 1.1f), v3f(1, 0, 0), grey}});
    pts.push_back({"floor " + show(d) + " from the block's foot", {v3f(0.4f + d, 0.0f, 0.0f), up, grey}});
  }
  const auto view = f.scene.view();
  int t = 0;
  while (!vplkit::vpl_has_flux(view.vpl_at(t))) ++t;
  const auto p = vplkit::dprsm_patch_vpl(view, t, vplkit::vec2<float>(0.3f, 0.7f), 0.0f);
  pts.push_back({"on a patch point", {p.point.position, glm::normalize(p.point.normal), grey}});
  pts.push_back({"on the red wall's plane (crease)", {v3f(-2.0f, 0.0f, -0.5f), up, grey}});
  pts.push_back({"background", {v3f(0.1f), v3f(0), grey}});
  pts.push_back({"NaN position", {v3f(std::numeric_limits<float>::quiet_NaN(), 0, 0), up, grey}});
  return pts;
}

template <class Tracer>
void check_case(const std::string& what, int tracer_kind, const Tracer& tracer, float dmin, int n,
                vplkit::vpl_mode vmode = vplkit::vpl_mode::point) {
  const fixture_t& f = fixture();
  const auto view = f.scene.view();
  const auto pts = gather_points();
  const float tol = tracer_kind == 0 ? 2.0f * vplkit::voxel_tracer_depth_tolerance(f.scene.grid.view()) : 0.0f;
  scene_params p = f.scene.params();
  p.ip.y = tracer_kind;
  p.ip.z = int(seed);
  p.ip.w = n;
  p.fp.x = dmin;
  p.fp.y = tol;
  p.ip2.x = vmode == vplkit::vpl_mode::patch ? 1 : 0;
  std::vector<ssbo> extra = f.inputs();
  const std::string defines = "#define VPLKIT_TRIANGLE_VOXELS\n";
  kernel_call call = scene_kernel(f.scene, k_source, p, pts, extra, "est_out result", k_estimate);
  call.name = "clamp_compensation_estimate.comp";
  call.defines = defines;
  const auto gpu = run_compute<est_out>(call, pts.size());

  // Every direction replayed on both sides.
  std::vector<ray_check> rays;
  std::vector<v3f> cpu_samples, cpu_unweighted;
  std::vector<v3f> cpu;
  std::vector<std::uint32_t> cpu_counter, cpu_key, gpu_counter, gpu_key;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    vplkit::counter_rng rng = vplkit::clamp_compensation_stream(vplkit::make_counter_rng(seed, std::uint32_t(i)));
    const vplkit::counter_rng start = rng;
    cpu.push_back(vplkit::estimate_clamp_compensation(pts[i].gp, view, rng, n, tracer, dmin, tol, vmode));
    cpu_counter.push_back(rng.counter);
    cpu_key.push_back(rng.key);
    gpu_counter.push_back(gpu[i].counter);
    gpu_key.push_back(gpu[i].key);
    if (!vplkit::gather_point_valid(pts[i].gp)) continue;
    vplkit::counter_rng r = start;
    const auto frame = vplkit::make_orthonormal_basis(vplkit::gather_point_shading_normal(pts[i].gp));
    for (int k = 0; k < n; ++k) {
      const float u0 = vplkit::rng_next_unit<float>(r), u1 = vplkit::rng_next_unit<float>(r);
      const v3f local = vplkit::sample_cosine_hemisphere(vplkit::vec2<float>(u0, u1));
      rays.push_back({std::uint32_t(i), u0, u1, 0});
      cpu_samples.push_back(vplkit::clamp_compensation_sample(pts[i].gp, view, frame, local, tracer, dmin, tol, vmode));
      cpu_unweighted.push_back(vplkit::gathering_sample(pts[i].gp, view, frame, local, tracer, tol));
    }
  }
  VPLKIT_CHECK_PARITY(compare_exact(gpu_key, cpu_key, [&](std::size_t i) { return pts[i].name; }, what + ": stream key"));
  VPLKIT_CHECK_PARITY(compare_exact(gpu_counter, cpu_counter, [&](std::size_t i) { return pts[i].name; },
                                    what + ": counter after the estimate"));
  std::set<std::size_t> flipped;
  std::size_t flips = 0, nonzero = 0;
  double worst_sample = 0.0;
  if (!rays.empty()) {
    kernel_call sc = scene_kernel(f.scene, k_source, p, pts, extra, "est_out result", k_sample);
    sc.inputs.push_back(input(9, rays, "ray_check rays"));
    sc.name = "clamp_compensation_sample.comp";
    sc.defines = defines;
    const auto gs = run_compute<est_out>(sc, rays.size());
    for (std::size_t k = 0; k < rays.size(); ++k) {
      const v3f g(gs[k].value.x, gs[k].value.y, gs[k].value.z), c = cpu_samples[k], u = cpu_unweighted[k];
      // the scale: the direction's value before the weight, rho_x L_o(y)
      const float scale = std::max({std::abs(u.x), std::abs(u.y), std::abs(u.z)});
      const bool decided_alike = (g == v3f(0.0f)) == (c == v3f(0.0f));
      const double diff = std::max({std::abs(g.x - c.x), std::abs(g.y - c.y), std::abs(g.z - c.z)});
      if (!decided_alike || diff > 1e-3 * scale) {
        ++flips;
        flipped.insert(rays[k].point);
        continue;
      }
      if (c != v3f(0.0f)) ++nonzero;
      if (scale > 0.0f) worst_sample = std::max(worst_sample, diff / scale);
    }
  }
  std::cout << "  " << what << ": " << rays.size() << " directions replayed, " << nonzero << " with a value, " << flips
            << " flipped near a tie (" << flipped.size() << " gather points); worst other direction "
            << worst_sample << " of its brightest channel before the weight\n";
  // Flips: directions whose hit lies within a few ulp of a voxel or triangle edge, of dmin or of the
  // plane test (none on llvmpipe, whose division and sqrt are correctly rounded; GPU sin/cos and
  // approximate division may flip a few: 0.5 % accepted). Values: measured worst 1.1e-6 (llvmpipe).
  CHECK(flips <= rays.size() / 200 + 2);
  CHECK(worst_sample <= 2e-5);
  std::vector<float> g, c;
  std::vector<std::size_t> index;
  double worst = 0.0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (flipped.count(i)) continue;
    const v3f gv(gpu[i].value.x, gpu[i].value.y, gpu[i].value.z);
    const float scale = std::max({std::abs(cpu[i].x), std::abs(cpu[i].y), std::abs(cpu[i].z)});
    for (int k = 0; k < 3; ++k) {
      CHECK((gv[k] == 0.0f) == (cpu[i][k] == 0.0f));
      if (scale > 0.0f) worst = std::max(worst, double(std::abs(gv[k] - cpu[i][k])) / scale);
    }
  }
  std::cout << "    estimates: worst difference " << worst << " of the point's brightest channel\n";
  CHECK(worst <= 2e-5);  // measured worst 3.1e-6 (llvmpipe)
}

}  // namespace

TEST_CASE("clamp compensation: the voxel tracer (voxel-entry hits), several dmin") {
  const fixture_t& f = fixture();
  REQUIRE(f.triangles.occupancy().words() == f.scene.grid.words());  // one occupancy buffer serves both grids
  const vplkit::voxel_tracer<float> tracer{f.scene.grid.view()};
  for (const float dmin : {0.3f, 0.064f, -0.3f, 0.0f})
    check_case("voxel tracer, dmin " + show(dmin), 0, tracer, dmin, 16);
}

TEST_CASE("clamp compensation: the triangle voxel tracer, DPRSM lit test and shadow ray") {
  const fixture_t& f = fixture();
  REQUIRE(f.triangles.occupancy().words() == f.scene.grid.words());
  const vplkit::triangle_voxel_tracer<float> tracer{f.triangles.view()};
  const auto shadow = vplkit::with_light_visibility(tracer, vplkit::triangle_voxel_visibility<float>{f.triangles.view()});
  for (const float dmin : {0.3f, 0.064f}) {
    check_case("triangle voxels, dmin " + show(dmin), 1, tracer, dmin, 16);
    check_case("triangle voxels + shadow ray, dmin " + show(dmin), 2, shadow, dmin, 16);
  }
  check_case("triangle voxels, patch VPLs (moved parts by the centre), dmin 0.3", 1, tracer, 0.3f, 16,
             vplkit::vpl_mode::patch);
  check_case("triangle voxels + shadow ray, patch VPLs, dmin 0.3", 2, shadow, 0.3f, 16, vplkit::vpl_mode::patch);
  check_case("triangle voxels, one direction", 1, tracer, 0.3f, 1);
  check_case("triangle voxels, no direction", 1, tracer, 0.3f, 0);
}

TEST_CASE("triangle_voxel_surface_within: the GPU's answer is the C++ one, with the voxels' planes and without") {
  const fixture_t& f = fixture();
  REQUIRE(f.triangles.occupancy().words() == f.scene.grid.words());
  const auto view = f.triangles.view();
  REQUIRE(view.planes != nullptr);
  // The room has voxels of one plane (walls, floor, the block's faces) and of several (its creases).
  std::size_t one_plane = 0;
  for (const auto& p : f.triangles.planes()) one_plane += vplkit::voxel_plane_is_several(p) ? 0u : 1u;
  REQUIRE(one_plane > 100);
  REQUIRE(f.triangles.planes().size() - one_plane > 100);
  struct near_query {
    float4 x_reach;  // xyz: x; w: reach
    float4 tol;      // x: plane tolerance
  };
  std::vector<near_query> qs;
  std::vector<std::uint32_t> cpu;
  const float inf = std::numeric_limits<float>::infinity();
  for (int k = 0; k < 6000; ++k) {
    const float u = float((k * 37) % 997) / 997.0f, v = float((k * 101) % 991) / 991.0f;
    const v3f pts[4] = {v3f(-2.0f + 4.0f * u, 0.0f, -2.0f + 4.0f * v), v3f(-2.0f, 3.0f * u * u, -2.0f + 4.0f * v),
                        v3f(-1.0f + 1.4f * u, 1.2f, -0.8f + 1.4f * v), v3f(-2.0f + 4.0f * u, 0.05f * v, 1.999f)};
    const v3f x = pts[k % 4];
    const float reach = k % 97 == 0 ? inf : 0.01f + 0.5f * float((k * 13) % 89) / 89.0f;
    // Mostly the compensation's tolerance; every fifth query a plane at exactly the tolerance (the
    // floor's distance from a point 0.05 v above it; the test asks s > tolerance).
    const float tol = k % 5 == 3 ? x.y : vplkit::vpl_coincidence_tolerance(x, x) / 4.0f;
    qs.push_back({f4(x, reach), {tol, 0, 0, 0}});
    const bool said = vplkit::triangle_voxel_surface_within(view, x, reach, tol);
    REQUIRE(said == vplkit::triangle_voxel_surface_within_scan(view, x, reach, tol));  // the planes change nothing
    cpu.push_back(said ? 1u : 0u);
  }
  std::size_t trues = 0;
  for (std::uint32_t c : cpu) trues += c;
  std::cout << "  surface_within: " << qs.size() << " queries, " << trues << " true\n";
  CHECK(trues > 500);
  CHECK(qs.size() - trues > 500);
  for (const bool planes : {true, false}) {
    kernel_call call;
    call.name = planes ? "triangle_voxel_surface_within_planes.comp" : "triangle_voxel_surface_within.comp";
    call.defines = std::string("#define VPLKIT_TRIANGLE_VOXELS\n") + (planes ? "#define VPLKIT_VOXEL_NEAR_PLANES\n" : "");
    call.source = std::string(scene_prelude) + R"(
#include "vplkit/visibility/triangle_voxel_near.glsl"
layout(std430, binding = 11) readonly buffer Rank { uint rank_words[]; };
layout(std430, binding = 12) readonly buffer Offsets { uint offsets[]; };
layout(std430, binding = 13) readonly buffer Entries { uint entries[]; };
layout(std430, binding = 14) readonly buffer Triangles { vec4 triangles[]; };
uint vplkit_load_voxel_rank(uint i) { return rank_words[i]; }
uint vplkit_load_voxel_offset(uint i) { return offsets[i]; }
uint vplkit_load_voxel_entry(uint i) { return entries[i]; }
vec4 vplkit_load_voxel_triangle(uint i) { return triangles[i]; }
#ifdef VPLKIT_VOXEL_NEAR_PLANES
layout(std430, binding = 15) readonly buffer Planes { vec4 voxel_planes[]; };
vec4 vplkit_load_voxel_near_plane(uint r) { return voxel_planes[r]; }
#endif
struct near_query { vec4 x_reach; vec4 tol; };
)";
    call.inputs = f.scene.inputs();
    call.inputs.push_back(input(5, std::vector<scene_params>{f.scene.params()}));
    call.inputs.push_back(input(7, pack_points({})));
    for (auto& e : f.inputs()) call.inputs.push_back(std::move(e));
    if (planes) call.inputs.push_back(input(15, f.triangles.planes()));  // a voxel_plane<float> is one vec4
    call.inputs.push_back(input(9, qs, "near_query qs"));
    call.output_glsl = "uint result";
    call.body = "result[i] = vplkit_triangle_voxel_surface_within(load_grid(), qs[i].x_reach.xyz, qs[i].x_reach.w, "
                "qs[i].tol.x) ? 1u : 0u;";
    const auto gpu = run_compute<std::uint32_t>(call, qs.size());
    // Decided on `precise` plane distances in the C++ order: bit for bit where division is
    // correctly rounded (llvmpipe); elsewhere a distance within an ulp of reach or of the
    // tolerance may flip.
    VPLKIT_CHECK_PARITY(compare_exact(gpu, cpu,
                                      [&](std::size_t i) {
                                        return "x " + show3(xyz(qs[i].x_reach)) + " reach " + show(qs[i].x_reach.w) +
                                               (planes ? " (planes)" : " (scan)");
                                      },
                                      "triangle_voxel_surface_within"));
  }
}
