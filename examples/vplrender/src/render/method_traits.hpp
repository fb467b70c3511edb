// SPDX-License-Identifier: MIT
#pragma once
// Every --method described once: its name, which estimator both backends run for it (and with
// which variant), which builder makes its distribution, which samples it takes. The command line,
// the backends, the report, the window and speed_vs_error read this table instead of switching on
// the method themselves (docs/renderer.md, "Methods"). Adding a method: an enumerator in
// render/settings.hpp's `method`, a row in method_traits.cpp, and, when no estimator kind fits, a
// kind here with its CPU estimator (render/cpu/cpu_backend.cpp) and its GPU kernel row
// (render/gpu/estimate_kernels.cpp).
#include "render/settings.hpp"

#include <optional>
#include <string>
#include <vector>

namespace vplrender {

// The estimator a method runs: one C++ template family of the library on the CPU backend, one
// kernel (examples/vplrender/shaders/estimate_<kind>.comp, exact.comp) on the GPU backend.
// ris: render/cpu/ris_render.hpp on the CPU, estimate_ris.comp on the GPU.
enum class estimator_kind { reference, vpl_sampling, local, gather, mis, exact, ris };

// What builds a method's distribution over the VPLs (none: it samples no distribution). flux: the
// light-power weights (vplkit::build_flux_weights); candidate_source: the one named by
// render_settings::ris_source (--candidate-source), see distribution_builder.
enum class builder_kind { none, global, local, gbg, flux, candidate_source };

// What speed_vs_error's --samples sets for a method: --vpls, --dirs, or both.
enum class sweep_count { vpls, dirs, vpls_and_dirs };

struct method_traits {
  method id;
  const char* name;         // the --method value, to_string(method) and the reports' "method"
  const char* help;         // its clause of the --method help text
  estimator_kind estimator;
  int variant;              // the estimator's variant: mis: the vplkit::mis_mode (0 solid angle, 1 as published);
                            // ris: 0 alone (clamped), 1 with gathering (vplkit::estimate_ris_mis)
  builder_kind builder;
  bool uses_vpls;           // draws VPLs: --vpl-mode applies
  bool uses_dirs;           // takes --dirs (gathering directions, the GBG builder's NBDIR)
  bool gathers;             // traces gathering rays: --lit-test applies
  bool exact_rays;          // always traces the scene's triangles (the frame needs its exact rays)
  bool swept;               // speed_vs_error may sweep it (not the references it compares against)
  bool swept_by_default;    // in speed_vs_error's default --methods
  sweep_count sweep;        // what the sweep's sample count sets
  bool gpu;                 // the GPU backend runs it (else run_estimator refuses --backend gpu)
  bool clamped;             // divides a VPL's contribution by max(d^2, dmin^2): --clamp-compensation applies
};

// The table, in the order of the help text and of the window's keys.
const std::vector<method_traits>& all_method_traits();

const method_traits& traits(method m);

// The method named `name` (a --method value), if any.
std::optional<method> method_from_name(const std::string& name);

// The builder that makes s's distribution: the method's, or for candidate_source the one
// --candidate-source names (global, local, gbg, flux).
builder_kind distribution_builder(const render_settings& s);

// The estimators that draw --sampler share-tree's trees: VPL sampling (global, gbg), local (one tree
// per region) and mis (its VPL draws; its gathering hits evaluate the tree's pmf). Not the
// resampled ones (ris, ris-mis: their candidates come from --candidate-source's CDFs).
bool draws_share_tree(estimator_kind k);

// The sampler a render uses: c.sampler, or for sampler_choice::automatic share_tree where the
// method draws it (draws_share_tree) with the joint face selection and the guided CDF search (the
// CPU and GPU images then agree at large DPRSMs: docs/math.md, "Image parity at large DPRSMs"),
// else cdf.
sampler_choice resolved_sampler(const render_choices& c);

// "reference|global|...": every name, in table order.
std::string method_names(const char* separator = "|");

}  // namespace vplrender
