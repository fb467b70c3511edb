// SPDX-License-Identifier: MIT
// vplkit GLSL pack: texel blocks of tiled candidate distributions (docs/math.md 13.5); mirrors
// include/vplkit/builders/tile_blocks.hpp (T = float): the blocks' grid, the per-block function
// (its proxy VPL and flux luminance) and the per-texel share. A block kernel runs
// vplkit_tile_block_proxy_of once per block and writes its texels' shares
// (vplkit_tile_texel_share of vplkit_flux_weight_texel and the block's flux luminance, 0 without a
// VPL), which builders/tiled_distribution.glsl then reads; builders/tile_weights.glsl weighs the
// proxies per tile.
//
// ACCESSORS: vplkit_load_dprsm_position / _normal / _albedo (vpl/dprsm_view.glsl).
//
// Arithmetic, as in the C++: the sums run over the block's texels in row-major order. Outside
// `precise` code a GPU may contract l * p + P into an FMA, and l / L is within 2.5 ulp, so a proxy
// or share may differ from the C++ one in its last bits (they shape the pmf, which stays exact for
// whatever values the kernel wrote).
#ifndef VPLKIT_BUILDERS_TILE_BLOCKS_GLSL
#define VPLKIT_BUILDERS_TILE_BLOCKS_GLSL

#include "vplkit/builders/flux_weights.glsl"
#include "vplkit/core/unit_or_zero.glsl"
#include "vplkit/paraboloid/texel_grid.glsl"
#include "vplkit/vpl/dprsm_view.glsl"
#include "vplkit/vpl/vpl.glsl"

// C++ tile_block_grid: R, B texels per block side, P = ceil(R / B) blocks per face side; block b =
// (face P + by) P + bx.
struct vplkit_tile_block_grid {
  int resolution;
  int block;
  int per_side;
};

// C++ make_tile_block_grid (R >= 1 and B >= 1 are the caller's to ensure).
vplkit_tile_block_grid vplkit_make_tile_block_grid(int resolution, int block) {
  return vplkit_tile_block_grid(resolution, block, (resolution + block - 1) / block);
}

int vplkit_tile_block_grid_count(vplkit_tile_block_grid g) { return 2 * g.per_side * g.per_side; }

int vplkit_tile_block_grid_block_of(vplkit_tile_block_grid g, int t) {
  ivec2 xy = vplkit_texel_coords(t, g.resolution);
  return (vplkit_texel_face(t, g.resolution) * g.per_side + xy.y / g.block) * g.per_side + xy.x / g.block;
}

int vplkit_tile_block_grid_face_of_block(vplkit_tile_block_grid g, int b) { return b / (g.per_side * g.per_side); }

// Block b's texels: [x0, x1) x [y0, y1) of its face, as (x0, y0, x1, y1).
ivec4 vplkit_tile_block_grid_rect(vplkit_tile_block_grid g, int b) {
  int in_face = b % (g.per_side * g.per_side);
  int x0 = (in_face % g.per_side) * g.block, y0 = (in_face / g.per_side) * g.block;
  return ivec4(x0, y0, min(x0 + g.block, g.resolution), min(y0 + g.block, g.resolution));
}

// C++ tile_block_proxy<float>.
struct vplkit_tile_block_proxy {
  vplkit_vpl proxy;
  float flux_luminance;
};

// C++ tile_block_proxy_of: the l-weighted mean position and unit normal and the total flux of the
// texels with l > 0; all zero for a block without one.
vplkit_tile_block_proxy vplkit_tile_block_proxy_of(vplkit_dprsm_view view, vplkit_tile_block_grid g, int b) {
  int face = vplkit_tile_block_grid_face_of_block(g, b);
  ivec4 r = vplkit_tile_block_grid_rect(g, b);
  float L = 0.0;
  vec3 P = vec3(0.0), N = vec3(0.0), F = vec3(0.0);
  for (int y = r.y; y < r.w; ++y)
    for (int x = r.x; x < r.z; ++x) {
      int t = vplkit_texel_index(face, x, y, g.resolution);
      float l = vplkit_flux_weight_texel(view, t);
      if (!(l > 0.0)) continue;
      vplkit_vpl v = vplkit_dprsm_view_vpl_at(view, t);
      L += l;
      P += l * v.position;
      N += l * vplkit_unit_or_zero(v.normal);
      F += v.flux;
    }
  if (!(L > 0.0)) return vplkit_tile_block_proxy(vplkit_vpl(vec3(0.0), vec3(0.0), vec3(0.0)), 0.0);
  return vplkit_tile_block_proxy(vplkit_vpl(P / L, vplkit_unit_or_zero(N), F), L);
}

// C++ tile_texel_share: l / L, 0 when either is not > 0 (NaN gives 0).
float vplkit_tile_texel_share(float l, float L) {
  float s = l > 0.0 && L > 0.0 ? l / L : 0.0;
  return s > 0.0 ? s : 0.0;
}

#endif  // VPLKIT_BUILDERS_TILE_BLOCKS_GLSL
