// SPDX-License-Identifier: MIT
// Minimal vplkit compute shader: every invocation picks one VPL by inverse-transform sampling from
// the CDF and guide table that the pack's cdf_build.comp wrote, where it wrote them: the same
// buffers at the same binding points (cdf_build_params.h), and the total from its info record, so
// nothing goes through the host between the two kernels.
// The host prepends #version (430 for OpenGL, 450 for Vulkan) and resolves the includes.
#extension GL_GOOGLE_include_directive : require
#include "vplkit/distribution/cdf_build_params.h"
#include "vplkit/distribution/discrete_cdf.glsl"
#include "vplkit/sampling/rng.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = VPLKIT_CDF_BUILD_BINDING_CDF) readonly buffer Cdf { float cdf_values[]; };
layout(std430, binding = VPLKIT_CDF_BUILD_BINDING_GUIDE) readonly buffer Guide { uint guide_values[]; };
layout(std430, binding = VPLKIT_CDF_BUILD_BINDING_INFO) readonly buffer Info { vplkit_cdf_build_info info[]; };
// Bindings of this shader's own: apart from cdf_build.comp's, so nothing is rebound in between.
layout(std430, binding = 6) writeonly buffer Picks { uint picks[]; };
layout(std140, binding = 7) uniform Params { uint n; uint count; };

// The accessors the pack's discrete_cdf.glsl reads its data through: your buffers, your bindings.
float vplkit_load_cdf(uint distribution, uint i) { return cdf_values[i]; }
uint vplkit_load_guide(uint distribution, uint j) { return guide_values[j]; }

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i >= count) return;
  vplkit_counter_rng rng = vplkit_make_counter_rng(42u, i);  // stream = invocation (pixel)
  const vplkit_discrete_cdf d = vplkit_discrete_cdf(0u, n, vplkit_discrete_guide_size(n), info[0].total);
  picks[i] = vplkit_discrete_cdf_sample(d, vplkit_rng_next_float(rng)).index;
}
