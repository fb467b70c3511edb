// SPDX-License-Identifier: MIT
#pragma once
// Texel blocks: the level of indirection of tiled candidate distributions
// (builders/tiled_distribution.hpp, docs/math.md 13.5). The DPRSM's faces are cut into blocks of
// B x B texels, block b = (face P + by) P + bx with P = ceil(R / B) blocks per face side. Per
// block, once per frame:
//  - each texel's share l_t / L_b of the block's flux luminance (l_t = flux_weight_texel, L_b their
//    sum; 0 for a texel without a VPL), with the running sums in the block's row-major order: a
//    draw within the block follows the flux;
//  - a proxy VPL: the l-weighted mean position and unit normal and the block's total flux. It
//    stands for the block where a tile weighs it (tile_block_weight), so a tile evaluates 2 R^2 /
//    B^2 proxies instead of 2 R^2 VPLs.
// The per-block and per-(block, tile) functions never throw; their GLSL mirrors are
// builders/tile_blocks.glsl, under the same names with the vplkit_ prefix.
#include <vplkit/builders/flux_weights.hpp>
#include <vplkit/core/error.hpp>
#include <vplkit/core/gather_point.hpp>
#include <vplkit/core/unit_or_zero.hpp>
#include <vplkit/paraboloid/texel_grid.hpp>
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/luminance.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

namespace vplkit {

// The block layout of a DPRSM of resolution R.
struct tile_block_grid {
  int resolution = 0;  // R
  int block = 1;       // B: texels per block side
  int per_side = 0;    // P = ceil(R / B)

  int count() const noexcept { return 2 * per_side * per_side; }
  // The block of texel t (face * R^2 + y * R + x).
  int block_of(int t) const noexcept {
    const ivec2 xy = texel_coords(t, resolution);
    return (texel_face(t, resolution) * per_side + xy.y / block) * per_side + xy.x / block;
  }
  int face_of_block(int b) const noexcept { return b / (per_side * per_side); }
  // Block b's texels: x in [x0, x1), y in [y0, y1) of its face (the last row and column of blocks
  // may be cut by the face's edge).
  int x0(int b) const noexcept { return (b % (per_side * per_side)) % per_side * block; }
  int y0(int b) const noexcept { return (b % (per_side * per_side)) / per_side * block; }
  int x1(int b) const noexcept { return std::min(x0(b) + block, resolution); }
  int y1(int b) const noexcept { return std::min(y0(b) + block, resolution); }
};

// R >= 1, B >= 1 (else invalid_input).
inline tile_block_grid make_tile_block_grid(int resolution, int block) {
  if (resolution < 1 || block < 1)
    throw invalid_input("make_tile_block_grid: resolution " + std::to_string(resolution) + " and block " +
                        std::to_string(block) + " must both be >= 1");
  return tile_block_grid{resolution, block, (resolution + block - 1) / block};
}

// One block's flux luminance L_b and proxy VPL (all zero for a block without a VPL).
template <class T>
struct tile_block_proxy {
  vpl<T> proxy{};
  T flux_luminance = T(0);
};

// Block b's proxy: the sums in row-major order over the texels with l_t > 0. Per-block function.
template <class T>
inline tile_block_proxy<T> tile_block_proxy_of(const dprsm_view<T>& view, const tile_block_grid& g, int b) {
  const int face = g.face_of_block(b);
  T L = T(0);
  vec3<T> P(T(0)), N(T(0)), F(T(0));
  for (int y = g.y0(b); y < g.y1(b); ++y)
    for (int x = g.x0(b); x < g.x1(b); ++x) {
      const int t = texel_index(face, x, y, g.resolution);
      const T l = flux_weight_texel(view, t);
      if (!(l > T(0))) continue;
      const vpl<T> v = view.vpl_at(t);
      L += l;
      P += l * v.position;
      N += l * unit_or_zero(v.normal);
      F += v.flux;
    }
  if (!(L > T(0))) return {};
  return {vpl<T>{P / L, unit_or_zero(N), F}, L};
}

// A texel's share l / L of its block (0 when either is not > 0). Per-texel function.
template <class T>
inline T tile_texel_share(T l, T L) noexcept {
  const T s = l > T(0) && L > T(0) ? l / L : T(0);
  return s > T(0) ? s : T(0);  // written so that NaN gives 0
}

// The frame's blocks: shares per texel, the texels of positive share block by block with their
// running sums, and the proxies.
template <class T>
struct tile_blocks {
  tile_block_grid grid;
  std::vector<T> share;                // per texel (2 R^2): l_t / L_b, 0 without a VPL
  std::vector<int> begin;              // per block: its first entry in texels (count() + 1)
  std::vector<int> texels;             // the texels of positive share, block by block, row-major
  std::vector<T> cumulative;           // per entry of texels: the running share within its block
  std::vector<vpl<T>> proxy;           // per block (flux 0 without a VPL)

  int count() const noexcept { return grid.count(); }
  int block_of(int t) const noexcept { return grid.block_of(t); }
  // The texel of block b at the fraction d / w of its flux: the first texel whose running share c
  // has d < w c (w c rounded first), else the block's last one; w <= 0 or NaN takes the first.
  // A block CDF's draw u' in [F(b), F(b + 1)) gives d = u' - F(b), w = F(b + 1) - F(b): the
  // position of u' in b's bin, compared without a division (GLSL does not round one correctly).
  // The block must hold a texel (begin[b] < begin[b + 1]).
  int texel_in_block(std::size_t b, T d, T w) const noexcept {
    if (!(w > T(0))) {
      d = T(0);
      w = T(1);
    }
    int k = begin[b];
    const int last = begin[b + 1] - 1;
    while (k < last && !(d < w * cumulative[std::size_t(k)])) ++k;
    return texels[std::size_t(k)];
  }
};

// The blocks of side B of a DPRSM (throws invalid_input for a bad view or B < 1).
template <class T>
inline tile_blocks<T> make_tile_blocks(const dprsm_view<T>& view, int block) {
  view.validate();
  tile_blocks<T> tb;
  tb.grid = make_tile_block_grid(view.resolution, block);
  const tile_block_grid& g = tb.grid;
  tb.share.assign(std::size_t(view.texel_count()), T(0));
  tb.begin.assign(std::size_t(g.count()) + 1, 0);
  tb.proxy.assign(std::size_t(g.count()), vpl<T>{});
  for (int b = 0; b < g.count(); ++b) {
    tb.begin[std::size_t(b)] = int(tb.texels.size());
    const tile_block_proxy<T> p = tile_block_proxy_of(view, g, b);
    if (!(p.flux_luminance > T(0))) continue;
    tb.proxy[std::size_t(b)] = p.proxy;
    const int face = g.face_of_block(b);
    T c = T(0);
    for (int y = g.y0(b); y < g.y1(b); ++y)
      for (int x = g.x0(b); x < g.x1(b); ++x) {
        const int t = texel_index(face, x, y, g.resolution);
        const T s = tile_texel_share(flux_weight_texel(view, t), p.flux_luminance);
        if (!(s > T(0))) continue;
        tb.share[std::size_t(t)] = s;
        c += s;
        tb.texels.push_back(t);
        tb.cumulative.push_back(c);
      }
  }
  tb.begin[std::size_t(g.count())] = int(tb.texels.size());
  return tb;
}

// A tile's weight of one block: the mean over its gather points of the proxy's unshadowed
// contribution's luminance (section 2's contribution, clamped at dmin), summed in the points'
// order and multiplied by 1 / count, as the global weights (global_weights.hpp); invalid points
// are skipped and not counted; 0 without a valid point or for a proxy without flux. Per-(block,
// tile) function.
template <class T>
inline T tile_block_weight(const gather_point<T>* points, std::size_t count, const vpl<T>& proxy, T dmin) noexcept {
  if (!vpl_has_flux(proxy)) return T(0);
  T sum = T(0);
  int used = 0;
  for (std::size_t i = 0; i < count; ++i) {
    if (!gather_point_valid(points[i])) continue;
    sum += luminance(vpl_contribution(points[i], proxy, dmin));
    ++used;
  }
  return used > 0 ? sum * (T(1) / T(used)) : T(0);
}

}  // namespace vplkit
