// SPDX-License-Identifier: MIT
// speed_vs_error's outputs: PREFIX.csv (one row per run), PREFIX_bias_variance.csv, PREFIX.md (the
// frame, the references and a table of the runs) and the analysis: PREFIX.svg, PREFIX_samples.svg
// and PREFIX_pareto.md.
#pragma once

#include "sweep.hpp"

#include <string>
#include <vector>

namespace speed_vs_error {

// Writes PREFIX.csv, PREFIX_bias_variance.csv (when there are bias/variance rows), PREFIX.md and
// the analysis for a sweep, then prints the line naming them.
void write_sweep_outputs(const sweep_options& so, const vplrender::prepared_scene& p, const sweep_frame& f,
                         const sweep_references& refs, const sweep_result& result);

// Per reference and method, the mean over seeds of time and error at each sample count; from
// these: PREFIX.svg (error against time), PREFIX_samples.svg (error against samples: the paper's
// Fig. 8) and PREFIX_pareto.md (Pareto front, equal-error table). ref_dirs 0: the gathering
// reference's directions are unknown (--replot). Returns the files written.
std::vector<std::string> write_analysis(const std::vector<run_row>& rows, const std::vector<std::string>& labels,
                                        const std::vector<int>& samples, bool has_vplsum, bool has_gather,
                                        bool has_exact, int ref_dirs, const std::string& caption,
                                        const std::string& scene_line, const std::string& out);

}  // namespace speed_vs_error
