// SPDX-License-Identifier: MIT
// vplkit GLSL pack: ray queries against a BVH, the closest hit and any hit (mirrors
// include/vplkit/visibility/bvh_traverse.hpp, T = float, statement for statement).
//
// Ray: origin + t * dir (dir any length, t in units of |dir|); hits for t in (t_min, t_max];
// t_min below 0 reads as 0. Invalid ray or node_count 0: no hit.
// Traversal: iterative, a fixed stack of vplkit_bvh_max_depth (32) entries (node, entry t);
// both children tested, the nearer visited first (the left on ties), popped nodes beyond the
// closest hit skipped; a triangle replaces the current hit only when strictly closer. The order
// is fixed by the data, so the GPU visits what the C++ visits and reports the same triangle.
// Loop bounds (llvmpipe silently ends loops after 65535 iterations per invocation, all loops
// together): the node loop runs at most node_count times (each iteration consumes a node, each
// node is reached once), the leaf loop at most count <= vplkit_bvh_max_leaf_size times. A query
// spends (nodes visited + triangles tested) of that budget, typically 50 to 200 on 10^5
// triangles; docs/glsl/bvh.md has measured numbers.
//
// ACCESSORS: vplkit_load_bvh_node, vplkit_load_bvh_triangle (see bvh_layout.glsl).
#ifndef VPLKIT_VISIBILITY_BVH_TRAVERSE_GLSL
#define VPLKIT_VISIBILITY_BVH_TRAVERSE_GLSL

#include "vplkit/core/constants.glsl"
#include "vplkit/visibility/bvh_layout.glsl"
#include "vplkit/visibility/bvh_ray.glsl"

struct vplkit_bvh_hit {
  bool hit;
  float t;        // ray parameter (0 on a miss)
  uint triangle;  // the host's index of the triangle hit (vplkit_bvh_triangle.id); ~0u on a miss
  float u;        // barycentric weight of its v1 (Embree's u)
  float v;        // barycentric weight of its v2
  vec3 position;  // w v0 + u v1 + v v2
  vec3 normal;    // unit geometric normal, cross(v1 - v0, v2 - v0) normalised (0 if it underflows)
};

// What the node loop found: the slot of the closest (or any) triangle hit and its t.
struct vplkit_bvh_traversal_result {
  bool hit;
  uint slot;
  float t;
};

// +infinity, the C++ default t_max.
float vplkit_bvh_infinity() {
  return uintBitsToFloat(0x7F800000u);
}

// The shared traversal of vplkit_bvh_closest_hit (any_hit false) and vplkit_bvh_occluded (true);
// t_min, t_max and the result's t in the ray's own parameter (r.t_scale times the caller's).
vplkit_bvh_traversal_result vplkit_bvh_traverse(vplkit_bvh b, vplkit_bvh_ray r, float t_min, float t_max,
                                                bool any_hit) {
  vplkit_bvh_traversal_result res = vplkit_bvh_traversal_result(false, 0u, t_max);
  if (!r.valid || b.node_count == 0u) return res;
  float t_lo = t_min > 0.0 ? t_min : 0.0;
  if (!(t_max >= t_lo)) return res;
  vplkit_bvh_node root = vplkit_load_bvh_node(0u);
  float t_root = 0.0;
  if (!vplkit_bvh_ray_box(r, root.bounds_min, root.bounds_max, t_lo, t_max, t_root)) return res;

  uint stack_node[vplkit_bvh_max_depth];
  float stack_t[vplkit_bvh_max_depth];
  int sp = 0;
  uint node = 0u;
  float node_t = t_root;
  for (uint it = 0u; it < b.node_count; ++it) {
    if (node_t <= res.t) {
      vplkit_bvh_node n = vplkit_load_bvh_node(node);
      if (n.count > 0u) {
        for (uint k = 0u; k < n.count && k < uint(vplkit_bvh_max_leaf_size); ++k) {
          vplkit_bvh_triangle tri = vplkit_load_bvh_triangle(n.first + k);
          vplkit_bvh_triangle_hit h = vplkit_bvh_ray_triangle(r, tri.v0, tri.v1, tri.v2, t_lo, res.t);
          if (h.hit && (!res.hit || h.t < res.t)) {
            res.hit = true;
            res.slot = n.first + k;
            res.t = h.t;
            if (any_hit) return res;
          }
        }
      } else {
        vplkit_bvh_node left = vplkit_load_bvh_node(n.first);
        vplkit_bvh_node right = vplkit_load_bvh_node(n.first + 1u);
        float t_left = 0.0;
        float t_right = 0.0;
        bool hit_left = vplkit_bvh_ray_box(r, left.bounds_min, left.bounds_max, t_lo, res.t, t_left);
        bool hit_right = vplkit_bvh_ray_box(r, right.bounds_min, right.bounds_max, t_lo, res.t, t_right);
        if (hit_left && hit_right) {
          bool left_first = t_left <= t_right;
          if (sp < vplkit_bvh_max_depth) {
            stack_node[sp] = left_first ? n.first + 1u : n.first;
            stack_t[sp] = left_first ? t_right : t_left;
            ++sp;
          }
          node = left_first ? n.first : n.first + 1u;
          node_t = left_first ? t_left : t_right;
          continue;
        }
        if (hit_left || hit_right) {
          node = hit_left ? n.first : n.first + 1u;
          node_t = hit_left ? t_left : t_right;
          continue;
        }
      }
    }
    if (sp == 0) break;
    --sp;
    node = stack_node[sp];
    node_t = stack_t[sp];
  }
  return res;
}

// The closest triangle hit by origin + t * dir for t in (t_min, t_max].
vplkit_bvh_hit vplkit_bvh_closest_hit(vplkit_bvh b, vec3 origin, vec3 dir, float t_min, float t_max) {
  vplkit_bvh_hit h = vplkit_bvh_hit(false, 0.0, ~0u, 0.0, 0.0, vec3(0.0), vec3(0.0));
  vplkit_bvh_ray r = vplkit_make_bvh_ray(origin, dir);
  precise float t_min_ray = t_min * r.t_scale;
  precise float t_max_ray = t_max * r.t_scale;
  vplkit_bvh_traversal_result res = vplkit_bvh_traverse(b, r, t_min_ray, t_max_ray, false);
  if (!res.hit) return h;
  // The winning triangle again, for its barycentrics: the same call gives the same t.
  vplkit_bvh_triangle tri = vplkit_load_bvh_triangle(res.slot);
  vplkit_bvh_triangle_hit th = vplkit_bvh_ray_triangle(r, tri.v0, tri.v1, tri.v2, -1.0, res.t);
  h.hit = true;
  precise float t_quarter = res.t * 0.25;
  h.t = r.t_scale == 1.0 ? res.t : t_quarter;
  h.triangle = tri.id;
  h.u = th.u;
  h.v = th.v;
  precise vec3 position = th.w * tri.v0 + th.u * tri.v1 + th.v * tri.v2;
  h.position = position;
  precise vec3 e1 = tri.v1 - tri.v0;
  precise vec3 e2 = tri.v2 - tri.v0;
  precise vec3 cr = vec3(e1.y * e2.z - e2.y * e1.z, e1.z * e2.x - e2.z * e1.x, e1.x * e2.y - e2.x * e1.y);
  h.normal = vplkit_bvh_unit_vector(cr);  // glm::cross, normalised
  return h;
}

// t_min = 0, t_max = +infinity (the C++ default arguments).
vplkit_bvh_hit vplkit_bvh_closest_hit(vplkit_bvh b, vec3 origin, vec3 dir) {
  return vplkit_bvh_closest_hit(b, origin, dir, 0.0, vplkit_bvh_infinity());
}

// Does any triangle meet origin + t * dir for t in (t_min, t_max]? For the segment p -> q:
// vplkit_bvh_occluded(b, p, q - p, 0.0, 1.0).
bool vplkit_bvh_occluded(vplkit_bvh b, vec3 origin, vec3 dir, float t_min, float t_max) {
  vplkit_bvh_ray r = vplkit_make_bvh_ray(origin, dir);
  precise float t_min_ray = t_min * r.t_scale;
  precise float t_max_ray = t_max * r.t_scale;
  return vplkit_bvh_traverse(b, r, t_min_ray, t_max_ray, true).hit;
}

bool vplkit_bvh_occluded(vplkit_bvh b, vec3 origin, vec3 dir) {
  return vplkit_bvh_occluded(b, origin, dir, 0.0, vplkit_bvh_infinity());
}

#endif  // VPLKIT_VISIBILITY_BVH_TRAVERSE_GLSL
