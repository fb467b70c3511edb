// SPDX-License-Identifier: MIT
#pragma once
// The GPU backend's estimate kernels: for each estimator kind (render/method_traits.hpp) the
// kernel that runs it (examples/vplrender/shaders/estimate_<kind>.comp, exact.comp), the loop
// iterations one of its units may spend (llvmpipe's loop budget, loop_budget.hpp), and the
// specialisation defines of a render (estimate_params.h: every switch that is constant during a
// render is compiled in, never read from a uniform). gpu_backend.cpp dispatches them.
#include "render/method_traits.hpp"
#include "render/settings.hpp"

#include "estimate_ris_params.h"

#include <headless_gl/compute.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace vplrender {

// Loop iterations one unit of work may spend (a texel, sample, round, direction or MIS step), the
// number of units, and the iterations every dispatch spends besides its units.
struct work_shape {
  long long cost = 1;
  long long units = 0;
  long long fixed = 0;
};

// What a kernel's shape depends on: the DPRSM's R, the loop iterations of one visibility query
// (gpu_query_cost), the region mixtures and the local rounds.
struct shape_inputs {
  int dprsm_resolution = 0;
  long long query_cost = 0;
  int regions = 1;
  int rounds = 1;
  // Gathering's lit test is a shadow ray (--lit-test shadow-ray with exact visibility): every
  // gathering ray's hit costs one more query (gpu_lit_test_shadow_ray).
  bool shadow_ray = false;
};

// One dispatch sequence over the whole image: a kernel file (in examples/vplrender/shaders) and the
// shape of its units.
struct gpu_kernel_stage {
  const char* file;
  work_shape (*shape)(const render_settings& s, const shape_inputs& in);
};

// An estimator on the GPU: its stages run in order, each over every pixel and finished before the
// next starts; the last writes the estimate. `variant`: the method_traits variant the row runs
// (any_variant: all of them; ris's variants are two kernels, mis's one kernel with VR_VARIANT).
constexpr int any_variant = -1;
struct gpu_estimate_kernel {
  estimator_kind kind;
  int variant;
  std::vector<gpu_kernel_stage> stages;
};

// The row of m's estimator (render/method_traits.hpp's estimator kind and variant).
const gpu_estimate_kernel& gpu_kernel_for(method m);

// A stage's kernel path relative to the repository (the report's "kernel").
std::string gpu_kernel_path(const gpu_kernel_stage& k);

// The stage's kernel compiled with `defines` as its preamble, once per variant (the process's
// program cache; needs a current GL context).
const vplkit::gl::program& gpu_kernel_program(const gpu_kernel_stage& k, const std::string& defines);

// Whether s's kernel adds the clamp's compensation (uses_clamp_compensation: reference, global,
// local, gbg; a method that takes it without a kernel that adds it is a logic_error).
bool gpu_clamp_compensation(const render_settings& s);

// The clamp compensation's passes (examples/vplrender/shaders/clamp_compensation.comp; docs/renderer.md,
// "The clamp compensation's passes"): whether s computes the term there before the estimate kernel
// (gpu_clamp_compensation and --clamp-compensation-pass compacted), the shape of its directions
// pass (a unit is a direction) and the preamble of its pass `pass` (VR_CLAMP_PASS_MARK, _DISPATCH,
// _DIRECTIONS: estimate_params.h).
constexpr const char* clamp_compensation_kernel = "clamp_compensation.comp";
// Its stage in the report: an "estimate" stage, so that speed_vs_error counts it in the estimate.
constexpr const char* clamp_compensation_stage_gpu = "estimate: clamp compensation (gpu)";
bool gpu_clamp_compensation_compacted(const render_settings& s);
work_shape clamp_compensation_shape(const render_settings& s, const shape_inputs& in);
std::string clamp_compensation_defines(const render_settings& s, visibility_choice v, bool shadow_ray, int pass);

// The preamble of s's variant (one "#define NAME VALUE" line per define the kernel reads):
// VR_VISIBILITY, VR_SAMPLER, VR_VPL_MODE, VR_LOCAL_COMBINATION, VR_VARIANT, VR_SPLIT, VR_DIRECT,
// VR_LIT_SHADOW_RAY, VR_CLAMP_COMPENSATION, for ris VR_RIS_PASS (`ris_pass`, estimate_ris_params.h),
// and for ris and ris-mis VR_RIS_PER_REGION, for ris-mis with --candidate-pool VR_RIS_POOL. `resampled`: the mixtures' components were built (--sampler alias,
// --face-selection roulette); `shadow_ray`: gathering's lit test by a shadow ray; `split`: the
// units are split over dispatches.
std::string gpu_kernel_defines(const render_settings& s, visibility_choice v, bool resampled, bool shadow_ray,
                               bool split, int ris_pass = 0);

// --method ris with --spatial K > 0 runs --vpls rounds of two dispatches over the image (a
// candidate pass and a reuse pass, estimate_ris_params.h's VR_RIS_PASS_CANDIDATES / _REUSE); a
// round cannot be split, so its loop iterations per invocation must fit the loop budget.
constexpr int ris_pass_estimate = VR_RIS_PASS_ESTIMATE;
constexpr int ris_pass_candidates = VR_RIS_PASS_CANDIDATES;
constexpr int ris_pass_reuse = VR_RIS_PASS_REUSE;
// ris-mis with --candidate-pool P > 0: a dispatch of one invocation per pool entry before the
// estimate's passes (VR_RIS_PASS_POOL), and every pass defines VR_RIS_POOL.
constexpr int ris_pass_pool = VR_RIS_PASS_POOL;
long long ris_round_cost(const render_settings& s, const shape_inputs& in, int ris_pass);

// Units per dispatch under the loop budget, and dispatches for `units`.
long long units_per_pass(const work_shape& s);

}  // namespace vplrender
