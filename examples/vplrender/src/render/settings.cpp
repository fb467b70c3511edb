// SPDX-License-Identifier: MIT
#include "render/settings.hpp"

#include "render/method_traits.hpp"

#include <vplkit/core/error.hpp>
#include <vplkit/sampling/rng.hpp>
#include <vplkit/visibility/visibility_callables.hpp>

namespace vplrender {

const char* to_string(method m) { return traits(m).name; }

const char* to_string(backend b) { return b == backend::gpu ? "gpu" : "cpu"; }
const char* to_string(local_combination_choice c) {
  return c == local_combination_choice::average ? "average" : "balance";
}
const char* to_string(gbg_accumulator_choice a) { return a == gbg_accumulator_choice::paper ? "paper" : "gathering"; }
const char* to_string(cdf_search_choice s) { return s == cdf_search_choice::binary ? "binary" : "guide"; }
const char* to_string(face_selection_choice f) { return f == face_selection_choice::roulette ? "roulette" : "joint"; }
const char* to_string(sampler_choice s) {
  switch (s) {
    case sampler_choice::alias: return "alias";
    case sampler_choice::share_tree: return "share-tree";
    case sampler_choice::automatic: return "auto";
    case sampler_choice::cdf: break;
  }
  return "cdf";
}
const char* to_string(visibility_choice v) {
  switch (v) {
    case visibility_choice::paper_voxels: return "paper-voxels";
    case visibility_choice::exact: return "exact";
    case visibility_choice::voxels: break;
  }
  return "voxels";
}
const char* to_string(vpl_mode_choice v) { return v == vpl_mode_choice::patch ? "patch" : "point"; }
const char* to_string(lit_test_choice l) { return l == lit_test_choice::shadow_ray ? "shadow-ray" : "shadow-map"; }
const char* to_string(voxel_contract_choice e) { return e == voxel_contract_choice::exact ? "exact" : "plane-rule"; }
const char* to_string(loop_budget_choice l) {
  switch (l) {
    case loop_budget_choice::always: return "always";
    case loop_budget_choice::never: return "never";
    case loop_budget_choice::automatic: break;
  }
  return "automatic";
}

const char* to_string(clamp_compensation_choice c) { return c == clamp_compensation_choice::on ? "on" : "off"; }
const char* to_string(clamp_compensation_pass_choice c) {
  return c == clamp_compensation_pass_choice::inline_pass ? "inline" : "compacted";
}
const char* to_string(ris_source_choice r) {
  switch (r) {
    case ris_source_choice::local: return "local";
    case ris_source_choice::gbg: return "gbg";
    case ris_source_choice::flux: return "flux";
    case ris_source_choice::tiles: return "tiles";
    case ris_source_choice::global: break;
  }
  return "global";
}

vplkit::vpl_mode library_vpl_mode(vpl_mode_choice v) {
  return v == vpl_mode_choice::patch ? vplkit::vpl_mode::patch : vplkit::vpl_mode::point;
}

bool has_distribution(method m) { return traits(m).builder != builder_kind::none; }
bool uses_vpls(method m) { return traits(m).uses_vpls; }

bool method_has_clamp(method m) { return traits(m).clamped; }

bool uses_clamp_compensation(const render_settings& s) {
  return s.clamp_compensation == clamp_compensation_choice::on && s.dmin > 0.0f && method_has_clamp(s.meth);
}

std::string to_string(const clamp_compensation_dirs_choice& c) {
  switch (c.kind) {
    case clamp_compensation_dirs_choice::rule::fixed: return std::to_string(c.value);
    case clamp_compensation_dirs_choice::rule::per_vpls: return "1:" + std::to_string(c.value);
    case clamp_compensation_dirs_choice::rule::automatic: break;
  }
  return "auto";
}

int clamp_compensation_dirs(const render_settings& s) {
  if (s.meth == method::reference) return reference_compensation_dirs;
  const clamp_compensation_dirs_choice& c = s.clamp_compensation_dirs_rule;
  if (c.kind == clamp_compensation_dirs_choice::rule::fixed) return c.value > 0 ? c.value : 1;
  const int k = c.kind == clamp_compensation_dirs_choice::rule::per_vpls && c.value > 0 ? c.value
                                                                                          : clamp_compensation_vpls_per_dir;
  return s.vpls > k ? (s.vpls - 1) / k + 1 : 1;  // ceil(vpls / k) without overflow at INT_MAX
}


std::uint32_t builder_seed(std::uint32_t seed, std::uint32_t stage) {
  return vplkit::rng_key(seed, 0xB0000000u + stage);
}

std::uint32_t ris_pool_seed(std::uint32_t seed) { return vplkit::rng_key(seed, 0xB1000000u); }

float gathering_depth_tolerance(const render_settings& s, const vplkit::voxel_grid_view<float>& grid) {
  // The paper's voxel tracer: its own error (one voxel diagonal, voxel_tracer_depth_tolerance)
  // doubled, as the paper's rule had it (the hit may lie a diagonal behind the surface it stands
  // for). The triangle voxels and exact visibility hit the triangles themselves.
  if (s.visibility == visibility_choice::paper_voxels) return 2.0f * vplkit::voxel_tracer_depth_tolerance(grid);
  return 0.0f;
}

}  // namespace vplrender
