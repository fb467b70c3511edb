// SPDX-License-Identifier: MIT
#pragma once
// Per-stage wall-clock times for the JSON report. GPU stages add their timer-query results with
// add() (and mark themselves running with running()); CPU stages use scoped(), which does both.
#include "render/running_stage.hpp"

#include <chrono>
#include <string>
#include <vector>

namespace vplrender {

struct stage_time {
  std::string name;
  double ms = 0.0;
  std::string clock;  // "cpu-wall" (steady_clock) or "gpu" (GL timer query)
};

class stage_timer {
public:
  class scope {
  public:
    scope(stage_timer& owner, std::string name)
        : owner_(owner), mark_(name), name_(std::move(name)), start_(std::chrono::steady_clock::now()) {}
    ~scope() {
      const std::chrono::duration<double, std::milli> d = std::chrono::steady_clock::now() - start_;
      owner_.add(name_, d.count(), "cpu-wall");
    }
    scope(const scope&) = delete;
    scope& operator=(const scope&) = delete;

  private:
    stage_timer& owner_;
    stage_mark mark_;
    std::string name_;
    std::chrono::steady_clock::time_point start_;
  };

  scope scoped(std::string name) { return scope(*this, std::move(name)); }
  // A stage timed elsewhere (a GL timer query reported with add()): only marked as running.
  static stage_mark running(std::string name) { return stage_mark(std::move(name)); }
  void add(std::string name, double ms, std::string clock) { stages_.push_back({std::move(name), ms, std::move(clock)}); }
  const std::vector<stage_time>& stages() const { return stages_; }

private:
  std::vector<stage_time> stages_;
};

}  // namespace vplrender
