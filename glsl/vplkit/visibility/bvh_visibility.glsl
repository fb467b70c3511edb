// SPDX-License-Identifier: MIT
// vplkit GLSL pack: exact visibility through a BVH, the GPU side of the C++ callables
// bvh_visibility<float> and bvh_tracer<float> (mirrors include/vplkit/visibility/bvh_visibility.hpp,
// T = float, statement for statement):
//
//   bvh_surface_offset(view[, rel])              <-> vplkit_bvh_surface_offset(bvh[, rel])
//   bvh_offset_point(x, n, offset)               <-> vplkit_bvh_offset_point(x, n, offset)
//   bvh_visible(view, x, n_x, y, n_y[, rel])     <-> vplkit_bvh_visible(bvh, x, n_x, y, n_y[, rel])
//   bvh_trace(view, x, n_x, dir[, rel])          <-> vplkit_bvh_trace(bvh, x, n_x, dir[, rel])
//   bvh_visibility<float>{view, rel}(x, n_x, y, n_y)
//                                                <-> vplkit_bvh_visibility_test(vplkit_make_bvh_visibility(bvh), ...)
//   bvh_tracer<float>{view, rel}(x, n_x, dir)    <-> vplkit_bvh_tracer_trace(vplkit_make_bvh_tracer(bvh), ...)
//
// Self-intersection: segment ends and ray origins are moved along their (unit) normal, as given,
// by offset_relative * D + 2^-15 * M, D = the root box's
// largest extent, M = its largest |coordinate| (default offset_relative 1e-4). Why: see
// docs/api/bvh.md. The segment between the moved ends is tested whole, t in (0, 1].
//
// To use these as the estimators' visibility and tracer (visibility/visibility_callables.glsl),
// define VPLKIT_USER_VISIBILITY / VPLKIT_USER_TRACER and forward vplkit_user_visible /
// vplkit_user_trace to vplkit_bvh_visible / vplkit_bvh_trace (docs/glsl/bvh.md shows it).
//
// ACCESSORS: vplkit_load_bvh_node, vplkit_load_bvh_triangle (see bvh_layout.glsl).
#ifndef VPLKIT_VISIBILITY_BVH_VISIBILITY_GLSL
#define VPLKIT_VISIBILITY_BVH_VISIBILITY_GLSL

#include "vplkit/core/gather_point.glsl"
#include "vplkit/visibility/bvh_layout.glsl"
#include "vplkit/visibility/bvh_ray.glsl"
#include "vplkit/visibility/bvh_traverse.glsl"

const float vplkit_bvh_offset_relative_default = 1e-4;
const float vplkit_bvh_offset_coordinate_scale = 3.0517578125e-05;  // 2^-15: 256 float ulps of a coordinate

// offset_relative * D + 2^-15 * M; 0 for an empty hierarchy.
float vplkit_bvh_surface_offset(vplkit_bvh b, float offset_relative) {
  if (b.node_count == 0u) return 0.0;
  vplkit_bvh_node root = vplkit_load_bvh_node(0u);
  vec3 lo = root.bounds_min;
  vec3 hi = root.bounds_max;
  precise vec3 ext = hi - lo;
  float d = max(ext.x, max(ext.y, ext.z));
  vec3 m3 = vec3(max(abs(lo.x), abs(hi.x)), max(abs(lo.y), abs(hi.y)), max(abs(lo.z), abs(hi.z)));
  float m = max(m3.x, max(m3.y, m3.z));
  precise float offset = offset_relative * d + vplkit_bvh_offset_coordinate_scale * m;
  return offset;
}

float vplkit_bvh_surface_offset(vplkit_bvh b) {
  return vplkit_bvh_surface_offset(b, vplkit_bvh_offset_relative_default);
}

// x moved by `offset` along the unit normal.
vec3 vplkit_bvh_offset_point(vec3 x, vec3 n, float offset) {
  precise vec3 p = x + offset * vplkit_bvh_unit_vector(n);
  return p;
}

// Are the surface points x (normal n_x) and y (normal n_y) mutually visible? Non-finite x or y:
// not visible.
bool vplkit_bvh_visible(vplkit_bvh b, vec3 x, vec3 n_x, vec3 y, vec3 n_y, float offset_relative) {
  if (!vplkit_bvh_vec3_finite(x) || !vplkit_bvh_vec3_finite(y)) return false;
  float offset = vplkit_bvh_surface_offset(b, offset_relative);
  vec3 o = vplkit_bvh_offset_point(x, n_x, offset);
  vec3 p = vplkit_bvh_offset_point(y, n_y, offset);
  precise vec3 seg = p - o;
  return !vplkit_bvh_occluded(b, o, seg, 0.0, 1.0);
}

bool vplkit_bvh_visible(vplkit_bvh b, vec3 x, vec3 n_x, vec3 y, vec3 n_y) {
  return vplkit_bvh_visible(b, x, n_x, y, n_y, vplkit_bvh_offset_relative_default);
}

// The first surface hit by the ray leaving surface x (normal n_x) along dir: the barycentric
// point on the triangle hit.
vplkit_ray_hit vplkit_bvh_trace(vplkit_bvh b, vec3 x, vec3 n_x, vec3 dir, float offset_relative) {
  vec3 o = vplkit_bvh_offset_point(x, n_x, vplkit_bvh_surface_offset(b, offset_relative));
  vplkit_bvh_hit h = vplkit_bvh_closest_hit(b, o, dir);
  vplkit_ray_hit r = vplkit_ray_hit(h.hit, vec3(0.0), vec3(0.0), vec3(0.0));
  if (h.hit) {
    r.position = h.position;
    r.normal = h.normal;
  }
  return r;
}

vplkit_ray_hit vplkit_bvh_trace(vplkit_bvh b, vec3 x, vec3 n_x, vec3 dir) {
  return vplkit_bvh_trace(b, x, n_x, dir, vplkit_bvh_offset_relative_default);
}

// The callables as plain values (change offset_relative after making them).
struct vplkit_bvh_visibility {
  vplkit_bvh bvh;
  float offset_relative;
};

struct vplkit_bvh_tracer {
  vplkit_bvh bvh;
  float offset_relative;
};

vplkit_bvh_visibility vplkit_make_bvh_visibility(vplkit_bvh b) {
  return vplkit_bvh_visibility(b, vplkit_bvh_offset_relative_default);
}

vplkit_bvh_tracer vplkit_make_bvh_tracer(vplkit_bvh b) {
  return vplkit_bvh_tracer(b, vplkit_bvh_offset_relative_default);
}

bool vplkit_bvh_visibility_test(vplkit_bvh_visibility v, vec3 x, vec3 n_x, vec3 y, vec3 n_y) {
  return vplkit_bvh_visible(v.bvh, x, n_x, y, n_y, v.offset_relative);
}

vplkit_ray_hit vplkit_bvh_tracer_trace(vplkit_bvh_tracer tr, vec3 x, vec3 n_x, vec3 dir) {
  return vplkit_bvh_trace(tr.bvh, x, n_x, dir, tr.offset_relative);
}

#endif  // VPLKIT_VISIBILITY_BVH_VISIBILITY_GLSL
