// SPDX-License-Identifier: MIT
#include "render/gpu/estimate_kernels.hpp"

#include "render/gpu/gpu_visibility.hpp"
#include "render/gpu/loop_budget.hpp"

#include <algorithm>
#include <stdexcept>

#ifndef VPLRENDER_SHADER_DIR
#error "VPLRENDER_SHADER_DIR must name examples/vplrender/shaders (set by core.cmake)"
#endif

namespace vplrender {

namespace {

// Loop iterations ray_scene.glsl's texture lookup may spend: vr_wrap_integral's doubling loop (at
// most 104 iterations, only for uv beyond 2^24 / size) for x and for y.
constexpr long long texture_wrap_cost = 2 * 104;

// One query's loops, doubled for the two-sided voxel test's two marches (a margin for the other
// kinds).
long long dda_cost(const shape_inputs& in) { return 2LL * in.query_cost + 32; }

// A guided CDF search (a binary search in the worst bucket), twice.
long long cdf_cost(const shape_inputs& in) {
  const long long texels = 2LL * in.dprsm_resolution * in.dprsm_resolution;
  long long log2n = 1;
  while ((1LL << log2n) < texels) ++log2n;
  return 2 * (log2n + 4);
}

// The exhaustive sum: every texel, each a query (a patch texel: its m x m strata).
work_shape reference_shape(const render_settings& s, const shape_inputs& in) {
  const long long strata =
      s.vpl_mode == vpl_mode_choice::patch ? 1LL * reference_patch_strata * reference_patch_strata : 1;
  return {strata * (dda_cost(in) + 4), 2LL * in.dprsm_resolution * in.dprsm_resolution, 0};
}
work_shape vpl_sampling_shape(const render_settings& s, const shape_inputs& in) {
  return {dda_cost(in) + cdf_cost(in) + 4, s.vpls, 0};
}
// A round: one draw per region, the balance heuristic's pmf of every region.
work_shape local_shape(const render_settings&, const shape_inputs& in) {
  return {in.regions * (dda_cost(in) + cdf_cost(in) + in.regions + 4), in.rounds, 0};
}
// A gathering ray: its trace and, with the shadow-ray lit test, its hit's shadow ray. Without the
// second query a direction's bound was short by the shadow ray's traversal: llvmpipe cut the loops
// of the last directions of a full pass, and at 256 directions on the cornell box the GPU's gather
// image read 3.9 % dark (14.5 % at 1024), silently.
long long gathering_ray_cost(const shape_inputs& in) { return (in.shadow_ray ? 2 : 1) * dda_cost(in); }
work_shape gather_shape(const render_settings& s, const shape_inputs& in) {
  return {gathering_ray_cost(in) + 4, s.dirs, 0};
}
// A step: a gathering ray and a VPL draw with its query.
work_shape mis_shape(const render_settings& s, const shape_inputs& in) {
  return {gathering_ray_cost(in) + dda_cost(in) + cdf_cost(in) + 8, std::max(s.dirs, s.vpls), 0};
}
// A direction: its first hit and the hit's shadow ray; a dispatch: the gather point's camera ray.
work_shape exact_shape(const render_settings& s, const shape_inputs& in) {
  return {2 * in.query_cost + texture_wrap_cost + 32, s.dirs, in.query_cost};
}

// A direction of the clamp's compensation: a short trace and the hit's lit test (a shadow ray
// with --lit-test shadow-ray).
long long clamp_direction_cost(const shape_inputs& in) { return 2 * dda_cost(in) + 8; }

// The clamp's compensation inline (VR_CLAMP_COMPENSATION without VR_CLAMP_COMPENSATION_PASS,
// estimate_clamp_compensation.glsl): its directions follow the estimator's units; a unit's cost is
// the larger of the two kinds. Compacted, the estimator's units are its own.
template <work_shape (*estimator)(const render_settings&, const shape_inputs&)>
work_shape with_clamp_compensation(const render_settings& s, const shape_inputs& in) {
  work_shape w = estimator(s, in);
  if (!uses_clamp_compensation(s) || gpu_clamp_compensation_compacted(s)) return w;
  w.cost = std::max(w.cost, clamp_direction_cost(in));
  w.units += clamp_compensation_dirs(s);
  return w;
}

// RIS: a sample is M candidates (a CDF draw and an unshadowed contribution each) and the kept one's
// query. ris-mis with --candidate-pool reads each candidate from the pool (VR_RIS_POOL: an index, a
// load and the contribution, no loop); the pool's CDF draws are its own dispatch, one per entry.
// A tile draw (--candidate-source tiles, estimate_tiles.glsl) also walks its block's B^2 texels.
long long ris_candidates_cost(const render_settings& s, const shape_inputs& in) {
  const bool pooled = traits(s.meth).variant == 1 && s.ris_pool > 0;
  const long long block = s.ris_source == ris_source_choice::tiles ? std::max(1, s.tile_block) : 0;
  return static_cast<long long>(std::max(1, s.ris_candidates)) * ((pooled ? 0 : cdf_cost(in) + block * block) + 8);
}
work_shape ris_shape(const render_settings& s, const shape_inputs& in) {
  return {ris_candidates_cost(s, in) + dda_cost(in) + 4, s.vpls, 0};
}
// RIS with gathering (ris-mis): a step is one RIS sample (its candidates and the kept one's query)
// and one gathering direction (its trace, with the shadow-ray lit test its hit's shadow ray, and the
// hit's pmf, a lookup without a loop), as mis's step is a VPL draw and a direction; like a ris
// sample, a step cannot be split.
work_shape ris_mis_shape(const render_settings& s, const shape_inputs& in) {
  return {ris_candidates_cost(s, in) + gathering_ray_cost(in) + dda_cost(in) + 8, std::max(s.dirs, s.vpls), 0};
}

// One row per estimator kind, in render/method_traits.hpp's order.
// ris-mis is unclamped: no compensation in its shape (estimate_ris_mis.comp has none).
const std::vector<gpu_estimate_kernel> k_kernels = {
    {estimator_kind::reference, any_variant, {{"estimate_reference.comp", with_clamp_compensation<reference_shape>}}},
    {estimator_kind::vpl_sampling, any_variant,
     {{"estimate_vpl_sampling.comp", with_clamp_compensation<vpl_sampling_shape>}}},
    {estimator_kind::local, any_variant, {{"estimate_local.comp", with_clamp_compensation<local_shape>}}},
    {estimator_kind::gather, any_variant, {{"estimate_gather.comp", gather_shape}}},
    {estimator_kind::mis, any_variant, {{"estimate_mis.comp", mis_shape}}},
    {estimator_kind::exact, any_variant, {{"exact.comp", exact_shape}}},
    {estimator_kind::ris, 0, {{"estimate_ris.comp", with_clamp_compensation<ris_shape>}}},
    {estimator_kind::ris, 1, {{"estimate_ris_mis.comp", ris_mis_shape}}},
};

std::string define(const char* name, int value) { return std::string("#define ") + name + " " + std::to_string(value) + "\n"; }

int sampler_value(const render_settings& s, bool resampled) {
  if (resampled) return s.sampler == sampler_choice::alias ? 2 : 3;  // VR_SAMPLER_ALIAS, VR_SAMPLER_ROULETTE
  if (s.sampler == sampler_choice::share_tree) return 4;             // VR_SAMPLER_SHARE_TREE
  return s.cdf_search == cdf_search_choice::binary ? 1 : 0;          // VR_SAMPLER_CDF_BINARY, _CDF_GUIDE
}

}  // namespace

const gpu_estimate_kernel& gpu_kernel_for(method m) {
  const method_traits& t = traits(m);
  for (const gpu_estimate_kernel& k : k_kernels)
    if (k.kind == t.estimator && (k.variant == any_variant || k.variant == t.variant)) return k;
  throw std::logic_error("estimate_kernels.cpp: no GPU kernel for the estimator of --method " + std::string(to_string(m)));
}

std::string gpu_kernel_path(const gpu_kernel_stage& k) { return std::string("examples/vplrender/shaders/") + k.file; }

const vplkit::gl::program& gpu_kernel_program(const gpu_kernel_stage& k, const std::string& defines) {
  return vplkit::gl::cached_kernel(std::string(VPLRENDER_SHADER_DIR) + "/" + k.file, defines);
}

std::string gpu_kernel_defines(const render_settings& s, visibility_choice v, bool resampled, bool shadow_ray,
                               bool split, int ris_pass) {
  const method_traits& t = traits(s.meth);
  std::string d;
  if (t.estimator != estimator_kind::exact)
    d += estimate_visibility_define(v);
  if (t.builder != builder_kind::none) d += define("VR_SAMPLER", sampler_value(s, resampled));
  if (t.uses_vpls) d += define("VR_VPL_MODE", s.vpl_mode == vpl_mode_choice::patch ? 1 : 0);
  if (t.estimator == estimator_kind::local)
    d += define("VR_LOCAL_COMBINATION", s.local_combination == local_combination_choice::average ? 1 : 0);
  d += define("VR_VARIANT", t.variant);
  d += define("VR_SPLIT", split ? 1 : 0);
  d += define("VR_DIRECT", s.direct ? 1 : 0);
  if (shadow_ray) d += "#define VR_LIT_SHADOW_RAY\n";
  if (gpu_clamp_compensation(s)) {
    d += "#define VR_CLAMP_COMPENSATION\n";
    if (gpu_clamp_compensation_compacted(s)) d += "#define VR_CLAMP_COMPENSATION_PASS\n";
  }
  if (!s.dprsm_planes) d += define("VR_DPRSM_PLANES", 0);
  if (t.estimator == estimator_kind::ris) {
    // ris-mis without reuse has one pass (and keeps its define list); with reuse both kernels have
    // the candidate and reuse passes.
    if (t.variant == 0 || ris_pass != ris_pass_estimate) d += define("VR_RIS_PASS", ris_pass);
    if (s.ris_source == ris_source_choice::local || s.ris_source == ris_source_choice::tiles)
      d += "#define VR_RIS_PER_REGION\n";
    if (s.ris_source == ris_source_choice::tiles) d += "#define VR_RIS_TILES\n";
    if (t.variant == 1 && s.ris_pool > 0) d += "#define VR_RIS_POOL\n";
  }
  return d;
}

bool gpu_clamp_compensation(const render_settings& s) {
  if (!uses_clamp_compensation(s)) return false;
  const estimator_kind k = traits(s.meth).estimator;
  if (k == estimator_kind::reference || k == estimator_kind::vpl_sampling || k == estimator_kind::local ||
      k == estimator_kind::ris)
    return true;
  throw std::logic_error("estimate_kernels.cpp: --method " + std::string(to_string(s.meth)) +
                         " takes the clamp compensation but its GPU kernel does not add it");
}

bool gpu_clamp_compensation_compacted(const render_settings& s) {
  return gpu_clamp_compensation(s) && s.clamp_compensation_pass == clamp_compensation_pass_choice::compacted;
}

work_shape clamp_compensation_shape(const render_settings& s, const shape_inputs& in) {
  return {clamp_direction_cost(in), clamp_compensation_dirs(s), 0};
}

std::string clamp_compensation_defines(const render_settings& s, visibility_choice v, bool shadow_ray, int pass) {
  std::string d = estimate_visibility_define(v);
  d += define("VR_VPL_MODE", s.vpl_mode == vpl_mode_choice::patch ? 1 : 0);
  d += define("VR_SPLIT", 0);  // the directions' state lives in the terms' buffer between dispatches
  if (shadow_ray) d += "#define VR_LIT_SHADOW_RAY\n";
  d += "#define VR_CLAMP_COMPENSATION\n#define VR_CLAMP_COMPENSATION_PASS\n";
  if (!s.dprsm_planes) d += define("VR_DPRSM_PLANES", 0);
  d += define("VR_CLAMP_PASS", pass);
  return d;
}

long long ris_round_cost(const render_settings& s, const shape_inputs& in, int ris_pass) {
  if (ris_pass == ris_pass_candidates) return ris_candidates_cost(s, in) + 4;
  // ris-mis: the reuse (its targets cost a pmf look-up more), the shade's query and the step's
  // gathering direction; unclamped, no compensation.
  if (traits(s.meth).variant == 1)
    return 8LL * std::max(0, s.ris_spatial) + cdf_cost(in) + dda_cost(in) + gathering_ray_cost(in) + 8;
  // The reuse: per attempt a similarity test and (pairwise MIS) two targets; the shade's query;
  // in the last round the whole clamp compensation (its directions are not split there).
  const long long compensation = uses_clamp_compensation(s) && !gpu_clamp_compensation_compacted(s)
                                     ? clamp_compensation_dirs(s) * clamp_direction_cost(in)
                                     : 0;
  return 8LL * std::max(0, s.ris_spatial) + dda_cost(in) + 8 + compensation;
}

long long units_per_pass(const work_shape& s) { return std::max(1LL, (gpu_loop_budget - s.fixed) / s.cost); }

}  // namespace vplrender
