// CPU/GPU parity of glsl/vplkit/estimators/*.glsl with include/vplkit/estimators/*.hpp (T = float)
// on the synthetic scene of tests/support/synthetic_scene.hpp: DPRSM R = 32, 32^3 voxel grid, the
// voxel visibility / voxel tracer on BOTH sides (the GPU can only march voxels), a 24 x 24 G-buffer
// plus the scene's named gather points and the hard cases of DESIGN 7 (gather point on a VPL, 8 eps
// from one, back-facing, unnormalised normals, background pixels, NaN / Inf positions, zero /
// negative counts, zero intensity).
#include "parity_estimators_support.hpp"

#include <vplkit/estimators/gathering_estimator.hpp>
#include <vplkit/estimators/visibility_callables.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/sampling/rng.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

namespace {

using namespace vplkit::parity::est;
using vplkit::parity::compare_exact;
using vplkit::parity::compare_floats;
using vplkit::parity::input;
using vplkit::parity::show;
using vplkit::parity::within_abs;
using vplkit::parity::within_rel;
using vplkit::parity::within_ulps;

const scene_fixture& fixture() {
  static const scene_fixture* f = new scene_fixture(32, 32, 24, 24);
  return *f;
}

// Gather points: the G-buffer (every `stride`-th pixel), the named points, and the hard cases.
std::vector<named_point> gather_points(int stride) {
  const scene_fixture& f = fixture();
  std::vector<named_point> pts;
  for (std::size_t i = 0; i < f.gbuffer.position.size(); i += std::size_t(stride))
    pts.push_back({"pixel " + std::to_string(i),
                   {f.gbuffer.position[i], f.gbuffer.normal[i], f.gbuffer.albedo[i]}});
  for (const auto& g : f.scene.gather_points()) pts.push_back({g.name, g.gp});
  const auto named = f.scene.gather_points();
  const auto& open = named[0].gp;  // floor_open
  // On a VPL: the gather point sits exactly at a lit texel's y_t (d2 = 0), and 8 eps from it.
  const auto view = f.view();
  int on = 0;
  for (int t = 0; t < view.texel_count() && on < 3; t += 97) {
    const auto v = view.vpl_at(t);
    if (!(v.flux.x > 0)) continue;
    pts.push_back({"on VPL " + std::to_string(t), {v.position, v.normal, v3f(0.6f)}});
    const float e = 8.0f * std::numeric_limits<float>::epsilon() *
                    std::max({std::abs(v.position.x), std::abs(v.position.y), std::abs(v.position.z)});
    pts.push_back({"8 eps from VPL " + std::to_string(t), {v.position + v3f(e, 0, e), v.normal, v3f(0.6f)}});
    ++on;
  }
  pts.push_back({"floor_open back-facing", {open.position, -open.normal, open.albedo}});
  for (float s : {1e-15f, 1e-5f, 7.0f, 1e15f, 1e19f})
    pts.push_back({"floor_open normal x " + show(s), {open.position, open.normal * s, open.albedo}});
  pts.push_back({"background (zero normal)", {open.position, v3f(0), open.albedo}});
  pts.push_back({"normal x 1e20 (n2 overflows: background)", {open.position, open.normal * 1e20f, open.albedo}});
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  pts.push_back({"NaN position", {v3f(nan, 0, 0), open.normal, open.albedo}});
  pts.push_back({"Inf position", {v3f(0, inf, 0), open.normal, open.albedo}});
  pts.push_back({"NaN normal", {open.position, v3f(0, nan, 0), open.albedo}});
  return pts;
}

struct est_out {
  float4 value;
  std::uint32_t counter, key, pad0, pad1;
};

const char* out_block = R"(
struct est_out { vec4 value; uvec4 aux; };
layout(std430, binding = 1) writeonly buffer Out { est_out result[]; };
vplkit_visibility make_visibility(int kind) {
  if (kind == 1) return vplkit_make_voxel_visibility(load_grid());
  if (kind == 2) return vplkit_make_voxel_visibility_one_sided(load_grid());
  return vplkit_make_always_visible();
}
)";

std::vector<est_out> run_points(const std::string& body, const std::vector<named_point>& pts,
                                const scene_params& p, const std::string& name) {
  const scene_fixture& f = fixture();
  vplkit::parity::kernel_call call;
  call.name = name;
  call.source = std::string(scene_prelude) + out_block + body;
  call.inputs = f.inputs();
  call.inputs.push_back(input(5, std::vector<scene_params>{p}));
  call.inputs.push_back(input(7, pack_points(pts)));
  call.output_binding = 1;
  return vplkit::parity::run_compute<est_out>(call, pts.size());
}

struct diff_stats {
  double worst_rel = 0;
  std::size_t worst = 0;
};

void print_worst(const std::string& what, const std::vector<named_point>& pts,
                 const std::vector<float>& gpu, const std::vector<float>& cpu) {
  double worst = 0;
  std::size_t wi = 0;
  for (std::size_t i = 0; i < gpu.size(); ++i) {
    const double d = std::abs(double(gpu[i]) - double(cpu[i]));
    const double r = d / std::max(1e-30, std::abs(double(cpu[i])));
    if (r > worst) {
      worst = r;
      wi = i;
    }
  }
  std::cout << "  " << what << ": worst rel " << worst << " at " << pts[wi / 3].name << " gpu "
            << gpu[wi] << " cpu " << cpu[wi] << "\n";
}

}  // namespace

TEST_CASE("exhaustive_vpl_sum: GPU (compensated float) vs C++ (double sum), voxel visibility") {
  const scene_fixture& f = fixture();
  const auto pts = gather_points(5);
  const auto view = f.view();
  const std::string body = R"(
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= VPLKIT_PARITY_COUNT) return;
  vec3 s = vplkit_exhaustive_vpl_sum(load_point(i), load_view(), make_visibility(ip.y), fp.x);
  result[i] = est_out(vec4(s, 0.0), uvec4(0u));
}
)";
  for (int kind : {1, 2, 0}) {
    for (float dmin : {0.05f, 0.0f}) {
      scene_params p = f.params();
      p.ip.y = kind;
      p.fp.x = dmin;
      const auto gpu = run_points(std::string("#include \"vplkit/estimators/vpl_sum.glsl\"\n") + body, pts, p,
                                  "exhaustive_vpl_sum.comp");
      std::vector<float> g, c;
      for (std::size_t i = 0; i < pts.size(); ++i) {
        vplkit::vec3<float> s;
        if (kind == 1)
          s = vplkit::exhaustive_vpl_sum(pts[i].gp, view, vplkit::voxel_visibility<float>{f.grid.view()}, dmin);
        else if (kind == 2)
          s = vplkit::exhaustive_vpl_sum(pts[i].gp, view, vplkit::voxel_visibility_one_sided<float>{f.grid.view()}, dmin);
        else
          s = vplkit::exhaustive_vpl_sum(pts[i].gp, view, vplkit::always_visible{}, dmin);
        for (int k = 0; k < 3; ++k) {
          g.push_back((&gpu[i].value.x)[k]);
          c.push_back(s[k]);
        }
      }
      print_worst("exhaustive kind " + std::to_string(kind) + " dmin " + std::to_string(dmin), pts, g, c);
    }
  }
}

TEST_CASE("estimate_gathering: voxel tracer on both sides, same streams") {
  const scene_fixture& f = fixture();
  const auto pts = gather_points(1);
  const auto view = f.view();
  const float tol = 0.2f + vplkit::voxel_tracer_depth_tolerance(f.grid.view());
  const std::string body = R"(
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= VPLKIT_PARITY_COUNT) return;
  vplkit_counter_rng rng = vplkit_make_counter_rng(uint(ip.z), i);
  vec3 s = vplkit_estimate_gathering(load_point(i), load_view(), rng, ip.w,
                                     vplkit_make_voxel_tracer(load_grid()), fp.y);
  result[i] = est_out(vec4(s, 0.0), uvec4(rng.counter, rng.key, 0u, 0u));
}
)";
  scene_params p = f.params();
  p.ip.z = 1234;
  p.ip.w = 16;
  p.fp.y = tol;
  const auto gpu = run_points(std::string("#include \"vplkit/estimators/gathering_estimator.glsl\"\n") + body, pts,
                              p, "estimate_gathering.comp");
  std::vector<float> g, c;
  std::vector<std::uint32_t> gc, cc;
  const vplkit::voxel_tracer<float> tracer{f.grid.view()};
  for (std::size_t i = 0; i < pts.size(); ++i) {
    vplkit::counter_rng rng = vplkit::make_counter_rng(1234u, std::uint32_t(i));
    const auto s = vplkit::estimate_gathering(pts[i].gp, view, rng, 16, tracer, tol);
    for (int k = 0; k < 3; ++k) {
      g.push_back((&gpu[i].value.x)[k]);
      c.push_back(s[k]);
    }
    gc.push_back(gpu[i].counter);
    cc.push_back(rng.counter);
  }
  print_worst("gathering", pts, g, c);
  VPLKIT_CHECK_PARITY(compare_exact(gc, cc, {}, "gathering rng counter"));
}

TEST_CASE("debug visibility") {
  const scene_fixture& f = fixture();
  const auto view = f.view();
  std::vector<named_point> pts;
  const auto named = f.scene.gather_points();
  const int n = view.texel_count();
  for (int t = 0; t < n; ++t) pts.push_back({"t", {named[0].gp.position, named[0].gp.normal, named[0].gp.albedo}});
  scene_params p = f.params();
  const std::string body = R"(
#include "vplkit/estimators/vpl_sum.glsl"
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= VPLKIT_PARITY_COUNT) return;
  vplkit_gather_point g = load_point(i);
  vplkit_vpl v = vplkit_dprsm_view_vpl_at(load_view(), int(i));
  bool a = vplkit_voxel_visible_two_sided(load_grid(), g.position, g.normal, v.position, v.normal);
  bool b = vplkit_visibility_test(vplkit_make_voxel_visibility(load_grid()), g.position, g.normal, v.position, v.normal);
  vec3 c = vplkit_vpl_visible_contribution(g, load_view(), int(i), vplkit_make_voxel_visibility(load_grid()), 0.05);
  result[i] = est_out(vec4(c, 0.0), uvec4(a ? 1u : 0u, b ? 1u : 0u, 0u, 0u));
}
)";
  const auto gpu = run_points(body, pts, p, "dbg.comp");
  int da = 0, db = 0, dc = 0;
  for (int t = 0; t < n; ++t) {
    const auto v = view.vpl_at(t);
    const bool c = vplkit::voxel_visible_two_sided(f.grid.view(), named[0].gp.position, named[0].gp.normal, v.position, v.normal);
    if (bool(gpu[t].counter) != c) ++da;
    if (bool(gpu[t].key) != c) ++db;
    const auto cc = vplkit::vpl_visible_contribution(named[0].gp, view, t, vplkit::voxel_visibility<float>{f.grid.view()}, 0.05f);
    if ((cc.x > 0) != (gpu[t].value.x > 0)) { ++dc; if (dc < 5) std::cout << t << " cpu " << cc.x << " gpu " << gpu[t].value.x << " vis " << c << "\n"; }
  }
  std::cout << "direct mismatches " << da << " via struct " << db << " contrib " << dc << "\n";
}

TEST_CASE("debug loop") {
  const scene_fixture& f = fixture();
  const auto view = f.view();
  const auto named = f.scene.gather_points();
  std::vector<named_point> pts = {{"a", named[0].gp}};
  scene_params p = f.params();
  const std::string body = R"(
#include "vplkit/estimators/vpl_sum.glsl"
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= VPLKIT_PARITY_COUNT) return;
  vplkit_gather_point g = load_point(i);
  vplkit_dprsm_view view = load_view();
  vplkit_visibility vis = vplkit_make_voxel_visibility(load_grid());
  vec3 s = vec3(0.0);
  uint cnt = 0u, cnt2 = 0u;
  for (int t = 0; t < vplkit_dprsm_view_texel_count(view); ++t) {
    vec3 c = vplkit_vpl_visible_contribution(g, view, t, vis, 0.05);
    s += c;
    if (c.x > 0.0) cnt++;
    vplkit_vpl v = vplkit_dprsm_view_vpl_at(view, t);
    if (vplkit_voxel_visible_two_sided(load_grid(), g.position, g.normal, v.position, v.normal)) cnt2++;
  }
  result[i] = est_out(vec4(s, 0.0), uvec4(cnt, cnt2, 0u, 0u));
}
)";
  const auto gpu = run_points(body, pts, p, "dbg2.comp");
  int cnt = 0, cnt2 = 0;
  vplkit::vec3<float> s(0);
  for (int t = 0; t < view.texel_count(); ++t) {
    const auto cc = vplkit::vpl_visible_contribution(named[0].gp, view, t, vplkit::voxel_visibility<float>{f.grid.view()}, 0.05f);
    s += cc;
    if (cc.x > 0) ++cnt;
    const auto v = view.vpl_at(t);
    if (vplkit::voxel_visible_two_sided(f.grid.view(), named[0].gp.position, named[0].gp.normal, v.position, v.normal)) ++cnt2;
  }
  std::cout << "gpu " << gpu[0].value.x << " " << gpu[0].counter << " " << gpu[0].key << " cpu " << s.x << " " << cnt << " " << cnt2 << "\n";
}
