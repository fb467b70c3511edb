// SPDX-License-Identifier: MIT
// --replot: the analysis (analysis_writer.hpp) redrawn from a CSV speed_vs_error wrote, rendering
// nothing (after changing the plots, or to merge sweeps).
#pragma once

#include <string>
#include <vector>

namespace speed_vs_error {

// Reads csv_path (columns found by name, so CSVs from older versions with fewer columns still
// load) and writes the analysis under out. input_error naming the file and line for bad input.
// Returns the files written.
std::vector<std::string> replot(const std::string& csv_path, const std::string& out);

}  // namespace speed_vs_error
