// SPDX-License-Identifier: MIT
// vplkit GLSL pack: 3D DDA ray marching through the voxel grid (Amanatides & Woo 1987; mirrors
// include/vplkit/visibility/dda.hpp, T = float, statement for statement).
//
// Ray: origin + t * d, d = dir normalised by vplkit_dda_unit_direction, so t and t_max are world
// distances. Returns the first occupied voxel whose closed box the segment [0, t_max] meets inside
// the grid, with its ENTRY distance max(0, t where the ray enters the box); a voxel entered exactly
// at t_max counts. The conventions (see docs/api/visibility.md, "Algorithm"):
//  1. direction: a non-finite component or a largest |component| below FLT_MIN means zero length
//     (no hit); else divide by the largest |component|, normalise, and set components below
//     FLT_MIN to 0. A non-finite origin or t_max < 0 / NaN: no hit.
//  2. clip [0, t_max] by slabs against the closed grid box; an axis with d == 0 only checks
//     bounds_min <= origin <= bounds_max; remember the FIRST axis whose slab entry is the largest.
//  3. entry voxel: floor((p - bounds_min) / voxel_size) at p = origin + t_enter * d, clamped into
//     the grid; on the entry axis exactly 0 or n - 1.
//  4. t_next[a] = (bounds_min[a] + k * size[a] - origin[a]) / d[a] for the next plane k,
//     recomputed from the plane after every step; an axis with d == 0 has step 0 and t_next =
//     FLT_MAX (never Inf or NaN).
//  5. at most nx + ny + nz iterations: test the voxel; step the axis with the smallest t_next,
//     x before y before z on ties (<=); stop on step 0, t_next > t_max, or leaving the grid;
//     t = max(t, t_next).
//
// ACCESSOR: uint vplkit_load_voxel_word(uint word_index) (see voxel_grid.glsl).
//
// Parity: every value that decides a voxel index is `precise` and evaluated in the C++ order. Where
// division and sqrt are correctly rounded (llvmpipe; measured) the GPU reproduces the C++ float
// march bit for bit, t included. GPUs with approximate division/sqrt (GLSL allows 2.5 ulp) agree on
// t to a few ulp and on the voxel except at near-ties: rays passing within a few ulp of a voxel
// edge or corner, or with t_max within a few ulp of a plane crossing.
#ifndef VPLKIT_VISIBILITY_DDA_GLSL
#define VPLKIT_VISIBILITY_DDA_GLSL

#include "vplkit/core/constants.glsl"
#include "vplkit/visibility/voxel_grid.glsl"

struct vplkit_dda_hit {
  bool hit;     // an occupied voxel was found within [0, t_max]
  float t;      // its entry distance (0 on a miss)
  ivec3 voxel;  // its index ((-1, -1, -1) on a miss)
};

struct vplkit_dda_trace_result {
  bool hit;
  float t;      // entry distance of the first occupied voxel (0 on a miss)
  ivec3 voxel;  // its index ((-1, -1, -1) on a miss)
  vec3 point;   // origin + t * unit direction: where the ray enters that voxel (origin on a miss)
};

// The C++ default t_max (+infinity).
float vplkit_dda_infinity() {
  return uintBitsToFloat(0x7F800000u);
}

// Unit direction for the DDA in `unit`, or false (and unit = 0) for a zero / non-finite direction.
bool vplkit_dda_unit_direction(vec3 dir, out vec3 unit) {
  unit = vec3(0.0);
  if (!vplkit_voxel_vec3_finite(dir)) return false;
  const float tiny = vplkit_FLT_MIN;  // GPUs flush denormals, so the CPU uses FLT_MIN too
  float m = max(abs(dir.x), max(abs(dir.y), abs(dir.z)));
  if (!(m >= tiny)) return false;
  // Division is bounded only for divisors in [2^-126, 2^126] (GLSL 4.7.1): scale by 1/4 (exact)
  // above that, as the C++ does (NVIDIA turned a direction of FLT_MAX into NaN without it).
  precise vec3 s = dir;
  precise float ms = m;
  if (ms > 8.5070591730234616e37) {  // 2^126
    s = s * 0.25;
    ms = ms * 0.25;
  }
  precise vec3 d = s / ms;
  precise float len = sqrt(vplkit_voxel_dot(d, d));  // dot(d, d) in [1, 3]: no under/overflow
  d = d / len;
  for (int a = 0; a < 3; ++a)
    if (abs(d[a]) < tiny) d[a] = 0.0;
  unit = d;
  return true;
}

// The march one voxel at a time (mirrors dda_walk, dda_walk_begin, dda_walk_next, dda_walk_exit):
// vplkit_dda_first_hit is begin, then up to nx + ny + nz times: test the voxel, advance.
struct vplkit_dda_walk {
  bool running;    // false: the ray misses the grid (after begin) or has left it / passed t_max
  vec3 origin;
  vec3 d;          // unit direction
  float t_max;
  float t;         // entry distance of the current voxel
  ivec3 voxel;
  ivec3 step_dir;  // the C++ `step` (a GLSL built-in's name)
  vec3 t_next;
  vec3 size;       // vplkit_voxel_size(g)
};

float vplkit_dda_walk_exit(vplkit_dda_walk w) {
  float m = w.t_next.x < w.t_next.y ? (w.t_next.x < w.t_next.z ? w.t_next.x : w.t_next.z)
                                    : (w.t_next.y < w.t_next.z ? w.t_next.y : w.t_next.z);
  return m < w.t_max ? m : w.t_max;
}

vplkit_dda_walk vplkit_dda_walk_begin(vplkit_voxel_grid g, vec3 origin, vec3 dir, float t_max) {
  vplkit_dda_walk w = vplkit_dda_walk(false, origin, vec3(0.0), t_max, 0.0, ivec3(-1), ivec3(0), vec3(0.0),
                                      vec3(0.0));
  vec3 d = vec3(0.0);
  if (!vplkit_dda_unit_direction(dir, d)) return w;
  // t_max NaN tested on the bits: a driver that assumes no NaN may fold !(t_max >= 0) into
  // t_max < 0 (NVIDIA 580 marched a ray with t_max = NaN).
  bool t_max_nan = vplkit_is_nan(t_max);
  if (!vplkit_voxel_vec3_finite(origin) || t_max_nan || !(t_max >= 0.0)) return w;
  vec3 size = vplkit_voxel_size(g);

  // Clip [0, t_max] to the closed grid box; remember which face the ray enters through.
  float t_enter = 0.0;
  float t_exit = t_max;
  int enter_axis = -1;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      if (origin[a] < g.bounds_min[a] || origin[a] > g.bounds_max[a]) return w;
    } else {
      precise float ta = (g.bounds_min[a] - origin[a]) / d[a];
      precise float tb = (g.bounds_max[a] - origin[a]) / d[a];
      if (ta > tb) {
        float s = ta;
        ta = tb;
        tb = s;
      }
      if (ta > t_enter) {
        t_enter = ta;
        enter_axis = a;
      }
      t_exit = tb < t_exit ? tb : t_exit;
    }
  }
  if (!(t_enter <= t_exit) || !vplkit_voxel_isfinite(t_enter)) return w;

  // Entry voxel and the distance to the next plane crossing on each axis.
  precise vec3 p = origin + t_enter * d;
  ivec3 v = ivec3(0);
  ivec3 step_dir = ivec3(0);
  vec3 t_next = vec3(0.0);
  for (int a = 0; a < 3; ++a) {
    precise float c = (p[a] - g.bounds_min[a]) / size[a];
    int i = vplkit_voxel_floor_to_int(c);
    v[a] = i < 0 ? 0 : (i > g.resolution[a] - 1 ? g.resolution[a] - 1 : i);
    if (a == enter_axis) v[a] = d[a] > 0.0 ? 0 : g.resolution[a] - 1;
    if (d[a] > 0.0) {
      step_dir[a] = 1;
      precise float tn = (g.bounds_min[a] + float(v[a] + 1) * size[a] - origin[a]) / d[a];
      t_next[a] = tn;
    } else if (d[a] < 0.0) {
      step_dir[a] = -1;
      precise float tn = (g.bounds_min[a] + float(v[a]) * size[a] - origin[a]) / d[a];
      t_next[a] = tn;
    } else {
      step_dir[a] = 0;
      t_next[a] = vplkit_FLT_MAX;
    }
  }
  w.running = true;
  w.d = d;
  w.t = t_enter;
  w.voxel = v;
  w.step_dir = step_dir;
  w.t_next = t_next;
  w.size = size;
  return w;
}

bool vplkit_dda_walk_next(vplkit_voxel_grid g, inout vplkit_dda_walk w) {
  int a = (w.t_next.x <= w.t_next.y && w.t_next.x <= w.t_next.z) ? 0 : (w.t_next.y <= w.t_next.z ? 1 : 2);
  if (w.step_dir[a] == 0 || w.t_next[a] > w.t_max) {
    w.running = false;
    return false;
  }
  w.voxel[a] += w.step_dir[a];
  if (w.voxel[a] < 0 || w.voxel[a] >= g.resolution[a]) {
    w.running = false;
    return false;
  }
  w.t = w.t_next[a] > w.t ? w.t_next[a] : w.t;
  precise float tn =
      (g.bounds_min[a] + float(w.step_dir[a] > 0 ? w.voxel[a] + 1 : w.voxel[a]) * w.size[a] - w.origin[a]) / w.d[a];
  w.t_next[a] = tn;
  return true;
}

int vplkit_dda_max_iterations(ivec3 resolution) {
  return resolution.x + resolution.y + resolution.z;
}

vplkit_dda_hit vplkit_dda_first_hit(vplkit_voxel_grid g, vec3 origin, vec3 dir, float t_max) {
  vplkit_dda_walk w = vplkit_dda_walk_begin(g, origin, dir, t_max);
  int max_iterations = vplkit_dda_max_iterations(g.resolution);
  for (int it = 0; w.running && it < max_iterations; ++it) {
    if (vplkit_voxel_test(g, w.voxel)) return vplkit_dda_hit(true, w.t, w.voxel);
    vplkit_dda_walk_next(g, w);
  }
  return vplkit_dda_hit(false, 0.0, ivec3(-1));
}

// t_max = +infinity (the C++ default argument).
vplkit_dda_hit vplkit_dda_first_hit(vplkit_voxel_grid g, vec3 origin, vec3 dir) {
  return vplkit_dda_first_hit(g, origin, dir, vplkit_dda_infinity());
}

// For the GBG gathering pass: the first occupied voxel and the point where the ray enters it
// (within one voxel diagonal of the surface that marked the voxel; see dda.hpp).
vplkit_dda_trace_result vplkit_dda_trace_hit_point(vplkit_voxel_grid g, vec3 origin, vec3 dir, float t_max) {
  vplkit_dda_hit h = vplkit_dda_first_hit(g, origin, dir, t_max);
  if (!h.hit) return vplkit_dda_trace_result(false, 0.0, h.voxel, origin);
  vec3 d = vec3(0.0);
  vplkit_dda_unit_direction(dir, d);  // succeeds: vplkit_dda_first_hit hit
  precise vec3 point = origin + h.t * d;
  return vplkit_dda_trace_result(true, h.t, h.voxel, point);
}

vplkit_dda_trace_result vplkit_dda_trace_hit_point(vplkit_voxel_grid g, vec3 origin, vec3 dir) {
  return vplkit_dda_trace_hit_point(g, origin, dir, vplkit_dda_infinity());
}

#endif  // VPLKIT_VISIBILITY_DDA_GLSL
