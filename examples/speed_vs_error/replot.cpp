// SPDX-License-Identifier: MIT
#include "replot.hpp"

#include "analysis_writer.hpp"
#include "report_format.hpp"
#include "run_rows.hpp"
#include "sve_options.hpp"

#include "io/errors.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>

namespace speed_vs_error {

using namespace vplrender;

std::vector<std::string> replot(const std::string& csv_path, const std::string& out) {
  std::ifstream f(csv_path, std::ios::binary);
  if (!f) throw input_error("--replot: cannot open '" + csv_path + "'");
  std::string line;
  const auto fields = [](const std::string& l) {
    std::vector<std::string> v;
    std::string cur;
    for (char c : l) {
      if (c == ',') v.push_back(cur), cur.clear();
      else if (c != '\r') cur += c;
    }
    v.push_back(cur);
    return v;
  };
  if (!std::getline(f, line)) throw input_error("--replot: '" + csv_path + "' is empty");
  const std::vector<std::string> header = fields(line);
  const auto col = [&](const std::string& name) -> std::size_t {
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return i;
    throw input_error("--replot: '" + csv_path + "' has no column '" + name + "'");
  };
  const std::size_t c_scene = col("scene"), c_backend = col("backend"), c_method = col("method"),
                    c_samples = col("samples"), c_width = col("width"), c_height = col("height"),
                    c_total = col("total_ms"), c_rv = col("rmse_vplsum"), c_lv = col("relmse_vplsum"),
                    c_rg = col("rmse_gather"), c_lg = col("relmse_gather");
  // Written since the exact reference exists; older CSVs have neither column.
  const auto optional_col = [&](const std::string& name) {
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return i;
    return header.size();
  };
  const std::size_t c_re = optional_col("rmse_exact"), c_le = optional_col("relmse_exact");
  const std::size_t c_cc = optional_col("clamp_compensation");  // since the clamp compensation exists
  // Since --ref-noise: the errors with the reference's noise removed.
  const std::size_t c_rgn = optional_col("rmse_gather_net"), c_lgn = optional_col("relmse_gather_net"),
                    c_ren = optional_col("rmse_exact_net"), c_len = optional_col("relmse_exact_net");
  const auto number = [&](const std::string& t, int line_no) {
    if (t.empty()) return std::numeric_limits<double>::quiet_NaN();
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    if (end == t.c_str() || *end != '\0')
      throw input_error("--replot: " + csv_path + ":" + std::to_string(line_no) + ": '" + t + "' is not a number");
    return v;
  };
  std::vector<run_row> rows;
  std::vector<int> samples;
  std::string scene, backend, size;
  bool has_vpl = false, has_gather = false, has_exact = false;
  int line_no = 1;
  while (std::getline(f, line)) {
    ++line_no;
    if (line.empty() || line == "\r") continue;
    const std::vector<std::string> v = fields(line);
    if (v.size() != header.size())
      throw input_error("--replot: " + csv_path + ":" + std::to_string(line_no) + ": " + std::to_string(v.size()) +
                        " fields, the header has " + std::to_string(header.size()));
    run_row r;
    try {
      r.meth = parse_swept_method(v[c_method]);
    } catch (const usage_error& e) {
      throw input_error("--replot: " + csv_path + ":" + std::to_string(line_no) + ": " + e.what());
    }
    r.samples = static_cast<int>(number(v[c_samples], line_no));
    r.total_ms = number(v[c_total], line_no);
    r.vs_vpl = {number(v[c_rv], line_no), number(v[c_lv], line_no)};
    r.vs_gather = {number(v[c_rg], line_no), number(v[c_lg], line_no)};
    if (c_re < v.size() && c_le < v.size()) r.vs_exact = {number(v[c_re], line_no), number(v[c_le], line_no)};
    else r.vs_exact = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
    if (c_rgn < v.size() && c_lgn < v.size()) r.vs_gather_net = {number(v[c_rgn], line_no), number(v[c_lgn], line_no)};
    if (c_ren < v.size() && c_len < v.size()) r.vs_exact_net = {number(v[c_ren], line_no), number(v[c_len], line_no)};
    has_exact = has_exact || !std::isnan(r.vs_exact.rmse);
    has_vpl = has_vpl || !std::isnan(r.vs_vpl.rmse);
    has_gather = has_gather || !std::isnan(r.vs_gather.rmse);
    if (c_cc < v.size() && v[c_cc] == "on") r.compensation = clamp_compensation_choice::on;
    if (std::find(samples.begin(), samples.end(), r.samples) == samples.end()) samples.push_back(r.samples);
    scene = v[c_scene], backend = v[c_backend], size = v[c_width] + "x" + v[c_height];
    rows.push_back(r);
  }
  if (rows.empty()) throw input_error("--replot: '" + csv_path + "' has no rows");
  std::sort(samples.begin(), samples.end());
  bool any_on = false, any_off = false;
  for (const run_row& r : rows) {
    if (series_label(r.meth, clamp_compensation_choice::off, true) == to_string(r.meth)) continue;  // no clamp
    (r.compensation == clamp_compensation_choice::on ? any_on : any_off) = true;
  }
  std::vector<std::string> labels;
  for (run_row& r : rows) {
    r.label = series_label(r.meth, r.compensation, any_on && any_off);
    if (std::find(labels.begin(), labels.end(), r.label) == labels.end()) labels.push_back(r.label);
  }
  const std::string caption = scene + " " + size + ", backend " + backend + " (from " + base_name(csv_path) + ".csv)";
  return write_analysis(rows, labels, samples, has_vpl, has_gather, has_exact, 0, caption,
                        "Scene `" + scene + "`, " + size + ", backend `" + backend + "`.", out);
}

}  // namespace speed_vs_error
