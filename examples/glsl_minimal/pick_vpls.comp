// SPDX-License-Identifier: MIT
// Minimal vplkit compute shader: every invocation picks one VPL by inverse-transform sampling.
// The host prepends #version (430 for OpenGL, 450 for Vulkan) and resolves the includes.
#extension GL_GOOGLE_include_directive : require
#include "vplkit/sampling/rng.glsl"
#include "vplkit/distribution/discrete_cdf.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Cdf { float cdf_values[]; };
layout(std430, binding = 1) readonly buffer Guide { uint guide_values[]; };
layout(std430, binding = 2) writeonly buffer Picks { uint picks[]; };
layout(std430, binding = 3) readonly buffer Params { uint n; uint guide_size; float total; uint count; };

// The accessors the pack's discrete_cdf.glsl reads its data through: your buffers, your bindings.
float vplkit_load_cdf(uint distribution, uint i) { return cdf_values[i]; }
uint vplkit_load_guide(uint distribution, uint j) { return guide_values[j]; }

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i >= count) return;
  vplkit_counter_rng rng = vplkit_make_counter_rng(42u, i);  // stream = invocation (pixel)
  const vplkit_discrete_cdf d = vplkit_discrete_cdf(0u, n, guide_size, total);
  picks[i] = vplkit_discrete_cdf_sample(d, vplkit_rng_next_float(rng)).index;
}
