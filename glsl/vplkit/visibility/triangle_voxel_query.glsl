// SPDX-License-Identifier: MIT
// vplkit GLSL pack: visibility and first hits decided by the triangles of a triangle voxel grid
// (mirrors include/vplkit/visibility/triangle_voxel_query.hpp, T = float, statement for statement).
//
//   vplkit_triangle_voxel_visible(g, x, y[, end_tolerance_voxels]): the segment x -> y, marched
//     with the DDA walk, is blocked by a listed triangle it crosses strictly inside (grown by
//     1e-3 voxel); triangles whose plane passes within end_tolerance (default 0.01 voxel) of x or
//     y are ignored (the END RULE: no self-occlusion at the ends or at concave junctions).
//   vplkit_triangle_voxel_first_hit(g, origin, dir[, t_max[, end_tolerance_voxels]]): the first
//     triangle met, t > 0; in each occupied voxel the nearest crossing no farther than the voxel's
//     exit (+ slack) wins.
//   The offset contract (exact visibility's, bvh_visibility.glsl, on the listed triangles):
//   vplkit_triangle_voxel_surface_offset(g[, offset_relative]), vplkit_triangle_voxel_offset_slack(g),
//   vplkit_triangle_voxel_segment_free(g, a, b, slack), vplkit_triangle_voxel_visible_offset(g, x,
//     n_x, y, n_y, offset): both ends moved `offset` along their normals, every listed triangle
//     (grown by the slack, 2^-18 of the grid's largest |coordinate|) counts at s in (0, 1];
//   vplkit_triangle_voxel_first_hit_offset(g, x, n_x, dir, offset[, t_max]): from x moved along
//     n_x, every listed triangle counts at t > 0.
// See docs/api/visibility.md ("Triangle voxels") for the rules and their measurements. The
// marches test a crossing against a triangle's edges only within the voxel's stretch of the segment
// grown by the edge slack (the local crossing rule of triangle_voxel_query.hpp) and, with
// VPLKIT_VOXEL_BRICKS, jump over empty bricks (voxel_bricks.glsl; the same answers).
//
// ACCESSORS: those of triangle_voxel_grid.glsl (word, rank, offset, entry, triangle), and with
// VPLKIT_VOXEL_BRICKS vplkit_load_voxel_brick_word (voxel_bricks.glsl).
//
// Parity: every value that decides an answer is `precise` and evaluated in the C++ order
// (vplkit_voxel_dot is glm::dot's order); with IEEE add/mul/div/sqrt the answer is the C++ float
// answer bit for bit. Elsewhere a pair can flip only at a near-tie: a crossing within a few ulps
// of a (grown) triangle edge, or an end within a few ulps of the end tolerance.
#ifndef VPLKIT_VISIBILITY_TRIANGLE_VOXEL_QUERY_GLSL
#define VPLKIT_VISIBILITY_TRIANGLE_VOXEL_QUERY_GLSL

#include "vplkit/visibility/bvh_ray.glsl"
#include "vplkit/visibility/dda.glsl"
#include "vplkit/visibility/triangle_voxel_grid.glsl"
#include "vplkit/visibility/voxel_bricks.glsl"
#include "vplkit/visibility/voxel_grid.glsl"

const float vplkit_triangle_voxel_default_end_tolerance = 0.01;  // voxels
const float vplkit_triangle_voxel_edge_slack = 1e-3;            // voxels
const uint vplkit_triangle_voxel_no_triangle = 0xFFFFFFFFu;

bool vplkit_triangle_voxel_visible(vplkit_voxel_grid g, vec3 x, vec3 y, float end_tolerance_voxels) {
  if (!vplkit_voxel_vec3_finite(x) || !vplkit_voxel_vec3_finite(y)) return false;
  precise vec3 dir = y - x;
  precise float len = sqrt(vplkit_voxel_dot(dir, dir));
  if (!(len > 0.0)) return true;
  float L = vplkit_voxel_length(g);
  precise float eps = end_tolerance_voxels * L;
  precise float slack = vplkit_triangle_voxel_edge_slack * L;
  vplkit_dda_walk w = vplkit_dda_walk_begin(g, x, dir, len);
  int max_iterations = vplkit_dda_max_iterations(g.resolution);
  for (int it = 0; w.running && it < max_iterations; ++it) {
#ifdef VPLKIT_VOXEL_BRICKS
    if (!vplkit_voxel_brick_occupied(g.resolution, w.voxel)) {
      vplkit_dda_walk_leave_brick(g, w);
      continue;
    }
#endif
    int r = vplkit_voxel_occupied_index(g, w.voxel);
    if (r >= 0) {
      // The voxel's stretch of the segment, in the fraction s of x -> y (the local crossing rule).
      precise float s_in = (w.t - slack) / len;
      precise float s_out = (vplkit_dda_walk_exit(w) + slack) / len;
      uint end = vplkit_load_voxel_offset(uint(r) + 1u);
      for (uint e = vplkit_load_voxel_offset(uint(r)); e < end; ++e) {
        // The plane first: most listed triangles are rejected by it (llvmpipe pays for every load).
        uint id = vplkit_load_voxel_entry(e);
        vec4 plane = vplkit_load_voxel_triangle(4u * id);
        precise float d0 = vplkit_voxel_dot(plane.xyz, x) - plane.w;
        precise float d1 = vplkit_voxel_dot(plane.xyz, y) - plane.w;
        if (!(abs(d0) > eps) || !(abs(d1) > eps) || (d0 > 0.0) == (d1 > 0.0)) continue;
        precise float s = d0 / (d0 - d1);
        if (s < s_in || s > s_out) continue;
        precise vec3 p = x + s * dir;
        if (vplkit_voxel_triangle_contains_at(id, p, slack)) return false;
      }
    }
    vplkit_dda_walk_next(g, w);
  }
  return true;
}

bool vplkit_triangle_voxel_visible(vplkit_voxel_grid g, vec3 x, vec3 y) {
  return vplkit_triangle_voxel_visible(g, x, y, vplkit_triangle_voxel_default_end_tolerance);
}

struct vplkit_triangle_voxel_hit {
  bool hit;
  float t;        // distance along the unit direction (0 on a miss)
  vec3 point;     // origin + t * unit direction (origin on a miss)
  uint triangle;  // its index (vplkit_triangle_voxel_no_triangle on a miss)
};

vplkit_triangle_voxel_hit vplkit_triangle_voxel_first_hit(vplkit_voxel_grid g, vec3 origin, vec3 dir, float t_max,
                                                          float end_tolerance_voxels) {
  vplkit_triangle_voxel_hit miss = vplkit_triangle_voxel_hit(false, 0.0, origin, vplkit_triangle_voxel_no_triangle);
  vplkit_dda_walk w = vplkit_dda_walk_begin(g, origin, dir, t_max);
  if (!w.running) return miss;
  float L = vplkit_voxel_length(g);
  precise float eps = end_tolerance_voxels * L;
  precise float slack = vplkit_triangle_voxel_edge_slack * L;
  int max_iterations = vplkit_dda_max_iterations(g.resolution);
  for (int it = 0; w.running && it < max_iterations; ++it) {
#ifdef VPLKIT_VOXEL_BRICKS
    if (!vplkit_voxel_brick_occupied(g.resolution, w.voxel)) {
      vplkit_dda_walk_leave_brick(g, w);
      continue;
    }
#endif
    int r = vplkit_voxel_occupied_index(g, w.voxel);
    if (r >= 0) {
      precise float t_out = vplkit_dda_walk_exit(w) + slack;
      float best = vplkit_dda_infinity();
      uint best_tri = vplkit_triangle_voxel_no_triangle;
      uint end = vplkit_load_voxel_offset(uint(r) + 1u);
      for (uint e = vplkit_load_voxel_offset(uint(r)); e < end; ++e) {
        uint id = vplkit_load_voxel_entry(e);
        vec4 plane = vplkit_load_voxel_triangle(4u * id);
        precise float d0 = vplkit_voxel_dot(plane.xyz, origin) - plane.w;
        precise float den = vplkit_voxel_dot(plane.xyz, w.d);
        if (!(abs(d0) > eps) || den == 0.0) continue;
        precise float tc = -d0 / den;
        if (!(tc > 0.0) || tc > t_max || tc > t_out || !(tc < best)) continue;
        precise vec3 p = origin + tc * w.d;
        if (vplkit_voxel_triangle_contains_at(id, p, slack)) {
          best = tc;
          best_tri = id;
        }
      }
      if (best_tri != vplkit_triangle_voxel_no_triangle) {
        precise vec3 point = origin + best * w.d;
        return vplkit_triangle_voxel_hit(true, best, point, best_tri);
      }
    }
    vplkit_dda_walk_next(g, w);
  }
  return miss;
}

vplkit_triangle_voxel_hit vplkit_triangle_voxel_first_hit(vplkit_voxel_grid g, vec3 origin, vec3 dir, float t_max) {
  return vplkit_triangle_voxel_first_hit(g, origin, dir, t_max, vplkit_triangle_voxel_default_end_tolerance);
}

vplkit_triangle_voxel_hit vplkit_triangle_voxel_first_hit(vplkit_voxel_grid g, vec3 origin, vec3 dir) {
  return vplkit_triangle_voxel_first_hit(g, origin, dir, vplkit_dda_infinity(),
                                         vplkit_triangle_voxel_default_end_tolerance);
}

// ---- The offset contract ----

// bvh_visibility.glsl's offset constants (the C++ names them once, in bvh_visibility.hpp).
const float vplkit_triangle_voxel_offset_relative_default = 1e-4;
const float vplkit_triangle_voxel_offset_coordinate_scale = 3.0517578125e-05;  // 2^-15

float vplkit_triangle_voxel_largest_coordinate(vplkit_voxel_grid g) {
  vec3 lo = g.bounds_min, hi = g.bounds_max;
  return max(max(max(abs(lo.x), abs(hi.x)), max(abs(lo.y), abs(hi.y))), max(abs(lo.z), abs(hi.z)));
}

float vplkit_triangle_voxel_surface_offset(vplkit_voxel_grid g, float offset_relative) {
  precise vec3 ext = g.bounds_max - g.bounds_min;
  float d = max(ext.x, max(ext.y, ext.z));
  float m = vplkit_triangle_voxel_largest_coordinate(g);
  precise float offset = offset_relative * d + vplkit_triangle_voxel_offset_coordinate_scale * m;
  return offset;
}

float vplkit_triangle_voxel_surface_offset(vplkit_voxel_grid g) {
  return vplkit_triangle_voxel_surface_offset(g, vplkit_triangle_voxel_offset_relative_default);
}

float vplkit_triangle_voxel_offset_slack(vplkit_voxel_grid g) {
  return vplkit_triangle_voxel_largest_coordinate(g) * (1.0 / 262144.0);  // 2^-18: exact
}

bool vplkit_triangle_voxel_segment_free(vplkit_voxel_grid g, vec3 a, vec3 b, float slack) {
  if (!vplkit_voxel_vec3_finite(a) || !vplkit_voxel_vec3_finite(b)) return false;
  precise vec3 dir = b - a;
  precise float len = sqrt(vplkit_voxel_dot(dir, dir));
  if (!(len > 0.0)) return true;
  float L = vplkit_voxel_length(g);
  precise float stretch = vplkit_triangle_voxel_edge_slack * L;
  vplkit_dda_walk w = vplkit_dda_walk_begin(g, a, dir, len);
  int max_iterations = vplkit_dda_max_iterations(g.resolution);
  for (int it = 0; w.running && it < max_iterations; ++it) {
#ifdef VPLKIT_VOXEL_BRICKS
    if (!vplkit_voxel_brick_occupied(g.resolution, w.voxel)) {
      vplkit_dda_walk_leave_brick(g, w);
      continue;
    }
#endif
    int r = vplkit_voxel_occupied_index(g, w.voxel);
    if (r >= 0) {
      precise float s_in = (w.t - stretch) / len;
      precise float s_out = (vplkit_dda_walk_exit(w) + stretch) / len;
      uint end = vplkit_load_voxel_offset(uint(r) + 1u);
      for (uint e = vplkit_load_voxel_offset(uint(r)); e < end; ++e) {
        uint id = vplkit_load_voxel_entry(e);
        vec4 plane = vplkit_load_voxel_triangle(4u * id);
        precise float d0 = vplkit_voxel_dot(plane.xyz, a) - plane.w;
        precise float d1 = vplkit_voxel_dot(plane.xyz, b) - plane.w;
        if (d0 == 0.0 || (d1 != 0.0 && (d0 > 0.0) == (d1 > 0.0))) continue;
        precise float s = d0 / (d0 - d1);
        if (s < s_in || s > s_out) continue;
        precise vec3 p = a + s * dir;
        if (vplkit_voxel_triangle_contains_at(id, p, slack)) return false;
      }
    }
    vplkit_dda_walk_next(g, w);
  }
  return true;
}

vec3 vplkit_triangle_voxel_offset_point(vec3 x, vec3 n, float offset) {
  precise vec3 p = x + offset * vplkit_bvh_unit_vector(n);
  return p;
}

bool vplkit_triangle_voxel_visible_offset(vplkit_voxel_grid g, vec3 x, vec3 n_x, vec3 y, vec3 n_y, float offset) {
  if (!vplkit_voxel_vec3_finite(x) || !vplkit_voxel_vec3_finite(y)) return false;
  return vplkit_triangle_voxel_segment_free(g, vplkit_triangle_voxel_offset_point(x, n_x, offset),
                                            vplkit_triangle_voxel_offset_point(y, n_y, offset),
                                            vplkit_triangle_voxel_offset_slack(g));
}

vplkit_triangle_voxel_hit vplkit_triangle_voxel_first_hit_offset(vplkit_voxel_grid g, vec3 x, vec3 n_x, vec3 dir,
                                                                 float offset, float t_max) {
  vec3 origin = vplkit_triangle_voxel_offset_point(x, n_x, offset);
  vplkit_triangle_voxel_hit miss = vplkit_triangle_voxel_hit(false, 0.0, origin, vplkit_triangle_voxel_no_triangle);
  if (!vplkit_voxel_vec3_finite(origin)) return miss;
  vplkit_dda_walk w = vplkit_dda_walk_begin(g, origin, dir, t_max);
  if (!w.running) return miss;
  float slack = vplkit_triangle_voxel_offset_slack(g);
  precise float stretch = vplkit_triangle_voxel_edge_slack * vplkit_voxel_length(g);
  int max_iterations = vplkit_dda_max_iterations(g.resolution);
  for (int it = 0; w.running && it < max_iterations; ++it) {
#ifdef VPLKIT_VOXEL_BRICKS
    if (!vplkit_voxel_brick_occupied(g.resolution, w.voxel)) {
      vplkit_dda_walk_leave_brick(g, w);
      continue;
    }
#endif
    int r = vplkit_voxel_occupied_index(g, w.voxel);
    if (r >= 0) {
      precise float t_out = vplkit_dda_walk_exit(w) + stretch;
      float best = vplkit_dda_infinity();
      uint best_tri = vplkit_triangle_voxel_no_triangle;
      uint end = vplkit_load_voxel_offset(uint(r) + 1u);
      for (uint e = vplkit_load_voxel_offset(uint(r)); e < end; ++e) {
        uint id = vplkit_load_voxel_entry(e);
        vec4 plane = vplkit_load_voxel_triangle(4u * id);
        precise float d0 = vplkit_voxel_dot(plane.xyz, origin) - plane.w;
        precise float den = vplkit_voxel_dot(plane.xyz, w.d);
        if (d0 == 0.0 || den == 0.0) continue;
        precise float tc = -d0 / den;
        if (!(tc > 0.0) || tc > t_max || tc > t_out || !(tc < best)) continue;
        precise vec3 p = origin + tc * w.d;
        if (vplkit_voxel_triangle_contains_at(id, p, slack)) {
          best = tc;
          best_tri = id;
        }
      }
      if (best_tri != vplkit_triangle_voxel_no_triangle) {
        precise vec3 point = origin + best * w.d;
        return vplkit_triangle_voxel_hit(true, best, point, best_tri);
      }
    }
    vplkit_dda_walk_next(g, w);
  }
  return miss;
}

vplkit_triangle_voxel_hit vplkit_triangle_voxel_first_hit_offset(vplkit_voxel_grid g, vec3 x, vec3 n_x, vec3 dir,
                                                                 float offset) {
  return vplkit_triangle_voxel_first_hit_offset(g, x, n_x, dir, offset, vplkit_dda_infinity());
}

#endif  // VPLKIT_VISIBILITY_TRIANGLE_VOXEL_QUERY_GLSL
