// SPDX-License-Identifier: MIT
// vplrender's passes of the clamp's compensation (--clamp-compensation on, --clamp-compensation-pass
// compacted; docs/renderer.md, "The clamp compensation's passes"), run before the estimate kernel,
// which adds vr_clamp_compensations[p] (estimate_clamp_compensation.glsl). The term is nonzero only
// where another surface lies within dmin of the gather point, a few pixels near the junctions; in
// the estimate kernel a SIMD group (a warp of 32 on NVIDIA, 8 lanes on llvmpipe) would run all the
// directions whenever one of its pixels needs them, the others idle. Here the pixels that need them
// are compacted first, so that the directions run in full groups over that list only:
//   VR_CLAMP_PASS_MARK: one invocation per pixel writes its term 0 (in vr_out, the pixel's estimate
//     slot, which the estimate kernel reads before it writes the estimate) and appends the pixel to the
//     list when it is valid and vr_clamp_compensation_may_add (the near-surface test, once per
//     pixel and frame);
//   VR_CLAMP_PASS_DISPATCH: one invocation turns the list's count into the indirect dispatch's
//     work groups (laid out as vplkit::gl::dispatch_linear lays them: x up to max_groups_x, then y);
//   VR_CLAMP_PASS_DIRECTIONS: one invocation per list entry (glDispatchComputeIndirect) traces the
//     directions [begin, end) of its pixel (split over dispatches under llvmpipe's loop budget, the
//     sum kept in the term's lanes) and the last writes the finished term.
// Each pixel's term depends on the pixel only (its own stream, vplkit_clamp_compensation_stream),
// never on its place in the list, so the list's order (set by the atomics) does not change the
// image: it is the inline form's bit for bit. The host puts "#version 430" first and the defines
// (estimate_params.h; VR_CLAMP_COMPENSATION, VR_CLAMP_COMPENSATION_PASS, VR_CLAMP_PASS) in the preamble.
#include "estimate_visibility.glsl"
#include "estimate_clamp_compensation.glsl"

#ifndef VR_CLAMP_PASS
#error "clamp_compensation.comp: the host defines VR_CLAMP_PASS"
#endif

// The list (estimate_params.h, VR_ESTIMATE_BINDING_CLAMP_LIST): the indirect dispatch's group
// counts (x, y, z), the count of pixels, then the pixels.
layout(std430, binding = VR_ESTIMATE_BINDING_CLAMP_LIST) buffer VrClampList {  // appended to by atomics
  uvec4 vr_clamp_header;  // x, y, z: work groups of the directions pass; w: pixels listed
  uint vr_clamp_pixels[];
};
void main() {
#if VR_CLAMP_PASS == VR_CLAMP_PASS_MARK
  uint p = vr_pixel();
  if (!vr_in_image(p)) return;
  vr_out[p] = vec4(0.0);
  vplkit_gather_point gp = vplkit_load_gather_point(int(p));
  if (vplkit_gather_point_valid(gp) && vr_clamp_compensation_may_add(gp))
    vr_clamp_pixels[atomicAdd(vr_clamp_header.w, 1u)] = p;
#elif VR_CLAMP_PASS == VR_CLAMP_PASS_DISPATCH
  if (gl_GlobalInvocationID.x != 0u) return;
  uint groups = (vr_clamp_header.w + uint(VR_ESTIMATE_LOCAL_SIZE) - 1u) / uint(VR_ESTIMATE_LOCAL_SIZE);
  uint max_x = uint(vr_params.clamp_max_groups_x);
  uint x = min(groups, max_x);
  vr_clamp_header.xyz = uvec3(x, x == 0u ? 0u : (groups + x - 1u) / x, 1u);
#elif VR_CLAMP_PASS == VR_CLAMP_PASS_DIRECTIONS
  uint i = vr_pixel();  // the list entry (vr_pixel's linear layout over the indirect groups)
  if (i >= vr_clamp_header.w) return;
  uint p = vr_clamp_pixels[i];
  vplkit_gather_point gp = vplkit_load_gather_point(int(p));
  vplkit_estimator_state c =
      vplkit_make_estimator_state(vplkit_clamp_compensation_stream(vplkit_make_counter_rng(vr_params.seed, p)));
  if (vr_params.first_pass == 0) {
    // The sum so far, kept in the pixel's out lane; the stream's counter is the numbers drawn so
    // far: two per direction (vplkit_estimate_clamp_compensation_range), begin directions.
    c.sum = vr_out[p].xyz;
    c.rng.counter = 2u * uint(vr_params.begin);
  }
  vr_clamp_compensation_trace(gp, c, vr_params.begin, vr_params.end);
  vr_out[p] = vec4(vr_params.last_pass != 0 ? vr_clamp_compensation_term(c) : c.sum, 0.0);
#else
#error "VR_CLAMP_PASS must be VR_CLAMP_PASS_MARK, VR_CLAMP_PASS_DISPATCH or VR_CLAMP_PASS_DIRECTIONS"
#endif
}
