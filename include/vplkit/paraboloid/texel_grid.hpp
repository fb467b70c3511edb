// SPDX-License-Identifier: MIT
#pragma once
// The R x R texel grid of each paraboloid face over uv in [-1,1]^2 (docs/math.md section 1).
//
// Layout (mirrored by glsl/vplkit): x runs along u, y along v; texel (x, y) covers
// u in [-1 + 2x/R, -1 + 2(x+1)/R] and likewise for v; its centre is
// uv = ((x + 0.5) / R * 2 - 1, (y + 0.5) / R * 2 - 1). The flat index over both faces is
//   index = face * R * R + y * R + x        (face 0 = front, 1 = back)
// so a DPRSM is 2 * R * R texels, front face first, each face row-major. Indices are int
// (as in GLSL): R is limited to paraboloid_max_resolution so that 2 R^2 fits.
#include <vplkit/core/vector.hpp>
#include <vplkit/paraboloid/paraboloid.hpp>

namespace vplkit {

// 2 * 16384^2 = 2^29 texels: the index and the integer validity test below stay in int.
inline constexpr int paraboloid_max_resolution = 16384;

inline int texel_count(int R) { return 2 * R * R; }

inline int texel_index(int face, int x, int y, int R) { return face * R * R + y * R + x; }

inline int texel_face(int index, int R) { return index / (R * R); }

// (x, y) of a flat index within its face.
inline ivec2 texel_coords(int index, int R) {
  const int in_face = index % (R * R);
  return ivec2(in_face % R, in_face / R);
}

template <class T>
inline vec2<T> texel_center_uv(int x, int y, int R) {
  return vec2<T>((T(x) + T(0.5)) / T(R) * T(2) - T(1), (T(y) + T(0.5)) / T(R) * T(2) - T(1));
}

// A point of texel (x, y) chosen by xi in [0, 1]^2: uv = ((x + xi.x) / R * 2 - 1, ...), written
// as texel_center_uv so that xi = (0.5, 0.5) gives the centre bit for bit. xi is clamped into
// [0, 1] (NaN -> 0), so the point never leaves the texel's closed square; a uniform xi gives a
// uniform point of the square, density (R/2)^2 per unit uv area. Near the rim part of the square
// lies outside the unit disk (r2 > 1): callers decide what such a point means (dprsm_patch.hpp
// rejects it).
template <class T>
inline vec2<T> texel_point_uv(int x, int y, int R, vec2<T> xi) {
  const T sx = !(xi.x >= T(0)) ? T(0) : (xi.x > T(1) ? T(1) : xi.x);
  const T sy = !(xi.y >= T(0)) ? T(0) : (xi.y > T(1) ? T(1) : xi.y);
  return vec2<T>((T(x) + sx) / T(R) * T(2) - T(1), (T(y) + sy) / T(R) * T(2) - T(1));
}

// The pointwise counterpart of texel_solid_angle: the Jacobian at uv times the texel's uv area,
// J(uv) (2/R)^2. Its mean over a uniform point of the square is the square's exact solid angle,
// which is what makes a VPL of this flux at a uniformly jittered point unbiased (docs/math.md
// section 11). No validity test: the caller has chosen uv inside a valid texel.
template <class T>
inline T texel_point_solid_angle(vec2<T> uv, int R) {
  const T h = T(2) / T(R);
  return paraboloid_jacobian(uv) * h * h;
}

// uv -> the texel containing it, clamped into [0, R-1]^2 (uv = 1 belongs to the last texel).
// The clamp happens in floating point before the conversion to int, so uv far outside the map,
// Inf or NaN (-> texel 0) never reach an out-of-range float-to-int conversion (UB in C++).
template <class T>
inline int texel_coord_from_u(T u, int R) {
  T t = (u + T(1)) * T(0.5) * T(R);
  if (!(t >= T(0))) t = T(0);
  if (t > T(R - 1)) t = T(R - 1);
  return int(t);  // t >= 0: truncation is floor
}

template <class T>
inline ivec2 texel_from_uv(vec2<T> uv, int R) {
  return ivec2(texel_coord_from_u(uv.x, R), texel_coord_from_u(uv.y, R));
}

// A texel is valid when its centre lies in the closed unit disk (about pi/4 of the map).
// Decided in exact integer arithmetic: with a = 2x + 1 - R, b = 2y + 1 - R the centre is
// (a, b) / R, so r2 <= 1 <=> a^2 + b^2 <= R^2. No centre lies exactly on the rim (a and b have
// the parity of R + 1, so a^2 + b^2 != R^2), but one can lie within 1/R^2 of it: below float
// resolution for R in the thousands, where a float r2 <= 1 test misclassifies some texels (see
// the hard-case test). The integer test cannot, and it is identical on CPU and GPU.
inline bool texel_is_valid(int x, int y, int R) {
  if (x < 0 || y < 0 || x >= R || y >= R) return false;
  const int a = 2 * x + 1 - R;
  const int b = 2 * y + 1 - R;
  return a * a + b * b <= R * R;
}

// The rim band (docs/math.md section 1): a texel square that the rim crosses is valid or not by
// its centre alone, so the parts of the invalid squares inside the disk (within sqrt(2)/R of the
// rim) are directions the light sees that no valid texel contains. Each is OWNED by one valid
// texel instead: the one containing uv pulled toward the pole by one texel width, uv (1 - 2/R).
// That texel is valid: |uv (1 - 2/R)| <= 1 - 2/R and a texel's centre lies within half a diagonal,
// sqrt(2)/R, of any of its points, so the centre has r <= 1 - (2 - sqrt(2))/R (a margin of
// 0.59/R, far above float rounding for every R allowed). It is an 8-neighbour of the texel uv lies
// in (the pull moves uv by at most 2/R, one texel width). Owning is a function of uv, so every
// direction of the disk has exactly one owner: the valid texels' domains still tile the disk, no
// VPL is counted twice, and the lookup (dprsm_view::texel_of_direction) never files a direction
// the light sees under a texel that carries no VPL. uv must lie in the closed unit disk (as
// paraboloid_from_direction's does); uv inside a valid texel is owned by that texel.
template <class T>
inline ivec2 texel_owner_from_uv(vec2<T> uv, int R) {
  const ivec2 xy = texel_from_uv(uv, R);
  if (texel_is_valid(xy.x, xy.y, R)) return xy;
  return texel_from_uv(uv * (T(1) - T(2) / T(R)), R);
}

// A rim texel: valid, with an invalid 8-neighbour inside the grid. Only rim texels own parts of
// other squares (the owner of a band part is an 8-neighbour of the invalid texel holding it); the
// other valid texels own exactly their squares (inside the disk).
inline bool texel_is_rim(int x, int y, int R) {
  if (!texel_is_valid(x, y, R)) return false;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int nx = x + dx, ny = y + dy;
      if (nx >= 0 && ny >= 0 && nx < R && ny < R && !texel_is_valid(nx, ny, R)) return true;
    }
  return false;
}

// The rectangle of texels a texel's patch is drawn over (dprsm_patch.hpp): columns x0 .. x0 + nx - 1,
// rows y0 .. y0 + ny - 1.
struct texel_block {
  int x0, y0, nx, ny;
};

// The texel itself off the rim. A rim texel (x, y) owns band parts only on its outer side: with
// k = 1 - 2/R, a band point uv lies in texel I and uv k in the owner (x, y), and per axis
// u - u k = 2u/R is at most one texel width toward u's sign, so I.x is x or x + sign(u); u k lies
// in column x, whose sign is that of a = 2x + 1 - R unless a = 0 (the middle column of an odd R,
// which straddles u = 0). So the block is 2 x 2 on the outer side (2 x 3 or 3 x 3 on an axis of an
// odd R): every band part the texel owns lies in it.
inline texel_block texel_patch_block(int x, int y, int R) {
  texel_block b{x, y, 1, 1};
  if (!texel_is_rim(x, y, R)) return b;
  const int a = 2 * x + 1 - R, c = 2 * y + 1 - R;
  if (a <= 0) b.x0 -= 1;
  if (c <= 0) b.y0 -= 1;
  b.nx = a == 0 ? 3 : 2;
  b.ny = c == 0 ? 3 : 2;
  return b;
}

// A point of block b chosen by xi in [0, 1]^2 (clamped as in texel_point_uv). For the block of
// one texel it is texel_point_uv bit for bit (x + 1 * sx rounds as x + sx). Uniform xi: density
// (R/2)^2 / (nx ny) per unit uv area.
template <class T>
inline vec2<T> texel_block_point_uv(texel_block b, int R, vec2<T> xi) {
  const T sx = !(xi.x >= T(0)) ? T(0) : (xi.x > T(1) ? T(1) : xi.x);
  const T sy = !(xi.y >= T(0)) ? T(0) : (xi.y > T(1) ? T(1) : xi.y);
  return vec2<T>((T(b.x0) + T(b.nx) * sx) / T(R) * T(2) - T(1), (T(b.y0) + T(b.ny) * sy) / T(R) * T(2) - T(1));
}

// J(uv) (2 nx / R) (2 ny / R): the pointwise solid angle of a point drawn uniformly over block b,
// texel_point_solid_angle for the block of one texel.
template <class T>
inline T texel_block_point_solid_angle(vec2<T> uv, texel_block b, int R) {
  const T h = T(2) / T(R);
  return paraboloid_jacobian(uv) * (h * T(b.nx)) * (h * T(b.ny));
}

// Solid angle of a valid texel: the Jacobian 4 / (1 + r2)^2 at the centre times the texel's
// uv area (2/R)^2 (midpoint rule; relative error O(R^-2), largest next to the pole: ~3e-4 at
// R = 64, 2e-5 at R = 256). 0 for invalid texels, so they carry no weight and can never be
// sampled.
template <class T>
inline T texel_solid_angle(int x, int y, int R) {
  if (!texel_is_valid(x, y, R)) return T(0);
  const T h = T(2) / T(R);
  return paraboloid_jacobian(texel_center_uv<T>(x, y, R)) * h * h;
}

}  // namespace vplkit
