// SPDX-License-Identifier: MIT
#pragma once
// Equal-error comparison and the Pareto front of (time, error) points: which method reaches a
// given error fastest. Pure functions on numbers, so they are unit-tested
// without running a renderer (tests/renderer/renderer_pareto_test.cpp).
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace speed_vs_error {

// One configuration of one method: its time (ms) and its error (e.g. RMSE), both > 0 to be used.
struct cost_error_point {
  std::string method;
  int samples = 0;
  double ms = 0.0;
  double error = 0.0;
};

// A point that can be placed on a log-log plot: finite, positive time and error.
inline bool usable(const cost_error_point& p) {
  return std::isfinite(p.ms) && std::isfinite(p.error) && p.ms > 0.0 && p.error > 0.0;
}

// The points no other point beats in both time and error: sorted by time, each strictly more
// accurate than every faster point. Points with a non-finite or non-positive time or error are
// ignored (they cannot be placed on a log-log plot either). Ties in time keep the lower error.
inline std::vector<cost_error_point> pareto_front(std::vector<cost_error_point> pts) {
  pts.erase(std::remove_if(pts.begin(), pts.end(), [](const cost_error_point& p) { return !usable(p); }), pts.end());
  std::stable_sort(pts.begin(), pts.end(), [](const cost_error_point& a, const cost_error_point& b) {
    return a.ms < b.ms || (a.ms == b.ms && a.error < b.error);
  });
  std::vector<cost_error_point> front;
  for (const cost_error_point& p : pts)
    if (front.empty() || p.error < front.back().error) front.push_back(p);
  return front;
}

// Time one method needs to reach `target` error, from its points (any order): the first pair of
// consecutive points (by time) whose errors bracket the target, interpolated linearly in
// log(time)-log(error) — Monte Carlo error falls as a power of time, a straight line there. A
// point already at or below the target gives its own time when it is the fastest such point.
// Empty when the method never reaches the target (no extrapolation: the claim would be unmeasured).
inline std::optional<double> time_to_error(std::vector<cost_error_point> pts, double target) {
  pts.erase(std::remove_if(pts.begin(), pts.end(), [](const cost_error_point& p) { return !usable(p); }), pts.end());
  if (pts.empty() || !(target > 0.0)) return std::nullopt;
  std::sort(pts.begin(), pts.end(), [](const cost_error_point& a, const cost_error_point& b) { return a.ms < b.ms; });
  if (pts.front().error <= target) return pts.front().ms;
  for (std::size_t i = 1; i < pts.size(); ++i) {
    const cost_error_point& a = pts[i - 1];
    const cost_error_point& b = pts[i];
    if (b.error > target) continue;
    // a.error > target >= b.error: interpolate in log space.
    const double la = std::log(a.error), lb = std::log(b.error), lt = std::log(target);
    const double f = la == lb ? 1.0 : (la - lt) / (la - lb);
    return std::exp(std::log(a.ms) + f * (std::log(b.ms) - std::log(a.ms)));
  }
  return std::nullopt;
}

// Error targets for an equal-error table: `count` values spaced evenly in log between the largest
// "best error" of any method (the level every method reaches) and the smallest error measured.
// Empty when there is nothing to compare.
inline std::vector<double> error_targets(const std::vector<cost_error_point>& pts, int count) {
  double lowest = 0.0, common = 0.0;
  bool any = false;
  std::vector<std::string> methods;
  for (const cost_error_point& p : pts)
    if (std::find(methods.begin(), methods.end(), p.method) == methods.end()) methods.push_back(p.method);
  for (const std::string& m : methods) {
    double best = 0.0;
    bool has = false;
    for (const cost_error_point& p : pts)
      if (p.method == m && std::isfinite(p.error) && p.error > 0.0 && (!has || p.error < best)) {
        best = p.error;
        has = true;
      }
    if (!has) continue;
    if (!any) {
      lowest = common = best;
      any = true;
    }
    lowest = std::min(lowest, best);
    common = std::max(common, best);
  }
  std::vector<double> t;
  if (!any || count <= 0) return t;
  if (count == 1 || common == lowest) return {common};
  // The ends are the measured values themselves: exp(log(x)) may round below x, and the best
  // method would then "not reach" its own best error.
  for (int i = 0; i < count; ++i)
    t.push_back(i == 0           ? common
                : i == count - 1 ? lowest
                                 : std::exp(std::log(common) + (std::log(lowest) - std::log(common)) * i / (count - 1)));
  return t;
}

}  // namespace speed_vs_error
