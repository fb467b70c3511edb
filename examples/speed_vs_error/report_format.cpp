// SPDX-License-Identifier: MIT
#include "report_format.hpp"

#include "io/errors.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace speed_vs_error {

using namespace vplrender;
namespace fs = std::filesystem;

std::string num(double v) {
  if (std::isnan(v)) return "";  // an error against a skipped reference
  char b[40];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}

double image_mean(const image_rgb& img) {
  double s = 0.0;
  for (float v : img.rgb) s += v;
  return img.rgb.empty() ? 0.0 : s / static_cast<double>(img.rgb.size());
}

std::string vec(const glm::vec3& v) { return num(v.x) + "," + num(v.y) + "," + num(v.z); }

std::string base_name(const std::string& scene_name) {
  std::string b = fs::path(scene_name).stem().string();
  for (char& c : b)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return b;
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f << text;
  if (!f) throw output_error("cannot write '" + path + "'");
}

std::string fixed(double v, int digits) {
  char b[40];
  std::snprintf(b, sizeof b, "%.*f", digits, v);
  return b;
}

std::string sci(double v) {
  if (std::isnan(v)) return "-";
  char b[40];
  std::snprintf(b, sizeof b, "%.3e", v);
  return b;
}

}  // namespace speed_vs_error
