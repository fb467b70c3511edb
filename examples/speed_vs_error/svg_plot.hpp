// SPDX-License-Identifier: MIT
#pragma once
// A hand-written log-log SVG line plot (no dependency): one polyline per series, decade ticks.
#include <string>
#include <vector>

namespace speed_vs_error {

struct series {
  std::string name;
  std::vector<double> x, y;  // non-positive or non-finite points are left out (log axes)
};

struct panel {
  std::string title, x_label, y_label;
  std::vector<series> lines;
};

// Panels side by side in one SVG document.
std::string svg_loglog(const std::vector<panel>& panels, const std::string& caption);

}  // namespace speed_vs_error
