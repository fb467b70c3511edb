// SPDX-License-Identifier: MIT
// vplkit GLSL pack: the R x R texel grid of each paraboloid face over uv in [-1,1]^2 (docs/math.md
// section 1). Mirrors include/vplkit/paraboloid/texel_grid.hpp (T = float) line for line.
//
// Layout: x runs along u, y along v; texel (x, y) covers u in [-1 + 2x/R, -1 + 2(x+1)/R) and
// likewise for v; its centre is ((x + 0.5) / R * 2 - 1, (y + 0.5) / R * 2 - 1). The flat index
// over both faces is  index = face * R * R + y * R + x  (face 0 = front, 1 = back): a DPRSM is
// 2 R^2 texels, front face first, each face row-major. 1 <= R <= vplkit_paraboloid_max_resolution
// keeps every index and the integer validity test in int. Indices passed in must be >= 0 (GLSL
// leaves % of negative operands undefined).
#ifndef VPLKIT_PARABOLOID_TEXEL_GRID_GLSL
#define VPLKIT_PARABOLOID_TEXEL_GRID_GLSL

#include "vplkit/paraboloid/paraboloid.glsl"

// 2 * 16384^2 = 2^29 texels: the index and the integer validity test below stay in int.
const int vplkit_paraboloid_max_resolution = 16384;

int vplkit_texel_count(int R) { return 2 * R * R; }

int vplkit_texel_index(int face, int x, int y, int R) { return face * R * R + y * R + x; }

int vplkit_texel_face(int index, int R) { return index / (R * R); }

// (x, y) of a flat index within its face.
ivec2 vplkit_texel_coords(int index, int R) {
  int in_face = index % (R * R);
  return ivec2(in_face % R, in_face / R);
}

vec2 vplkit_texel_center_uv(int x, int y, int R) {
  return vec2((float(x) + 0.5) / float(R) * 2.0 - 1.0, (float(y) + 0.5) / float(R) * 2.0 - 1.0);
}

// A point of texel (x, y) chosen by xi in [0, 1]^2, clamped there (NaN -> 0 on the CPU); the
// centre for xi = (0.5, 0.5), bit for bit vplkit_texel_center_uv.
vec2 vplkit_texel_point_uv(int x, int y, int R, vec2 xi) {
  float sx = !(xi.x >= 0.0) ? 0.0 : (xi.x > 1.0 ? 1.0 : xi.x);
  float sy = !(xi.y >= 0.0) ? 0.0 : (xi.y > 1.0 ? 1.0 : xi.y);
  return vec2((float(x) + sx) / float(R) * 2.0 - 1.0, (float(y) + sy) / float(R) * 2.0 - 1.0);
}

// J(uv) (2/R)^2: the pointwise counterpart of vplkit_texel_solid_angle (no validity test).
float vplkit_texel_point_solid_angle(vec2 uv, int R) {
  float h = 2.0 / float(R);
  return vplkit_paraboloid_jacobian(uv) * h * h;
}

// uv -> the texel containing it, clamped into [0, R-1] (u = 1 belongs to the last texel). The
// clamp happens in float before int(): int() of an out-of-range or NaN float is undefined in GLSL.
// Infinite u clamps like the CPU; NaN gives texel 0 on the CPU (GPU compilers may assume no NaN).
int vplkit_texel_coord_from_u(float u, int R) {
  float t = (u + 1.0) * 0.5 * float(R);
  if (!(t >= 0.0)) t = 0.0;
  if (t > float(R - 1)) t = float(R - 1);
  return int(t);  // t >= 0: truncation is floor
}

ivec2 vplkit_texel_from_uv(vec2 uv, int R) {
  return ivec2(vplkit_texel_coord_from_u(uv.x, R), vplkit_texel_coord_from_u(uv.y, R));
}

// A texel is valid when its centre lies in the closed unit disk (about pi/4 of the map). Decided
// in exact integer arithmetic, identical on CPU and GPU: with a = 2x + 1 - R, b = 2y + 1 - R the
// centre is (a, b) / R, so r2 <= 1 <=> a^2 + b^2 <= R^2 (a float r2 test misclassifies texels
// within 1/R^2 of the rim for R in the thousands).
bool vplkit_texel_is_valid(int x, int y, int R) {
  if (x < 0 || y < 0 || x >= R || y >= R) return false;
  int a = 2 * x + 1 - R;
  int b = 2 * y + 1 - R;
  return a * a + b * b <= R * R;
}

// The rim band (texel_grid.hpp, docs/math.md section 1): the parts of invalid rim squares inside
// the disk are owned by the valid texel containing uv (1 - 2/R), an 8-neighbour whose centre lies
// at r <= 1 - (2 - sqrt(2))/R. Every uv of the closed disk has exactly one owner, always valid.
ivec2 vplkit_texel_owner_from_uv(vec2 uv, int R) {
  ivec2 xy = vplkit_texel_from_uv(uv, R);
  if (vplkit_texel_is_valid(xy.x, xy.y, R)) return xy;
  return vplkit_texel_from_uv(uv * (1.0 - 2.0 / float(R)), R);
}

// A rim texel: valid, with an invalid 8-neighbour inside the grid (only these own band parts).
bool vplkit_texel_is_rim(int x, int y, int R) {
  if (!vplkit_texel_is_valid(x, y, R)) return false;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      int nx = x + dx, ny = y + dy;
      if (nx >= 0 && ny >= 0 && nx < R && ny < R && !vplkit_texel_is_valid(nx, ny, R)) return true;
    }
  return false;
}

// The rectangle of texels a texel's patch is drawn over: columns x0 .. x0 + nx - 1, rows
// y0 .. y0 + ny - 1.
struct vplkit_texel_block {
  int x0;
  int y0;
  int nx;
  int ny;
};

// The texel itself off the rim; for a rim texel the 2 x 2 block on its outer side (the side of
// a = 2x + 1 - R, both sides where a = 0), which holds every band part it owns (texel_grid.hpp).
vplkit_texel_block vplkit_texel_patch_block(int x, int y, int R) {
  vplkit_texel_block b = vplkit_texel_block(x, y, 1, 1);
  if (!vplkit_texel_is_rim(x, y, R)) return b;
  int a = 2 * x + 1 - R, c = 2 * y + 1 - R;
  if (a <= 0) b.x0 -= 1;
  if (c <= 0) b.y0 -= 1;
  b.nx = a == 0 ? 3 : 2;
  b.ny = c == 0 ? 3 : 2;
  return b;
}

// A point of block b chosen by xi in [0, 1]^2 (clamped); vplkit_texel_point_uv bit for bit for the
// block of one texel.
vec2 vplkit_texel_block_point_uv(vplkit_texel_block b, int R, vec2 xi) {
  float sx = !(xi.x >= 0.0) ? 0.0 : (xi.x > 1.0 ? 1.0 : xi.x);
  float sy = !(xi.y >= 0.0) ? 0.0 : (xi.y > 1.0 ? 1.0 : xi.y);
  return vec2((float(b.x0) + float(b.nx) * sx) / float(R) * 2.0 - 1.0,
              (float(b.y0) + float(b.ny) * sy) / float(R) * 2.0 - 1.0);
}

// J(uv) (2 nx / R) (2 ny / R): the pointwise solid angle of a point drawn uniformly over block b.
float vplkit_texel_block_point_solid_angle(vec2 uv, vplkit_texel_block b, int R) {
  float h = 2.0 / float(R);
  return vplkit_paraboloid_jacobian(uv) * (h * float(b.nx)) * (h * float(b.ny));
}

// Solid angle of a valid texel: the Jacobian at the centre times the uv area (2/R)^2 (midpoint
// rule). 0 for invalid texels, so they carry no weight and can never be sampled.
float vplkit_texel_solid_angle(int x, int y, int R) {
  if (!vplkit_texel_is_valid(x, y, R)) return 0.0;
  float h = 2.0 / float(R);
  return vplkit_paraboloid_jacobian(vplkit_texel_center_uv(x, y, R)) * h * h;
}

#endif  // VPLKIT_PARABOLOID_TEXEL_GRID_GLSL
