// SPDX-License-Identifier: MIT
#pragma once
// Loop iterations one dispatch may spend per invocation: llvmpipe leaves every loop after 65535
// iterations per invocation, silently (docs/glsl.md), so the GPU backend splits long loops over
// dispatches and keeps a margin.
namespace vplrender {

constexpr int gpu_loop_budget = 60000;

}  // namespace vplrender
