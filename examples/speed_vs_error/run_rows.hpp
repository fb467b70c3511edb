// SPDX-License-Identifier: MIT
// One row of speed_vs_error's results: a timed run with its errors, and per (method, samples) the
// bias/variance split over the seeds. The sweep makes them, the analysis writer and --replot read them.
#pragma once

#include "metrics.hpp"

#include "render/method_traits.hpp"
#include "render/settings.hpp"

#include <cstdint>
#include <limits>
#include <string>

namespace speed_vs_error {

struct run_row {
  vplrender::method meth;
  std::string label;  // the method's name, or METHOD-clamped (its clamped runs when both are swept)
  vplrender::clamp_compensation_choice compensation = vplrender::clamp_compensation_choice::off;  // as the run used it
  int samples = 0;
  int vpls = 0, dirs = 0;  // the run's --vpls and --dirs (dirs: R samples with --dirs-per-sample R)
  std::uint32_t seed = 0;
  double build_ms = 0, estimate_ms = 0, total_ms = 0, wall_ms = 0;
  double total_ms_min = 0;
  int repeats = 1;
  long long gpu_peak_bytes = 0;  // GPU buffers the estimator held at its peak (docs/results.md, memory)
  std::string stages;
  double mean = 0;  // the image's mean over pixels and channels (linear HDR)
  double band_mean = std::numeric_limits<double>::quiet_NaN();  // over the junction band's pixels
  image_error vs_vpl, vs_gather, vs_exact;
  // vs_gather and vs_exact with their reference's noise removed (compare_net); NaN without --ref-noise.
  image_error vs_gather_net{std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  image_error vs_exact_net{std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
};

// A run's series: the method's name, or METHOD-clamped for the clamped runs of global, local, gbg
// and ris when both settings of the clamp compensation are swept.
inline std::string series_label(vplrender::method m, vplrender::clamp_compensation_choice c, bool both) {
  using namespace vplrender;
  const bool clamped = m != method::reference && method_has_clamp(m);
  return std::string(to_string(m)) + (both && clamped && c == clamp_compensation_choice::off ? "-clamped" : "");
}

struct bias_variance_row {
  vplrender::method meth;
  std::string label;
  vplrender::clamp_compensation_choice compensation = vplrender::clamp_compensation_choice::off;
  int samples = 0, seeds = 0;
  double variance = 0, bias2_vpl = 0, bias2_gather = 0, bias2_exact = 0;
  // bias2 against gather and exact less their reference's noise (its MSE): the squared bias
  // against the truth itself. NaN without --ref-noise.
  double bias2_gather_net = std::numeric_limits<double>::quiet_NaN();
  double bias2_exact_net = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace speed_vs_error
