// SPDX-License-Identifier: MIT
// vplkit GLSL pack: empty-space skipping for the voxel march (mirrors
// include/vplkit/visibility/voxel_bricks.hpp, T = float, statement for statement): the brick level
// of the occupancy (a brick of vplkit_voxel_brick_edge^3 voxels is occupied when any voxel is) and
// the walk's exit from an empty brick in one move.
//
// Layout (identical to the C++ voxel_brick_words, so one buffer serves both sides):
//   brick resolution = ceil(resolution / 4) per axis; brick of voxel v = v / 4; flat index
//   j = bx + by * rx + bz * rx * ry; word j >> 5, bit j & 31.
//
// Compiled in only with #define VPLKIT_VOXEL_BRICKS before the first include; the shader then
// defines the ACCESSOR
//   uint vplkit_load_voxel_brick_word(uint word_index);
// e.g. layout(std430, binding = 14) readonly buffer Bricks { uint bricks[]; };
//      uint vplkit_load_voxel_brick_word(uint i) { return bricks[i]; }
// and the triangle voxel queries (triangle_voxel_query.glsl) jump over empty bricks. Without it
// they step through them; the answers are the same either way (voxel_bricks.hpp, EXACTNESS).
//
// Parity: the crossing distances are dda.glsl's expression, `precise`; with the same rounding the
// walk's state after a jump is the state after the steps it replaces, bit for bit.
#ifndef VPLKIT_VISIBILITY_VOXEL_BRICKS_GLSL
#define VPLKIT_VISIBILITY_VOXEL_BRICKS_GLSL

#include "vplkit/core/constants.glsl"
#include "vplkit/visibility/dda.glsl"
#include "vplkit/visibility/voxel_grid.glsl"

const int vplkit_voxel_brick_edge = 4;

ivec3 vplkit_voxel_brick_resolution(ivec3 resolution) {
  return (resolution + ivec3(vplkit_voxel_brick_edge - 1)) / vplkit_voxel_brick_edge;
}

// The walk's crossing distance of plane k on axis a (vplkit_dda_walk_begin's and
// vplkit_dda_walk_next's expression).
float vplkit_dda_walk_plane_t(vplkit_voxel_grid g, vplkit_dda_walk w, int a, int k) {
  precise float t = (g.bounds_min[a] + float(k) * w.size[a] - w.origin[a]) / w.d[a];
  return t;
}

bool vplkit_dda_crosses_before(float t, int axis, float t_exit, int axis_exit) {
  return t < t_exit || (t == t_exit && axis < axis_exit);
}

// Moves a running walk out of the brick of its current voxel, which the caller found empty.
// Returns w.running.
bool vplkit_dda_walk_leave_brick(vplkit_voxel_grid g, inout vplkit_dda_walk w) {
  vec3 t_exit = vec3(vplkit_FLT_MAX);
  ivec3 exit_plane = ivec3(0);
  for (int a = 0; a < 3; ++a) {
    if (w.step_dir[a] == 0) continue;
    int lo = (w.voxel[a] / vplkit_voxel_brick_edge) * vplkit_voxel_brick_edge;
    int hi = lo + vplkit_voxel_brick_edge < g.resolution[a] ? lo + vplkit_voxel_brick_edge : g.resolution[a];
    int k = w.step_dir[a] > 0 ? hi : lo;
    int next = w.step_dir[a] > 0 ? w.voxel[a] + 1 : w.voxel[a];
    exit_plane[a] = k;
    t_exit[a] = k == next ? w.t_next[a] : vplkit_dda_walk_plane_t(g, w, a, k);
  }
  int e = (t_exit.x <= t_exit.y && t_exit.x <= t_exit.z) ? 0 : (t_exit.y <= t_exit.z ? 1 : 2);
  if (w.step_dir[e] == 0 || t_exit[e] > w.t_max) {
    w.running = false;
    return false;
  }
  for (int a = 0; a < 3; ++a) {
    if (a == e || w.step_dir[a] == 0) continue;
    for (int n = 1; n < vplkit_voxel_brick_edge && vplkit_dda_crosses_before(w.t_next[a], a, t_exit[e], e); ++n) {
      w.voxel[a] += w.step_dir[a];
      w.t_next[a] = vplkit_dda_walk_plane_t(g, w, a, w.step_dir[a] > 0 ? w.voxel[a] + 1 : w.voxel[a]);
    }
  }
  w.voxel[e] = w.step_dir[e] > 0 ? exit_plane[e] : exit_plane[e] - 1;
  if (w.voxel[e] < 0 || w.voxel[e] >= g.resolution[e]) {
    w.running = false;
    return false;
  }
  w.t = t_exit[e] > w.t ? t_exit[e] : w.t;
  w.t_next[e] = vplkit_dda_walk_plane_t(g, w, e, w.step_dir[e] > 0 ? w.voxel[e] + 1 : w.voxel[e]);
  return true;
}

#ifdef VPLKIT_VOXEL_BRICKS
uint vplkit_load_voxel_brick_word(uint word_index);

// Is the brick of voxel v (inside the grid) occupied?
bool vplkit_voxel_brick_occupied(ivec3 resolution, ivec3 v) {
  uint j = vplkit_voxel_flat_index(vplkit_voxel_brick_resolution(resolution), v / vplkit_voxel_brick_edge);
  return ((vplkit_load_voxel_brick_word(j >> 5u) >> (j & 31u)) & 1u) != 0u;
}
#endif

#endif  // VPLKIT_VISIBILITY_VOXEL_BRICKS_GLSL
