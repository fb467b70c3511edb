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

TEST_CASE("exhaustive_vpl_sum: GPU (compensated float) vs C++ (double sum)") {
  const scene_fixture& f = fixture();
  const auto view = f.view();
  // Whole sums, V = 1: 2 R^2 loop iterations per invocation (within llvmpipe's loop budget).
  {
    const auto pts = gather_points(1);
    const std::string body = R"(
#include "vplkit/estimators/vpl_sum.glsl"
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= VPLKIT_PARITY_COUNT) return;
  vec3 s = vplkit_exhaustive_vpl_sum(load_point(i), load_view(), make_visibility(ip.y), fp.x);
  result[i] = est_out(vec4(s, 0.0), uvec4(0u));
}
)";
    for (float dmin : {0.05f, 0.0f}) {
      scene_params p = f.params();
      p.ip.y = 0;
      p.fp.x = dmin;
      const auto gpu = run_points(body, pts, p, "exhaustive_vpl_sum.comp");
      std::vector<float> g, c;
      for (std::size_t i = 0; i < pts.size(); ++i) {
        const auto s = vplkit::exhaustive_vpl_sum(pts[i].gp, view, vplkit::always_visible{}, dmin);
        for (int k = 0; k < 3; ++k) {
          g.push_back((&gpu[i].value.x)[k]);
          c.push_back(s[k]);
        }
      }
      print_worst("exhaustive V=1 dmin " + std::to_string(dmin), pts, g, c);
    }
  }
  // Voxel visibility: texel ranges of 128 per invocation, partial sums added on the host in
  // double (the whole sum would exceed llvmpipe's loop budget; see vpl_sum.glsl).
  {
    const auto pts = gather_points(3);
    const int chunk = 128, chunks = (view.texel_count() + chunk - 1) / chunk;
    const std::string body = R"(
#include "vplkit/estimators/vpl_sum.glsl"
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= VPLKIT_PARITY_COUNT) return;
  uint p = i / uint(ip.z), c = i % uint(ip.z);
  vec3 s = vplkit_exhaustive_vpl_sum_range(load_point(p), load_view(), make_visibility(ip.y), fp.x,
                                           int(c) * ip.w, ip.w);
  result[i] = est_out(vec4(s, 0.0), uvec4(0u));
}
)";
    for (int kind : {1, 2}) {
      for (float dmin : {0.05f, 0.0f}) {
        scene_params p = f.params();
        p.ip.y = kind;
        p.ip.z = chunks;
        p.ip.w = chunk;
        p.fp.x = dmin;
        const scene_fixture& fx = f;
        vplkit::parity::kernel_call call;
        call.name = "exhaustive_vpl_sum_range.comp";
        call.source = std::string(scene_prelude) + out_block + body;
        call.inputs = fx.inputs();
        call.inputs.push_back(input(5, std::vector<scene_params>{p}));
        call.inputs.push_back(input(7, pack_points(pts)));
        call.output_binding = 1;
        const auto gpu = vplkit::parity::run_compute<est_out>(call, pts.size() * std::size_t(chunks));
        std::vector<float> g, c;
        for (std::size_t i = 0; i < pts.size(); ++i) {
          vplkit::vec3<double> gs(0.0);
          for (int k = 0; k < chunks; ++k) {
            const auto& o = gpu[i * std::size_t(chunks) + std::size_t(k)].value;
            gs += vplkit::vec3<double>(o.x, o.y, o.z);
          }
          vplkit::vec3<float> s;
          if (kind == 1)
            s = vplkit::exhaustive_vpl_sum(pts[i].gp, view, vplkit::voxel_visibility<float>{f.grid.view()}, dmin);
          else
            s = vplkit::exhaustive_vpl_sum(pts[i].gp, view, vplkit::voxel_visibility_one_sided<float>{f.grid.view()}, dmin);
          for (int k = 0; k < 3; ++k) {
            g.push_back(float(gs[k]));
            c.push_back(s[k]);
          }
        }
        print_worst("exhaustive voxel kind " + std::to_string(kind) + " dmin " + std::to_string(dmin), pts, g, c);
      }
    }
  }
}

