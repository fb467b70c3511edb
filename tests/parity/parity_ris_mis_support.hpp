// SPDX-License-Identifier: MIT
#pragma once
// Shared by parity_estimators_ris_mis_test.cpp and parity_estimators_ris_pool_test.cpp (not a test
// program: only parity_*.cpp files become programs): their scaffolding over the synthetic room of
// parity_estimators_support.hpp (DPRSM R = 32, 32^3 voxels, a 24 x 24 G-buffer, voxel visibility
// and the voxel tracer on both sides) -- the fixture; the two distributions an estimator draws from
// (distribution 0: a CDF over the DPRSM texels, distribution 1: `fixed`, every draw the same index
// and pmf, for the hard cases) in C++ and as the GLSL hooks; the kernels' output record, source and
// inputs; the gather points; the relative comparison that counts the decisions at 0; and the
// fingerprint of an estimate's decisions around a RIS step that each program supplies.
//
// Each program defines source_weights(), the weights of distribution 0's CDF.
//
// Bindings on top of the prelude's (2 to 8): 1 the output (out4, or the kernel's own), 9 and 10
// distribution 0's CDF and guide table, 12 the distributions' dist_info; 11 and 13 are the
// programs' own.
#include "parity_estimators_support.hpp"
#include "parity_fma_model.hpp"

#include <gpu_precision.hpp>

#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/estimators/ris_mis_estimator.hpp>
#include <vplkit/visibility/visibility_callables.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

namespace vplkit::parity::rismis {

using est::v3f;

inline const float inf = std::numeric_limits<float>::infinity();
// The float chain of h (the reflected radiance, p2's area and division, the balance heuristic's 16
// ulps) on one side, both sides together.
inline constexpr double base_rel = 2e-5;

inline const est::scene_fixture& fixture() {
  static const est::scene_fixture* f = new est::scene_fixture(32, 32, 24, 24);
  return *f;
}

// Exact decisions only between llvmpipe (correctly rounded, nothing contracted) and an uncontracted
// reference.
inline bool bit_exact_device() {
  static const bool exact = vplkit::gl::is_software_renderer() && !vplkit_test::reference_contracts;
  return exact;
}

inline float window() { return 0.2f + vplkit::voxel_tracer_depth_tolerance(fixture().grid.view()); }

// ---- the distributions ---------------------------------------------------------------------------
struct fixed_distribution {
  std::size_t index = 0;
  float p = 0.0f;
  vplkit::discrete_sample<float> sample(float) const { return {index, p}; }
  float pmf(std::size_t i) const { return i == index ? p : 0.0f; }
};

// Distribution 0's weights, one per DPRSM texel of fixture(): defined by each program.
std::vector<float> source_weights();

struct source_cdf {
  vplkit::discrete_cdf<float> cdf;
  std::vector<float> cdf_data;
  std::vector<std::uint32_t> guide_data;
  source_cdf() : cdf(source_weights()) {
    cdf_data.assign(cdf.cdf().begin(), cdf.cdf().end());
    guide_data.assign(cdf.guide().begin(), cdf.guide().end());
  }
};

inline const source_cdf& source() {
  static const source_cdf* s = new source_cdf();
  return *s;
}

// The C++ side of distribution `id`.
struct distribution_ref {
  int id = 0;
  fixed_distribution fixed;
  vplkit::discrete_sample<float> sample(float u) const { return id == 1 ? fixed.sample(u) : source().cdf.sample(u); }
  float pmf(std::size_t i) const { return id == 1 ? fixed.pmf(i) : source().cdf.pmf(i); }
};

// Distribution 1 drawing `texel` (possibly outside the view) with pmf p.
inline distribution_ref fixed_case(float p, int texel) {
  distribution_ref d;
  d.id = 1;
  d.fixed.p = p;
  d.fixed.index = std::size_t(texel);
  return d;
}

// A texel with a VPL (t % 5 == 3, away from the first ones); -1 where there is none.
inline int lit_texel() {
  const auto view = fixture().view();
  for (int t = 0; t < view.texel_count(); ++t)
    if (vplkit::vpl_has_flux(view.vpl_at(t)) && t % 5 == 3) return t;
  return -1;
}

struct dist_info {
  std::int32_t cdf_size, guide_size, fixed_index;
  float fixed_pmf;
};

// The hooks of both distributions (bindings 9, 10, 12), in front of the estimator's file.
inline const char* const distribution_hooks_glsl = R"(
#include "vplkit/distribution/discrete_cdf.glsl"
layout(std430, binding = 9) readonly buffer CdfData { float cdf_data[]; };
layout(std430, binding = 10) readonly buffer GuideData { uint guide_data[]; };
struct dist_info { int cdf_size; int guide_size; int fixed_index; float fixed_pmf; };
layout(std430, binding = 12) readonly buffer DistInfo { dist_info dinfo; };
float vplkit_load_cdf(uint d, uint i) { return cdf_data[i]; }
uint vplkit_load_guide(uint d, uint j) { return guide_data[j]; }
vplkit_discrete_sample vplkit_estimator_distribution_sample(uint d, float u) {
  if (d == 1u) return vplkit_discrete_sample(uint(dinfo.fixed_index), dinfo.fixed_pmf);
  return vplkit_discrete_cdf_sample(vplkit_discrete_cdf(0u, uint(dinfo.cdf_size), uint(dinfo.guide_size), 1.0), u);
}
float vplkit_estimator_distribution_pmf(uint d, uint i) {
  if (d == 1u) return i == uint(dinfo.fixed_index) ? dinfo.fixed_pmf : 0.0;
  return vplkit_discrete_cdf_pmf(vplkit_discrete_cdf(0u, uint(dinfo.cdf_size), uint(dinfo.guide_size), 1.0), i);
}
)";

// ---- kernels -------------------------------------------------------------------------------------
// The output record of most kernels (binding 1).
struct out4 {
  float4 a, b;
  int4 c;
  std::uint32_t d[4];
};

inline const char* const out4_glsl = R"(
struct out4 { vec4 a; vec4 b; ivec4 c; uvec4 d; };
layout(std430, binding = 1) writeonly buffer Out { out4 result[]; };
)";

// A kernel of the prelude, `hooks` and `head`, running `body` for i < `limit` (a GLSL expression),
// over the fixture's buffers, the parameter block `p` (binding 5), the gather points `pts` (7),
// distribution `dist`'s buffers (9, 10, 12) and `extra`; its output at binding 1.
inline kernel_call ris_kernel(const std::string& name, const std::string& hooks, const std::string& head,
                              const std::string& body, const std::string& limit, const est::scene_params& p,
                              const std::vector<est::named_point>& pts, const distribution_ref& dist,
                              std::vector<ssbo> extra) {
  const est::scene_fixture& f = fixture();
  kernel_call call;
  call.name = name;
  call.source = std::string(est::scene_prelude) + hooks + head +
                "void main() {\n  uint i = gl_GlobalInvocationID.x;\n  if (i >= " + limit + ") return;\n" + body + "}\n";
  call.inputs = f.inputs();
  call.inputs.push_back(input(5, std::vector<est::scene_params>{p}));
  call.inputs.push_back(input(7, est::pack_points(pts)));
  call.inputs.push_back(input(9, source().cdf_data));
  call.inputs.push_back(input(10, source().guide_data));
  const dist_info info{int(source().cdf.size()), int(source().cdf.guide_size()), int(dist.fixed.index), dist.fixed.p};
  call.inputs.push_back(input(12, std::vector<dist_info>{info}));
  for (auto& e : extra) call.inputs.push_back(std::move(e));
  call.output_binding = 1;
  return call;
}

inline std::uint32_t bits(float x) {
  std::uint32_t b;
  std::memcpy(&b, &x, 4);
  return b;
}

// ---- gather points and comparisons ---------------------------------------------------------------
// Every third G-buffer pixel, one in five again with its shading normal tilted 50 degrees, the named
// points, and hard cases: on a lit texel's VPL (d2 = 0), 1e-3 from one (the near field, where h
// stays bounded by gathering's weight), back-facing, background, NaN position.
inline std::vector<est::named_point> gather_points() {
  const est::scene_fixture& f = fixture();
  std::vector<est::named_point> pts;
  for (std::size_t i = 0; i < f.gbuffer.position.size(); i += 3) {
    pts.push_back({"pixel " + std::to_string(i), {f.gbuffer.position[i], f.gbuffer.normal[i], f.gbuffer.albedo[i]}});
    const v3f n = f.gbuffer.normal[i];
    if (i % 15 != 0 || !(glm::dot(n, n) > 0.0f)) continue;
    const v3f nn = glm::normalize(n);
    const v3f side = glm::normalize(glm::cross(nn, std::abs(nn.x) < 0.9f ? v3f(1, 0, 0) : v3f(0, 1, 0)));
    pts.push_back({"pixel " + std::to_string(i) + " shading normal tilted 50 deg",
                   {f.gbuffer.position[i], n, f.gbuffer.albedo[i], 0.6428f * nn + 0.7660f * side}});
  }
  const auto named = f.scene.gather_points();
  for (const auto& g : named) pts.push_back({g.name, g.gp});
  const auto view = f.view();
  int on = 0;
  for (int t = 0; t < view.texel_count() && on < 3; t += 97) {
    const auto v = view.vpl_at(t);
    if (!vplkit::vpl_has_flux(v)) continue;
    const v3f n = glm::normalize(v.normal);
    const v3f side = glm::normalize(glm::cross(n, std::abs(n.x) < 0.9f ? v3f(1, 0, 0) : v3f(0, 1, 0)));
    pts.push_back({"on VPL " + std::to_string(t), {v.position, v.normal, v3f(0.6f)}});
    pts.push_back({"1e-3 from VPL " + std::to_string(t), {v.position + 1e-3f * side, n, v3f(0.6f)}});
    ++on;
  }
  const auto& open = named[0].gp;
  pts.push_back({"floor_open back-facing", {open.position, -open.normal, open.albedo}});
  pts.push_back({"background", {v3f(0.1f, 0.2f, 0.3f), v3f(0.0f), v3f(0.6f)}});
  pts.push_back({"NaN position", {v3f(std::numeric_limits<float>::quiet_NaN(), 0, 0), v3f(0, 1, 0), v3f(0.6f)}});
  return pts;
}

// Per channel |gpu - cpu| <= rel[k] |cpu| + 1e-30; a value that is 0 on one side only is a decision
// (counted in `zero_flips`, accepted only where the C++ side's conditioning says it is a tie,
// rel >= 0.5). Prints the worst ratio; returns the number outside.
inline std::size_t check_rel(const std::string& what, const std::vector<float>& gpu, const std::vector<float>& cpu,
                             const std::vector<double>& rel, std::size_t& zero_flips) {
  std::size_t outside = 0, worst_at = 0;
  double worst = 0.0, worst_rel = 0.0;
  for (std::size_t k = 0; k < gpu.size(); ++k) {
    if ((gpu[k] == 0.0f) != (cpu[k] == 0.0f)) {
      ++zero_flips;
      if (!(rel[k] >= 0.5)) ++outside;
      continue;
    }
    const double diff = std::abs(double(gpu[k]) - double(cpu[k]));
    const double ratio = diff / (rel[k] * std::abs(double(cpu[k])) + 1e-30);
    if (!std::isfinite(gpu[k]) || !(ratio <= 1.0)) ++outside;
    if (ratio > worst) worst = ratio, worst_at = k;
    if (cpu[k] != 0.0f) worst_rel = std::max(worst_rel, diff / std::abs(double(cpu[k])));
  }
  std::cout << "parity " << what << ": " << gpu.size() << " floats, worst rel " << worst_rel
            << ", worst |gpu - cpu| / bound " << worst;
  if (!gpu.empty()) std::cout << " at [" << worst_at << "] gpu " << gpu[worst_at] << " cpu " << cpu[worst_at];
  std::cout << ", " << outside << " outside, " << zero_flips << " zero on one side only\n";
  return outside;
}

// The smallest relative margin |u S - w| / w of the reservoir decisions of one candidate pass, the
// largest relative error bound of its weights (both from the C++ candidates), and whether a
// candidate's target is a cosine at a tie (0 on one side, usable on the other: the pass may keep
// another sample whatever the margins).
struct pass_facts {
  double margin = inf, weight_rel = 0.0;
  bool cosine_tie = false;
};

// ---- the fingerprint of an estimate's decisions ----------------------------------------------------
// Every decision of an estimate's steps at a gather point, hashed (FNV-1a on 32-bit words): per RIS
// step the kept texel, its jitter and its visibility (the program's kept_visible), per direction the
// ray's texel, lit, in-front and (patch) at-centre tests. Computed with the same library functions
// and the same stream as the estimate, in GLSL and in C++ (replay_steps).
//
// The GLSL function fingerprint(gp, view, <sources>, rng, nd, nr, m, tracer, vis, tol, mode):
// `sources` declares the parameters the RIS step draws from, `ris_step` is its statements, which
// set `vplkit_ris_reservoir r` and `uint visible` from those and gp, view, rng, m, n1, n2, vis, tol
// and mode.
inline std::string fingerprint_glsl(const std::string& sources, const std::string& ris_step) {
  return std::string(R"(
uint fnv(uint h, uint v) { return (h ^ v) * 16777619u; }
uint fingerprint(vplkit_gather_point gp, vplkit_dprsm_view view, )") +
         sources + R"(, vplkit_counter_rng rng, int nd, int nr,
                 int m, vplkit_voxel_tracer tracer, vplkit_visibility vis, float tol, int mode) {
  uint h = 2166136261u;
  if (!vplkit_gather_point_valid(gp)) return h;
  if (nd < 0) nd = 0;
  if (nr < 0 || m <= 0) nr = 0;
  float n1 = float(nd), n2 = float(nr);
  vplkit_orthonormal_basis frame = vplkit_make_orthonormal_basis(vplkit_gather_point_shading_normal(gp));
  for (int j = 0; j < max(nd, nr); ++j) {
    if (j < nr) {
)" + ris_step + R"(
      h = fnv(h, uint(r.kept.texel + 1));
      h = fnv(h, floatBitsToUint(r.kept.xi.x));
      h = fnv(h, floatBitsToUint(r.kept.xi.y));
      h = fnv(h, visible);
    }
    if (j < nd) {
      float u0 = vplkit_rng_next_unit(rng);
      float u1 = vplkit_rng_next_unit(rng);
      vec3 local = vplkit_sample_cosine_hemisphere(vec2(u0, u1));
      vec3 dir = vplkit_to_world(frame, local);
      uint code = 7u;
      if (local.z > 0.0 && vplkit_gather_point_accepts_direction(gp, dir)) {
        vplkit_gathering_ray_result g = vplkit_trace_gathering_ray(view, gp.position, gp.normal, dir, tracer, tol);
        code = uint(g.texel + 1) * 8u + (g.lit ? 1u : 0u) + (g.in_front ? 2u : 0u);
        if (g.lit && mode == vplkit_vpl_patch && vplkit_mis_patch_hit_at_centre(view, g.texel, g.hit)) code += 4u;
      }
      h = fnv(h, code);
    }
  }
  return h;
}
)";
}

inline std::uint32_t fnv(std::uint32_t h, std::uint32_t v) { return (h ^ v) * 16777619u; }

// The C++ fingerprint, and the point's conditioning: the largest bound of a RIS step's weights (h,
// the target, the same sample's error, and weight_sum: 2 h + weight_sum, 3 of them, plus the M
// roundings) and of a lit gathering sample (spec::gathering_sample_rel of its hit distance over its
// distance to the light, three times: in f and in the hit's p2 through d2^2 and cos1, as
// estimate_mis's parity test).
struct point_facts {
  std::uint32_t fingerprint = 2166136261u;
  double rel = 0.0;
};

// What one RIS step gives the fingerprint: the kept sample, its visibility (kept_visible) and the
// largest relative error bound of the pass's weights (pass_facts::weight_rel).
struct ris_step_facts {
  vplkit::ris_reservoir<float> r;
  std::uint32_t visible = 0;
  double weight_rel = 0.0;
};

// replay_steps(gp, rng, ...): the C++ side of fingerprint(), with `ris_step(rng, n1, n2)` for the
// GLSL statements (it advances `rng` as the step does and returns its ris_step_facts).
template <class RisStep>
point_facts replay_steps(const vplkit::gather_point<float>& gp, vplkit::counter_rng rng, int nd, int nr, int m,
                         vplkit::vpl_mode mode, float tol, const RisStep& ris_step) {
  const est::scene_fixture& f = fixture();
  const auto view = f.view();
  const vplkit::voxel_tracer<float> tracer{f.grid.view()};
  point_facts out;
  if (!vplkit::gather_point_valid(gp)) return out;
  if (nd < 0) nd = 0;
  if (nr < 0 || m <= 0) nr = 0;
  const float n1 = float(nd), n2 = float(nr);
  const auto frame = vplkit::make_orthonormal_basis(vplkit::gather_point_shading_normal(gp));
  std::uint32_t& h = out.fingerprint;
  for (int j = 0; j < std::max(nd, nr); ++j) {
    if (j < nr) {
      const ris_step_facts s = ris_step(rng, n1, n2);
      out.rel = std::max(out.rel, 3.0 * s.weight_rel + double(m) * vplkit_test::spec::ulp_rel);
      h = fnv(h, std::uint32_t(s.r.kept.texel + 1));
      h = fnv(h, bits(s.r.kept.xi.x));
      h = fnv(h, bits(s.r.kept.xi.y));
      h = fnv(h, s.visible);
    }
    if (j < nd) {
      const float u0 = vplkit::rng_next_unit<float>(rng);
      const float u1 = vplkit::rng_next_unit<float>(rng);
      const v3f local = vplkit::sample_cosine_hemisphere(vplkit::vec2<float>(u0, u1));
      const v3f dir = vplkit::to_world(frame, local);
      std::uint32_t code = 7u;
      if (local.z > 0.0f && vplkit::gather_point_accepts_direction(gp, dir)) {
        const auto g = vplkit::trace_gathering_ray(view, gp.position, gp.normal, dir, tracer, tol);
        code = std::uint32_t(g.texel + 1) * 8u + (g.lit ? 1u : 0u) + (g.in_front ? 2u : 0u);
        if (g.lit && mode == vplkit::vpl_mode::patch && vplkit::mis_patch_hit_at_centre(view, g.texel, g.hit)) code += 4u;
        if (g.lit) {
          const double t = glm::length(vplkit::vec3<double>(g.hit) - vplkit::vec3<double>(gp.position));
          const double d1 = glm::length(vplkit::vec3<double>(view.light.position) - vplkit::vec3<double>(g.hit));
          if (d1 > 0.0) out.rel = std::max(out.rel, 3.0 * vplkit_test::spec::gathering_sample_rel(t / d1));
        }
      }
      h = fnv(h, code);
    }
  }
  return out;
}

}  // namespace vplkit::parity::rismis
