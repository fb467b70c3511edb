// SPDX-License-Identifier: MIT
// speed_vs_error's command line: its own sweep flags, and vplrender's scene flags passed through
// to vplrender's parser (cli/options.hpp: its validation, defaults and limits).
#pragma once

#include "cli/options.hpp"
#include "render/method_traits.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace speed_vs_error {

// The text of --help.
extern const char* const k_help;

// The swept methods when --methods is not given: method_traits' swept_by_default column.
std::vector<vplrender::method> default_methods();

struct sweep_options {
  std::vector<vplrender::method> methods = default_methods();
  std::vector<int> samples{1, 4, 16, 64};
  std::vector<std::uint32_t> seeds{1};
  // --dirs-per-sample R: mis, mis-as-published and ris-mis at n samples trace R n gathering
  // directions beside their n VPL samples (the two strategies' sample allocation).
  int dirs_per_sample = 1;
  std::vector<vplrender::clamp_compensation_choice> compensations;  // empty: vplrender's default
  int ref_dirs = 4096;
  int ref_exact_dirs = 4096;
  bool ref_vplsum = true, ref_gather = true, ref_exact = true;
  bool ref_noise = true;  // --ref-noise: measure the gathering and exact references' noise and remove it
  int repeats = 1;
  std::string replot;  // --replot CSV
  std::string cache_dir = "speed_vs_error_cache";
  std::string out = "speed_vs_error";
  vplrender::options base;  // the scene flags as vplrender parsed them
};

// args[0] is the program name. Returns false for --help. Throws usage_error with a one-line
// message that names the flag.
bool parse_sweep_options(const std::vector<std::string>& args, sweep_options& so);

// A --methods entry (also a CSV's method column in --replot): a swept method, or usage_error.
vplrender::method parse_swept_method(const std::string& name);

}  // namespace speed_vs_error
