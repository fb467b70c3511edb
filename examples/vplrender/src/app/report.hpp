// SPDX-License-Identifier: MIT
#pragma once
// The JSON report written beside every image: what was asked (all parameters), what scene it
// became, where it ran (GL renderer string), and how long each stage took.
#include "cli/options.hpp"
#include "cli/scene_setup.hpp"
#include "render/stage_timer.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace vplrender {

nlohmann::json options_to_json(const options& o);

struct run_info {
  std::string gl_renderer;  // empty: no GL context (CPU backend) -> null in the JSON
  std::vector<stage_time> stages;
  std::vector<std::string> warnings;
  std::vector<std::string> outputs;  // files written
};

nlohmann::json make_report(const options& o, const prepared_scene& p, const run_info& run);

// The process's peak resident set (getrusage ru_maxrss) in bytes; -1 where the OS gives none.
long long host_peak_rss_bytes();

}  // namespace vplrender
