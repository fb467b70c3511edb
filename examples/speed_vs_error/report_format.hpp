// SPDX-License-Identifier: MIT
// How speed_vs_error writes numbers and names into its CSVs, Markdown and plots, and how it writes
// a file (whole, or an output_error naming it).
#pragma once

#include "io/image.hpp"

#include <glm/vec3.hpp>

#include <string>

namespace speed_vs_error {

// %.9g; NaN (an error against a skipped reference) as an empty field.
std::string num(double v);
// %.*f.
std::string fixed(double v, int digits);
// %.3e; NaN as "-".
std::string sci(double v);
// x,y,z with num.
std::string vec(const glm::vec3& v);
// The scene's file stem with every character but letters and digits as '_' (file names, CSV column).
std::string base_name(const std::string& scene_name);
// Mean over pixels and channels (linear HDR); 0 for an empty image.
double image_mean(const vplrender::image_rgb& img);
// Writes text to path (binary, truncating); output_error when it cannot.
void write_text(const std::string& path, const std::string& text);

}  // namespace speed_vs_error
