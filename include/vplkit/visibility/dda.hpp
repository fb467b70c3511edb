// SPDX-License-Identifier: MIT
#pragma once
// 3D DDA ray marching through a voxel_grid_view (Amanatides & Woo, "A fast voxel traversal
// algorithm for ray tracing", Eurographics 1987).
//
// Ray: origin + t * d, where d = dir normalised (dda_unit_direction), so t and t_max are world
// distances. The march visits, in order of t, the voxels whose closed boxes the segment
// [0, t_max] meets inside the grid, and returns the first occupied one with its ENTRY distance:
// max(0, t at which the ray enters that voxel's box) -- 0 when the origin is inside an occupied
// voxel. A voxel entered exactly at t_max counts (closed interval).
// Two exceptions to "every voxel whose closed box the segment meets", both at exact ties:
// - On an axis the ray does not move along (d_a == 0) whose coordinate lies exactly on a voxel
//   plane, only the voxel above the plane (floor) is visited, the one below it on the grid's max
//   face; a ray lying in a boundary plane thus walks one layer, not both.
// - Where the ray crosses several planes at the same t (an edge or a corner), the side voxels it
//   only touches are visited in the order of the tie rule below, not all of them.
// Neither lets a ray pass a conservative shell: the voxels around the point where a ray crosses a
// surface are all marked, whichever of them the march is in.
//
// Conventions the GLSL mirror (vplkit_dda_first_hit) follows statement for statement:
// - Direction: a direction with a NaN or infinite component, or whose largest |component| is
//   below 1.17549435e-38 (FLT_MIN, the smallest normal float, also for T = double) counts as zero
//   length: GPUs flush denormals to zero. Otherwise it is scaled by its largest |component| before
//   normalising (no underflow / overflow), and components of the unit vector below FLT_MIN are set
//   to 0. A zero-length direction, a non-finite origin, or t_max < 0 / NaN give no hit.
// - Clipping: slabs against the closed grid box, t in [0, t_max]; an axis with d_a == 0 only checks
//   bounds_min_a <= origin_a <= bounds_max_a. The ray misses when t_enter > t_exit.
// - Entry voxel: floor((p - bounds_min) / voxel_size) at p = origin + t_enter * d, clamped into the
//   grid (p on the box face may round outside it); on the axis whose face the ray enters through
//   (the first axis whose slab entry is the largest, when the origin is outside) the index is set
//   exactly to the first layer, 0 or n - 1, since p there may have lost all precision (origin far
//   away).
// - Crossing distances are recomputed from the plane each step, t_next_a = (bounds_min_a +
//   k * voxel_size_a - origin_a) / d_a, not accumulated (no drift over 128+ steps); an axis with
//   d_a == 0 has t_next_a = the largest finite T and step 0, never an infinite or NaN tDelta.
// - Ties: the axis with the smallest t_next steps first, x before y before z when equal. At an
//   exact edge or corner crossing the march therefore also visits the side voxel(s) the ray only
//   touches, which is what keeps a ray from slipping diagonally between two voxels of a
//   conservative shell.
// - The loop runs at most nx + ny + nz iterations (a ray visits at most nx + ny + nz - 2 voxels).
// - The reported t is kept non-decreasing (t = max(t, t_next)) so rounding at the entry voxel
//   cannot make it go backwards.
#include <vplkit/core/normal_range.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/visibility/voxel_grid.hpp>

#include <cmath>
#include <limits>

namespace vplkit {

template <class T>
struct dda_hit {
  bool hit;     // an occupied voxel was found within [0, t_max]
  T t;          // its entry distance (0 on a miss)
  ivec3 voxel;  // its index ((-1, -1, -1) on a miss)
};

// Unit direction for the DDA in `out`, or false (and out = 0) for a zero / non-finite direction
// (see the header).
template <class T>
inline bool dda_unit_direction(vec3<T> dir, vec3<T>& out) {
  using std::isfinite;  // or a float-like T's own (the tests' GPU model, gpu_model_float.hpp)
  out = vec3<T>(T(0));
  if (!isfinite(dir.x) || !isfinite(dir.y) || !isfinite(dir.z)) return false;
  const T tiny = T(1.17549435e-38f);  // FLT_MIN, for T = double too (parity with the GPU)
  const T ax = detail::abs_of(dir.x), ay = detail::abs_of(dir.y), az = detail::abs_of(dir.z);
  const T myz = ay < az ? az : ay;
  const T m = ax < myz ? myz : ax;  // fmax of the finite |components|
  if (!(m >= tiny)) return false;
  // GLSL bounds division only for divisors in [2^-126, 2^126] (4.7.1): beyond, a GPU may compute
  // x / m as x * (1 / m) with 1 / m flushed to 0 (NVIDIA: a direction of FLT_MAX became NaN).
  // Scaling by 1/4 is exact and brings m below 2^126; it changes nothing where m <= 2^126.
  vec3<T> s = dir;
  T ms = m;
  if (ms > T(8.5070591730234616e37)) {  // 2^126
    s = s * T(0.25);
    ms = ms * T(0.25);
  }
  vec3<T> d = s / ms;
  d = d / detail::sqrt_of(glm::dot(d, d));  // dot(d, d) in [1, 3]: no underflow, no overflow
  for (int a = 0; a < 3; ++a)
    if (detail::abs_of(d[a]) < tiny) d[a] = T(0);
  out = d;
  return true;
}

// ---- The march, one voxel at a time ---------------------------------------------------------
// dda_walk_begin / dda_walk_next expose the march that dda_first_hit runs, for callers that must
// look at every voxel the ray meets (the triangle voxel queries, triangle_voxel_query.hpp), not only at
// the first occupied one. dda_first_hit is exactly: begin; then up to nx + ny + nz times, test the
// current voxel and advance.
template <class T>
struct dda_walk {
  bool running;    // false: the ray misses the grid (after begin) or has left it / passed t_max
  vec3<T> origin;  // as given
  vec3<T> d;       // unit direction (dda_unit_direction)
  T t_max;
  T t;             // entry distance of the current voxel (non-decreasing)
  ivec3 voxel;     // the current voxel
  ivec3 step;      // -1, 0, +1 per axis
  vec3<T> t_next;  // distance to the next plane crossing per axis (largest finite T when step 0)
  vec3<T> size;    // voxel_size(g)
};

// Distance at which the walk leaves its current voxel: the smallest t_next, at most t_max.
template <class T>
inline T dda_walk_exit(const dda_walk<T>& w) {
  const T m = w.t_next.x < w.t_next.y ? (w.t_next.x < w.t_next.z ? w.t_next.x : w.t_next.z)
                                      : (w.t_next.y < w.t_next.z ? w.t_next.y : w.t_next.z);
  return m < w.t_max ? m : w.t_max;
}

// Steps 1-4 of the header: direction, clipping, entry voxel, first crossings.
template <class T>
inline dda_walk<T> dda_walk_begin(const voxel_grid_view<T>& g, vec3<T> origin, vec3<T> dir,
                                  T t_max = std::numeric_limits<T>::infinity()) {
  dda_walk<T> w{false, origin, vec3<T>(T(0)), t_max, T(0), ivec3(-1), ivec3(0), vec3<T>(T(0)), vec3<T>(T(0))};
  vec3<T> d(T(0));
  if (!dda_unit_direction(dir, d)) return w;
  if (!std::isfinite(origin.x) || !std::isfinite(origin.y) || !std::isfinite(origin.z) || !(t_max >= T(0)))
    return w;
  const vec3<T> size = voxel_size(g);

  // Clip [0, t_max] to the closed grid box; remember which face the ray enters through.
  T t_enter = T(0), t_exit = t_max;
  int enter_axis = -1;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == T(0)) {
      if (origin[a] < g.bounds_min[a] || origin[a] > g.bounds_max[a]) return w;
    } else {
      T ta = (g.bounds_min[a] - origin[a]) / d[a];
      T tb = (g.bounds_max[a] - origin[a]) / d[a];
      if (ta > tb) {
        const T s = ta;
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
  if (!(t_enter <= t_exit) || !std::isfinite(t_enter)) return w;

  // Entry voxel and the distance to the next plane crossing on each axis.
  const vec3<T> p = origin + t_enter * d;
  ivec3 v(0);
  ivec3 step(0);
  vec3<T> t_next(T(0));
  for (int a = 0; a < 3; ++a) {
    const int i = voxel_floor_to_int((p[a] - g.bounds_min[a]) / size[a]);
    v[a] = i < 0 ? 0 : (i > g.resolution[a] - 1 ? g.resolution[a] - 1 : i);
    if (a == enter_axis) v[a] = d[a] > T(0) ? 0 : g.resolution[a] - 1;
    if (d[a] > T(0)) {
      step[a] = 1;
      t_next[a] = (g.bounds_min[a] + T(v[a] + 1) * size[a] - origin[a]) / d[a];
    } else if (d[a] < T(0)) {
      step[a] = -1;
      t_next[a] = (g.bounds_min[a] + T(v[a]) * size[a] - origin[a]) / d[a];
    } else {
      step[a] = 0;
      t_next[a] = std::numeric_limits<T>::max();
    }
  }
  w.running = true;
  w.d = d;
  w.t = t_enter;
  w.voxel = v;
  w.step = step;
  w.t_next = t_next;
  w.size = size;
  return w;
}

// Step 5 of the header, after the voxel test: moves to the next voxel. Returns false (and clears
// `running`) when the walk ends: a step of 0, the next crossing beyond t_max, or leaving the grid.
template <class T>
inline bool dda_walk_next(const voxel_grid_view<T>& g, dda_walk<T>& w) {
  const int a = (w.t_next.x <= w.t_next.y && w.t_next.x <= w.t_next.z) ? 0 : (w.t_next.y <= w.t_next.z ? 1 : 2);
  if (w.step[a] == 0 || w.t_next[a] > w.t_max) {
    w.running = false;
    return false;
  }
  w.voxel[a] += w.step[a];
  if (w.voxel[a] < 0 || w.voxel[a] >= g.resolution[a]) {
    w.running = false;
    return false;
  }
  w.t = w.t_next[a] > w.t ? w.t_next[a] : w.t;
  w.t_next[a] = (g.bounds_min[a] + T(w.step[a] > 0 ? w.voxel[a] + 1 : w.voxel[a]) * w.size[a] - w.origin[a]) / w.d[a];
  return true;
}

// Iteration bound of a walk: a ray visits at most nx + ny + nz - 2 voxels.
inline int dda_max_iterations(ivec3 resolution) { return resolution.x + resolution.y + resolution.z; }

template <class T>
inline dda_hit<T> dda_first_hit(const voxel_grid_view<T>& g, vec3<T> origin, vec3<T> dir,
                                T t_max = std::numeric_limits<T>::infinity()) {
  dda_walk<T> w = dda_walk_begin(g, origin, dir, t_max);
  const int max_iterations = dda_max_iterations(g.resolution);
  for (int it = 0; w.running && it < max_iterations; ++it) {
    if (voxel_test(g, w.voxel)) return dda_hit<T>{true, w.t, w.voxel};
    dda_walk_next(g, w);
  }
  return dda_hit<T>{false, T(0), ivec3(-1)};
}

template <class T>
struct dda_trace_result {
  bool hit;
  T t;           // entry distance of the first occupied voxel (0 on a miss)
  ivec3 voxel;   // its index ((-1, -1, -1) on a miss)
  vec3<T> point; // origin + t * normalize(dir): where the ray enters that voxel (origin on a miss)
};

// For the GBG gathering pass: the first occupied voxel along the ray and the point where the ray
// enters it. Accuracy: one voxel. The point lies on the boundary of (or, at t = 0, inside) the
// first occupied voxel; the surface that marked that voxel lies somewhere in the same closed box,
// so the point is within one voxel diagonal of that surface. Because the voxelisation is
// conservative, the ray itself may pass through the voxel without meeting the surface: the point
// is then up to a voxel diagonal from any true intersection, and a DPRSM depth test against it
// needs a tolerance of about a voxel diagonal (sqrt(3) * voxel_length).
template <class T>
inline dda_trace_result<T> dda_trace_hit_point(const voxel_grid_view<T>& g, vec3<T> origin, vec3<T> dir,
                                               T t_max = std::numeric_limits<T>::infinity()) {
  const dda_hit<T> h = dda_first_hit(g, origin, dir, t_max);
  if (!h.hit) return dda_trace_result<T>{false, T(0), h.voxel, origin};
  vec3<T> d(T(0));
  dda_unit_direction(dir, d);  // succeeds: dda_first_hit hit
  return dda_trace_result<T>{true, h.t, h.voxel, origin + h.t * d};
}

}  // namespace vplkit
