// SPDX-License-Identifier: MIT
// --candidate-source tiles on the GPU: the frame's texel blocks, render/cpu/tiled_candidates.hpp's
// make_tile_blocks statement for statement. One invocation per block of B x B texels (block b =
// (face * P + by) * P + bx, P = ceil(R / B) blocks per face side): the block's flux luminance L
// (the flux weights of builders/flux_weights.glsl), each texel's share l_t / L (0 without a VPL;
// estimate_tiles.glsl draws within a block from them), and the block's proxy VPL: the
// l-weighted mean position and unit normal and the total flux (tile_weights.comp weighs it). The
// host (render/gpu/gpu_tiles.cpp) prepends "#version 430".
//
// Precision: the sums run in the C++ order; the GPU may contract l * p + P into an FMA and rounds
// l / L within 2.5 ulp, so shares and proxies are the C++ values within a few ulps
// (renderer_gpu_parity_ris_mis_test's bound covers what that moves).
layout(local_size_x = 64) in;

#include "vplkit/builders/flux_weights.glsl"
#include "vplkit/core/unit_or_zero.glsl"
#include "vplkit/paraboloid/texel_grid.glsl"

struct vr_surfel {
  vec4 position;
  vec4 normal;
  vec4 albedo;
};
layout(std430, binding = 0) readonly buffer VrDprsm { vr_surfel vr_dprsm[]; };
layout(std430, binding = 1) writeonly buffer VrShares { float vr_shares[]; };   // 2 R^2: per texel
layout(std430, binding = 2) writeonly buffer VrProxies { vec4 vr_proxies[]; };  // 3 per block

uniform int u_dprsm_res;
uniform vec3 u_light_pos;
uniform vec3 u_light_int;
uniform vec3 u_frame_pos;
uniform vec3 u_axis_x;
uniform vec3 u_axis_y;
uniform vec3 u_axis_z;
uniform int u_block;     // B
uniform int u_per_side;  // P = ceil(R / B)

vec3 vplkit_load_dprsm_position(int texel) { return vr_dprsm[texel].position.xyz; }
vec3 vplkit_load_dprsm_normal(int texel) { return vr_dprsm[texel].normal.xyz; }
vec3 vplkit_load_dprsm_albedo(int texel) { return vr_dprsm[texel].albedo.xyz; }

void main() {
  vplkit_dprsm_view view = vplkit_dprsm_view(
      u_dprsm_res, vplkit_point_light(u_light_pos, u_light_int,
                                      vplkit_light_frame(u_frame_pos, u_axis_x, u_axis_y, u_axis_z)));
  int R = u_dprsm_res, B = u_block, per_face = u_per_side * u_per_side;
  // Groups spread over x and y past GL_MAX_COMPUTE_WORK_GROUP_COUNT (vplkit::gl::dispatch_linear).
  int b = int(gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x);
  if (b >= 2 * per_face) return;
  int face = b / per_face, in_face = b % per_face;
  int x0 = (in_face % u_per_side) * B, y0 = (in_face / u_per_side) * B;
  int x1 = min(x0 + B, R), y1 = min(y0 + B, R);
  float L = 0.0;
  vec3 P = vec3(0.0), N = vec3(0.0), F = vec3(0.0);
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      int t = vplkit_texel_index(face, x, y, R);
      float l = vplkit_flux_weight_texel(view, t);
      if (!(l > 0.0)) continue;
      vplkit_vpl v = vplkit_dprsm_view_vpl_at(view, t);
      L += l;
      P += l * v.position;
      N += l * vplkit_unit_or_zero(v.normal);
      F += v.flux;
    }
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      int t = vplkit_texel_index(face, x, y, R);
      float l = L > 0.0 ? vplkit_flux_weight_texel(view, t) : 0.0;
      float s = l > 0.0 ? l / L : 0.0;
      vr_shares[t] = s > 0.0 ? s : 0.0;
    }
  bool lit = L > 0.0;
  vr_proxies[3 * b] = vec4(lit ? P / L : vec3(0.0), 0.0);
  vr_proxies[3 * b + 1] = vec4(lit ? vplkit_unit_or_zero(N) : vec3(0.0), 0.0);
  vr_proxies[3 * b + 2] = vec4(lit ? F : vec3(0.0), 0.0);
}
