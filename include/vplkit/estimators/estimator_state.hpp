// SPDX-License-Identifier: MIT
#pragma once
// What a per-pixel estimate carries from one range of its samples to the next: the running sum
// and the random-number stream. Every estimator comes in three parts (docs/api/estimators.md,
// "Range forms"): estimate_X_range(..., state, begin, end, ...) runs samples [begin, end) of its
// loop, estimate_X_finish(state, ...) turns the sum into the estimate, and the one-shot
// estimate_X(..., rng, n, ...) is make_estimator_state + range(0, n) + finish. Consecutive ranges
// that cover [0, n) perform exactly the floating-point operations and random draws of one loop,
// so a GPU can spread an estimate over several dispatches and match the one-shot bit for bit.
#include <vplkit/core/vector.hpp>
#include <vplkit/sampling/rng.hpp>

namespace vplkit {

template <class T>
struct estimator_state {
  vec3<T> sum = vec3<T>(T(0));  // the samples' values so far, added in sample order
  counter_rng rng{};            // where the next draw comes from
};

template <class T>
inline estimator_state<T> make_estimator_state(const counter_rng& rng) {
  return estimator_state<T>{vec3<T>(T(0)), rng};
}

}  // namespace vplkit
