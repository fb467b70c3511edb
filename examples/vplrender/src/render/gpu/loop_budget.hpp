// SPDX-License-Identifier: MIT
#pragma once
// Loop iterations one dispatch may spend per invocation where the driver limits them: llvmpipe
// (and softpipe) leave every loop after 65535 iterations per invocation, silently (docs/glsl.md),
// so there the GPU backend splits long loops over dispatches and keeps a margin. Other drivers run
// each estimate in one dispatch: the split costs a storage round trip of the pixel's state per
// dispatch and a variant that carries the state's code, for a limit they do not have.
#include "render/settings.hpp"

#include <headless_gl/compute.hpp>

namespace vplrender {

constexpr int gpu_loop_budget = 60000;

// Whether the estimate dispatches must stay under gpu_loop_budget (render_settings::loop_budget;
// needs a current GL context).
inline bool loop_budget_applies(loop_budget_choice c) {
  switch (c) {
    case loop_budget_choice::always: return true;
    case loop_budget_choice::never: return false;
    case loop_budget_choice::automatic: break;
  }
  return vplkit::gl::is_software_renderer();
}

}  // namespace vplrender
