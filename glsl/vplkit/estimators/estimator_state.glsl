// SPDX-License-Identifier: MIT
// vplkit GLSL pack: what a per-pixel estimate carries from one range of its samples to the next
// (the running sum and the random-number stream); mirrors
// include/vplkit/estimators/estimator_state.hpp (T = float). With the range forms of the
// estimators (vplkit_estimate_X_range / _finish) a kernel spreads one estimate over several
// dispatches, keeping this state in a buffer between them, and matches the one-shot form bit for
// bit (docs/glsl/estimators.md, "Range forms").
#ifndef VPLKIT_ESTIMATORS_ESTIMATOR_STATE_GLSL
#define VPLKIT_ESTIMATORS_ESTIMATOR_STATE_GLSL

#include "vplkit/sampling/rng.glsl"

struct vplkit_estimator_state {
  vec3 sum;                 // the samples' values so far, added in sample order
  vplkit_counter_rng rng;   // where the next draw comes from
};

vplkit_estimator_state vplkit_make_estimator_state(vplkit_counter_rng rng) {
  return vplkit_estimator_state(vec3(0.0), rng);
}

#endif  // VPLKIT_ESTIMATORS_ESTIMATOR_STATE_GLSL
