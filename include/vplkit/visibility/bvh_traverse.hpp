// SPDX-License-Identifier: MIT
#pragma once
// Ray queries against a BVH (bvh_layout.hpp): the closest hit, and any hit (occlusion of a
// segment). glsl/vplkit/visibility/bvh_traverse.glsl is the same code statement for statement.
//
// Ray: origin + t * dir, dir of any length (t in units of |dir|, as Embree's rtcIntersect1),
// hits accepted for t in (t_min, t_max]. t_min below 0 or NaN is read as 0; t_max < t_min or NaN
// gives no hit. An invalid ray (non-finite origin or direction, zero direction) or an empty
// hierarchy gives no hit.
//
// Traversal: iterative, with a fixed stack of bvh_max_depth entries (node index + entry
// distance). At an inner node both children's boxes are tested; the nearer is visited next and
// the farther pushed (the left child on equal entry distances); a popped node whose entry
// distance lies beyond the closest hit so far is skipped. Leaves test their triangles in slot
// order, and a hit replaces the current one only when strictly closer, so among triangles hit at
// exactly the same t the first one visited wins. The order is fixed by the data, so C++ and GLSL
// visit the same nodes and, with IEEE arithmetic, report the same triangle.
// Loop bound (llvmpipe ends any shader loop after 65535 iterations per invocation, silently):
// every iteration of the node loop consumes one node, each node is reached at most once, so the
// loop runs at most node_count times; the leaf loop runs count <= bvh_max_leaf_size times per
// leaf. One query therefore costs (nodes visited + triangles tested) iterations of the budget;
// the parity test prints the largest count it met.
// Scaled rays: where make_bvh_ray stored the direction scaled by 1/4 (a component above 2^126,
// bvh_ray.hpp), the traversal runs in the ray's own parameter, t_scale * t: t_min and t_max are
// multiplied by t_scale on the way in and the hit's t by 1/4 on the way out (powers of two,
// exact unless the result leaves the normal range; t_scale = 1 changes nothing).
// Stack: the builder (and validate_bvh) guarantee depth <= bvh_max_depth, so the stack cannot
// overflow; the push is guarded anyway, so a corrupt hierarchy loses nodes instead of writing
// out of bounds.
#include <vplkit/core/vector.hpp>
#include <vplkit/visibility/bvh_layout.hpp>
#include <vplkit/visibility/bvh_ray.hpp>

#include <cmath>
#include <cstdint>
#include <limits>

namespace vplkit {

template <class T>
struct bvh_hit {
  bool hit;
  T t;                     // ray parameter (0 on a miss)
  std::uint32_t triangle;  // the input index of the triangle hit (bvh_triangle::id); ~0u on a miss
  T u, v;                  // barycentric weights of its v1 and v2 (Embree's u, v)
  vec3<T> position;        // w v0 + u v1 + v v2: on the triangle's plane to rounding
  vec3<T> normal;          // unit geometric normal, cross(v1 - v0, v2 - v0) normalised (0 if it underflows)
};

// Work counts of one query (C++ only; the GLSL has no counters).
struct bvh_traversal_counts {
  std::uint32_t nodes = 0;      // iterations of the node loop
  std::uint32_t triangles = 0;  // ray/triangle tests
};

namespace detail {

// What the node loop found: the slot of the closest (or any) triangle hit and its t.
template <class T>
struct bvh_traversal_result {
  bool hit;
  std::uint32_t slot;
  T t;
};

// The shared traversal of bvh_closest_hit (any_hit false) and bvh_occluded (any_hit true). t_min,
// t_max and the result's t are in the ray's own parameter (bvh_ray::t_scale times the caller's).
template <class T>
inline bvh_traversal_result<T> bvh_traverse(const bvh_view<T>& b, const bvh_ray<T>& r, T t_min, T t_max, bool any_hit,
                                            bvh_traversal_counts* counts) {
  bvh_traversal_result<T> res{false, 0u, t_max};
  if (!r.valid || b.node_count == 0) return res;
  const T t_lo = t_min > T(0) ? t_min : T(0);
  if (!(t_max >= t_lo)) return res;
  T t_root = T(0);
  if (!bvh_ray_box(r, b.nodes[0].bounds_min, b.nodes[0].bounds_max, t_lo, t_max, t_root)) return res;

  std::uint32_t stack_node[bvh_max_depth];
  T stack_t[bvh_max_depth];
  int sp = 0;
  std::uint32_t node = 0;
  T node_t = t_root;
  const auto node_count = std::uint32_t(b.node_count);
  for (std::uint32_t it = 0; it < node_count; ++it) {
    if (counts) ++counts->nodes;
    if (node_t <= res.t) {
      const bvh_node<T> n = b.nodes[node];
      if (n.count > 0u) {
        for (std::uint32_t k = 0; k < n.count && k < std::uint32_t(bvh_max_leaf_size); ++k) {
          const bvh_triangle<T> tri = b.triangles[n.first + k];
          if (counts) ++counts->triangles;
          const bvh_triangle_hit<T> h = bvh_ray_triangle(r, tri.v0, tri.v1, tri.v2, t_lo, res.t);
          if (h.hit && (!res.hit || h.t < res.t)) {
            res.hit = true;
            res.slot = n.first + k;
            res.t = h.t;
            if (any_hit) return res;
          }
        }
      } else {
        const bvh_node<T> left = b.nodes[n.first];
        const bvh_node<T> right = b.nodes[n.first + 1u];
        T t_left = T(0), t_right = T(0);
        const bool hit_left = bvh_ray_box(r, left.bounds_min, left.bounds_max, t_lo, res.t, t_left);
        const bool hit_right = bvh_ray_box(r, right.bounds_min, right.bounds_max, t_lo, res.t, t_right);
        if (hit_left && hit_right) {
          const bool left_first = t_left <= t_right;
          if (sp < bvh_max_depth) {
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

}  // namespace detail

// The closest triangle hit by origin + t * dir for t in (t_min, t_max].
template <class T>
inline bvh_hit<T> bvh_closest_hit(const bvh_view<T>& b, vec3<T> origin, vec3<T> dir, T t_min = T(0),
                                  T t_max = std::numeric_limits<T>::infinity(), bvh_traversal_counts* counts = nullptr) {
  bvh_hit<T> h{false, T(0), ~0u, T(0), T(0), vec3<T>(T(0)), vec3<T>(T(0))};
  const bvh_ray<T> r = make_bvh_ray(origin, dir);
  const detail::bvh_traversal_result<T> res =
      detail::bvh_traverse(b, r, t_min * r.t_scale, t_max * r.t_scale, false, counts);
  if (!res.hit) return h;
  // The winning triangle again, for its barycentrics: the same call gives the same t.
  const bvh_triangle<T> tri = b.triangles[res.slot];
  const bvh_triangle_hit<T> th = bvh_ray_triangle(r, tri.v0, tri.v1, tri.v2, T(-1), res.t);
  h.hit = true;
  h.t = r.t_scale == T(1) ? res.t : res.t * T(0.25);
  h.triangle = tri.id;
  h.u = th.u;
  h.v = th.v;
  h.position = th.w * tri.v0 + th.u * tri.v1 + th.v * tri.v2;
  const vec3<T> e1 = tri.v1 - tri.v0, e2 = tri.v2 - tri.v0;
  h.normal = detail::bvh_unit_vector(
      vec3<T>(e1.y * e2.z - e2.y * e1.z, e1.z * e2.x - e2.z * e1.x, e1.x * e2.y - e2.x * e1.y));  // glm::cross
  return h;
}

// Does any triangle meet origin + t * dir for t in (t_min, t_max]? For the segment from p to q,
// bvh_occluded(b, p, q - p, 0, 1).
template <class T>
inline bool bvh_occluded(const bvh_view<T>& b, vec3<T> origin, vec3<T> dir, T t_min = T(0),
                         T t_max = std::numeric_limits<T>::infinity(), bvh_traversal_counts* counts = nullptr) {
  const bvh_ray<T> r = make_bvh_ray(origin, dir);
  return detail::bvh_traverse(b, r, t_min * r.t_scale, t_max * r.t_scale, true, counts).hit;
}

}  // namespace vplkit
