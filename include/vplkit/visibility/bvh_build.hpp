// SPDX-License-Identifier: MIT
#pragma once
// Building a BVH over triangles on the host: binned SAH (Wald, "On fast construction of SAH-based
// bounding volume hierarchies", 2007), single-threaded and deterministic.
//
// Input is a view, as everywhere in vplkit: an indexed mesh (positions + 3 indices per triangle)
// or a triangle soup (3 consecutive vertices per triangle). The result owns two flat arrays in
// the GPU layout of bvh_layout.hpp.
//
// Algorithm, per node (top-down, depth first):
// - Bin the triangles' bounding-box centres into bin_count equal bins along each axis of the
//   centres' bounds; sweep the bins to cost every split between bins:
//     cost = traversal_cost + (area(L) n_L + area(R) n_R) / area(node)   (one triangle test = 1).
//   Areas are computed in double, so boxes spanning 1e30 do not overflow.
// - A node with n <= max_leaf_size triangles becomes a leaf unless a split is strictly cheaper
//   than n. A larger node always splits: at its cheapest SAH split, or, when every centre lies in
//   one bin (identical centres, a zero-extent axis), at the object median.
// - Depth limit: a node at depth d with n triangles may use SAH only while
//   d + 1 + ceil(log2(ceil(n / max_leaf_size))) <= bvh_max_depth - 1; past that it is split at the
//   object median, which halves it. So every leaf lies at depth <= bvh_max_depth - 1 whatever
//   the input (2^30 triangles need at most 30 median levels).
// Determinism: no threads, no unordered containers, ties broken by the lowest axis, then the
// lowest bin, and the median sort orders by (centre, input index), a total order. The same input
// gives the same bytes with every standard library.
// Robustness: degenerate (zero-area, collinear, point) triangles are kept; their boxes are valid
// and the ray test never reports them with a NaN (see bvh_ray.hpp). Non-finite vertices, indices
// out of range and bad parameters throw invalid_input naming the culprit. Empty input gives an
// empty hierarchy (no nodes) that every traversal misses.
#include <vplkit/core/error.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/visibility/bvh_layout.hpp>
#include <vplkit/visibility/bvh_ray.hpp>
#include <vplkit/visibility/voxelize.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace vplkit {

struct bvh_build_params {
  int bin_count = 32;           // SAH bins per axis, in [2, 256]
  int max_leaf_size = 4;        // in [1, bvh_max_leaf_size]
  double traversal_cost = 1.0;  // cost of visiting an inner node, in triangle tests; finite, >= 0
};

namespace detail {

template <class T>
inline bool bvh_box_contains(vec3<T> outer_min, vec3<T> outer_max, vec3<T> p) {
  return p.x >= outer_min.x && p.y >= outer_min.y && p.z >= outer_min.z && p.x <= outer_max.x &&
         p.y <= outer_max.y && p.z <= outer_max.z;
}

// Half the surface area of a box, in double (boxes of size 1e30 would overflow float).
template <class T>
inline double bvh_half_area(vec3<T> lo, vec3<T> hi) {
  const double dx = double(hi.x) - double(lo.x), dy = double(hi.y) - double(lo.y), dz = double(hi.z) - double(lo.z);
  return dx * dy + dy * dz + dz * dx;
}

// Levels of object-median splits that n triangles need to reach leaves of at most leaf_size.
inline int bvh_median_levels(std::size_t n, std::size_t leaf_size) {
  int levels = 0;
  std::size_t capacity = leaf_size;
  while (capacity < n) {
    capacity *= 2;
    ++levels;
  }
  return levels;
}

}  // namespace detail

// Checks that (nodes, triangles) form a tree the traversal can walk safely: every node reached
// exactly once from the root, no deeper than bvh_max_depth - 1, children inside the node array,
// leaves of 1 .. bvh_max_leaf_size triangles covering every triangle slot exactly once, ids a
// permutation of 0 .. triangle_count - 1, finite boxes that contain their children and their
// triangles. Throws invalid_input naming the first bad node; returns the depth (levels; 0 if
// empty).
template <class T>
inline int validate_bvh(const bvh_view<T>& b, const char* who = "validate_bvh") {
  const std::string w(who);
  if (b.node_count == 0) {
    if (b.triangle_count != 0)
      throw invalid_input(w + ": " + std::to_string(b.triangle_count) + " triangles but no nodes");
    return 0;
  }
  if (b.nodes == nullptr || b.triangles == nullptr) throw invalid_input(w + ": null node or triangle array");
  if (b.triangle_count == 0 || b.triangle_count > bvh_max_triangles)
    throw invalid_input(w + ": triangle count " + std::to_string(b.triangle_count) + " is not in [1, 2^30]");
  std::vector<unsigned char> node_seen(b.node_count, 0), slot_seen(b.triangle_count, 0), id_seen(b.triangle_count, 0);
  std::vector<std::pair<std::size_t, int>> stack{{0, 0}};
  int depth = 0;
  std::size_t nodes_reached = 0, slots_covered = 0;
  while (!stack.empty()) {
    const std::size_t i = stack.back().first;
    const int d = stack.back().second;
    stack.pop_back();
    const auto at = [&] { return w + ": node " + std::to_string(i); };
    if (node_seen[i]) throw invalid_input(at() + " is reached twice (not a tree)");
    node_seen[i] = 1;
    ++nodes_reached;
    if (d >= bvh_max_depth)
      throw invalid_input(at() + " lies at depth " + std::to_string(d) + " (limit " + std::to_string(bvh_max_depth - 1) + ")");
    depth = std::max(depth, d + 1);
    const bvh_node<T>& n = b.nodes[i];
    if (!detail::bvh_vec3_finite(n.bounds_min) || !detail::bvh_vec3_finite(n.bounds_max) ||
        !detail::bvh_box_contains(n.bounds_min, n.bounds_max, n.bounds_min))
      throw invalid_input(at() + " has a non-finite or inverted box");
    if (n.count == 0) {
      if (n.first == 0 || std::size_t(n.first) + 1 >= b.node_count)
        throw invalid_input(at() + " has children " + std::to_string(n.first) + ", " + std::to_string(n.first + 1ull) +
                            " outside [1, " + std::to_string(b.node_count) + ")");
      for (std::uint32_t c = n.first; c <= n.first + 1; ++c) {
        const bvh_node<T>& ch = b.nodes[c];
        if (!detail::bvh_box_contains(n.bounds_min, n.bounds_max, ch.bounds_min) ||
            !detail::bvh_box_contains(n.bounds_min, n.bounds_max, ch.bounds_max))
          throw invalid_input(at() + ": the box of child " + std::to_string(c) + " is not inside it");
        stack.push_back({c, d + 1});
      }
      continue;
    }
    if (n.count > std::uint32_t(bvh_max_leaf_size) || std::size_t(n.first) + n.count > b.triangle_count)
      throw invalid_input(at() + " is a leaf of " + std::to_string(n.count) + " triangles from slot " +
                          std::to_string(n.first) + " (at most " + std::to_string(bvh_max_leaf_size) + ", within " +
                          std::to_string(b.triangle_count) + " slots)");
    for (std::uint32_t s = n.first; s < n.first + n.count; ++s) {
      const bvh_triangle<T>& tri = b.triangles[s];
      if (slot_seen[s]) throw invalid_input(at() + ": triangle slot " + std::to_string(s) + " is in two leaves");
      slot_seen[s] = 1;
      ++slots_covered;
      if (std::size_t(tri.id) >= b.triangle_count || id_seen[tri.id])
        throw invalid_input(at() + ": triangle slot " + std::to_string(s) + " has id " + std::to_string(tri.id) +
                            " (out of range or repeated)");
      id_seen[tri.id] = 1;
      for (const vec3<T>& v : {tri.v0, tri.v1, tri.v2})
        if (!detail::bvh_vec3_finite(v) || !detail::bvh_box_contains(n.bounds_min, n.bounds_max, v))
          throw invalid_input(at() + ": triangle slot " + std::to_string(s) + " has a vertex outside the leaf's box");
    }
  }
  if (nodes_reached != b.node_count)
    throw invalid_input(w + ": " + std::to_string(b.node_count - nodes_reached) + " nodes are not reachable from the root");
  if (slots_covered != b.triangle_count)
    throw invalid_input(w + ": " + std::to_string(b.triangle_count - slots_covered) + " triangle slots are in no leaf");
  return depth;
}

// A view of arrays from elsewhere (a cache, a read-back), validated by validate_bvh.
template <class T>
inline bvh_view<T> make_bvh_view(const bvh_node<T>* nodes, std::size_t node_count, const bvh_triangle<T>* triangles,
                                 std::size_t triangle_count) {
  const bvh_view<T> v{nodes, node_count, triangles, triangle_count};
  validate_bvh(v, "make_bvh_view");
  return v;
}

// Owns the two arrays. Made by build_bvh / build_bvh_soup, or by adopting arrays (validated).
template <class T>
class bvh {
 public:
  bvh() = default;  // empty: no nodes, no triangles
  bvh(std::vector<bvh_node<T>> nodes, std::vector<bvh_triangle<T>> triangles)
      : nodes_(std::move(nodes)), triangles_(std::move(triangles)) {
    depth_ = validate_bvh(view(), "bvh");
  }
  const std::vector<bvh_node<T>>& nodes() const { return nodes_; }
  const std::vector<bvh_triangle<T>>& triangles() const { return triangles_; }
  std::size_t node_count() const { return nodes_.size(); }
  std::size_t triangle_count() const { return triangles_.size(); }
  bool empty() const { return nodes_.empty(); }
  int depth() const { return depth_; }  // levels: the deepest leaf's depth + 1 (0 if empty)
  bvh_view<T> view() const { return bvh_view<T>{nodes_.data(), nodes_.size(), triangles_.data(), triangles_.size()}; }

 private:
  std::vector<bvh_node<T>> nodes_;
  std::vector<bvh_triangle<T>> triangles_;
  int depth_ = 0;
};

namespace detail {

inline void validate_bvh_build_params(const bvh_build_params& p, const char* who) {
  if (p.bin_count < 2 || p.bin_count > 256)
    throw invalid_input(std::string(who) + ": bin_count " + std::to_string(p.bin_count) + " is not in [2, 256]");
  if (p.max_leaf_size < 1 || p.max_leaf_size > bvh_max_leaf_size)
    throw invalid_input(std::string(who) + ": max_leaf_size " + std::to_string(p.max_leaf_size) + " is not in [1, " +
                        std::to_string(bvh_max_leaf_size) + "]");
  if (!(p.traversal_cost >= 0.0) || !std::isfinite(p.traversal_cost))
    throw invalid_input(std::string(who) + ": traversal_cost must be finite and >= 0");
}

// One triangle while building: its box, the box's centre (in double: exact enough to bin boxes
// 1e30 wide) and its input index. Items are moved, not indexed, so every pass reads memory in
// order.
template <class T>
struct bvh_build_item {
  vec3<T> lo, hi;
  vec3<double> centre;
  std::uint32_t id;
};

// SAH bins of one axis: triangle count and the union of their boxes.
template <class T>
struct bvh_bin {
  std::size_t n;
  vec3<T> lo, hi;
};

// The binned SAH builder over triangle_count triangles whose vertices vertex(t, k) returns.
template <class T, class Vertex>
inline bvh<T> build_bvh_core(std::size_t triangle_count, Vertex vertex, const bvh_build_params& p) {
  if (triangle_count == 0) return bvh<T>();
  const std::size_t n = triangle_count;
  std::vector<bvh_build_item<T>> items(n);
  for (std::size_t t = 0; t < n; ++t) {
    const vec3<T> a = vertex(t, 0), b = vertex(t, 1), c = vertex(t, 2);
    bvh_build_item<T>& it = items[t];
    it.lo = glm::min(a, glm::min(b, c));
    it.hi = glm::max(a, glm::max(b, c));
    it.centre = 0.5 * (vec3<double>(it.lo) + vec3<double>(it.hi));
    it.id = std::uint32_t(t);
  }

  const int bins = p.bin_count;
  const auto nbins = std::size_t(bins);
  const std::size_t leaf_size = std::size_t(p.max_leaf_size);
  std::vector<bvh_node<T>> nodes;
  nodes.reserve(2 * n - 1);
  nodes.push_back(bvh_node<T>{vec3<T>(T(0)), 0u, vec3<T>(T(0)), 0u});
  struct task {
    std::uint32_t node;
    std::size_t begin, end;
    int depth;
  };
  std::vector<task> work{{0u, 0, n, 0}};
  std::vector<bvh_bin<T>> bin(3 * nbins);  // axis a: bin[a * nbins + k]
  std::vector<double> right_area(nbins, 0.0);
  std::vector<std::size_t> right_n(nbins, 0);

  while (!work.empty()) {
    const task tk = work.back();
    work.pop_back();
    const std::size_t count = tk.end - tk.begin;
    vec3<T> box_lo = items[tk.begin].lo, box_hi = items[tk.begin].hi;
    vec3<double> c_lo = items[tk.begin].centre, c_hi = c_lo;
    for (std::size_t i = tk.begin + 1; i < tk.end; ++i) {
      const bvh_build_item<T>& it = items[i];
      box_lo = glm::min(box_lo, it.lo);
      box_hi = glm::max(box_hi, it.hi);
      c_lo = glm::min(c_lo, it.centre);
      c_hi = glm::max(c_hi, it.centre);
    }
    nodes[tk.node].bounds_min = box_lo;
    nodes[tk.node].bounds_max = box_hi;

    std::size_t mid = 0;  // 0: make a leaf
    if (count > 1) {
      const bool sah_allowed = tk.depth + 1 + bvh_median_levels(count, leaf_size) <= bvh_max_depth - 1;
      if (sah_allowed) {
        // Bin the centres along all three axes in one pass (an axis without extent is skipped).
        vec3<double> scale(0.0);
        for (int a = 0; a < 3; ++a) scale[a] = c_hi[a] > c_lo[a] ? double(bins) / (c_hi[a] - c_lo[a]) : 0.0;
        auto bin_of = [&](const bvh_build_item<T>& it, int a) {
          const int k = int((it.centre[a] - c_lo[a]) * scale[a]);
          return k < bins - 1 ? k : bins - 1;
        };
        for (bvh_bin<T>& b : bin) b.n = 0;
        for (std::size_t i = tk.begin; i < tk.end; ++i) {
          const bvh_build_item<T>& it = items[i];
          for (int a = 0; a < 3; ++a) {
            if (scale[a] == 0.0) continue;
            bvh_bin<T>& b = bin[std::size_t(a) * nbins + std::size_t(bin_of(it, a))];
            b.lo = b.n == 0 ? it.lo : glm::min(b.lo, it.lo);
            b.hi = b.n == 0 ? it.hi : glm::max(b.hi, it.hi);
            ++b.n;
          }
        }
        // Cost every split between two bins: sweep from the right, then from the left.
        const double node_area = bvh_half_area(box_lo, box_hi);
        double best_cost = 0.0;
        int best_axis = -1, best_bin = -1;
        for (int a = 0; a < 3; ++a) {
          if (scale[a] == 0.0) continue;
          const bvh_bin<T>* ab = &bin[std::size_t(a) * nbins];
          vec3<T> r_lo(T(0)), r_hi(T(0));
          std::size_t r_n = 0;
          for (std::size_t k = nbins - 1; k >= 1; --k) {  // right_*[k]: bins k .. bins - 1
            if (ab[k].n > 0) {
              r_lo = r_n == 0 ? ab[k].lo : glm::min(r_lo, ab[k].lo);
              r_hi = r_n == 0 ? ab[k].hi : glm::max(r_hi, ab[k].hi);
              r_n += ab[k].n;
            }
            right_n[k] = r_n;
            right_area[k] = r_n == 0 ? 0.0 : bvh_half_area(r_lo, r_hi);
          }
          vec3<T> l_lo(T(0)), l_hi(T(0));
          std::size_t l_n = 0;
          for (std::size_t k = 0; k + 1 < nbins; ++k) {  // split between bin k and bin k + 1
            if (ab[k].n > 0) {
              l_lo = l_n == 0 ? ab[k].lo : glm::min(l_lo, ab[k].lo);
              l_hi = l_n == 0 ? ab[k].hi : glm::max(l_hi, ab[k].hi);
              l_n += ab[k].n;
            }
            if (l_n == 0 || right_n[k + 1] == 0) continue;
            const double weighted = bvh_half_area(l_lo, l_hi) * double(l_n) + right_area[k + 1] * double(right_n[k + 1]);
            // A node of zero area (all its triangles at one point) has no SAH: count triangles.
            const double cost = p.traversal_cost + (node_area > 0.0 ? weighted / node_area : double(count));
            if (best_axis < 0 || cost < best_cost) {
              best_cost = cost;
              best_axis = a;
              best_bin = int(k);
            }
          }
        }
        if (best_axis >= 0 && (count > leaf_size || best_cost < double(count))) {
          std::size_t i = tk.begin, j = tk.end;
          while (i < j) {  // in-place partition: bins <= best_bin go left
            if (bin_of(items[i], best_axis) <= best_bin) {
              ++i;
            } else {
              --j;
              std::swap(items[i], items[j]);
            }
          }
          mid = i;
        }
      }
      if (mid == 0 && count > leaf_size) {
        // Object median along the widest axis of the centres, ordered by (centre, input index).
        const vec3<double> ext = c_hi - c_lo;
        const int a = ext.x >= ext.y ? (ext.x >= ext.z ? 0 : 2) : (ext.y >= ext.z ? 1 : 2);
        std::sort(items.begin() + std::ptrdiff_t(tk.begin), items.begin() + std::ptrdiff_t(tk.end),
                  [a](const bvh_build_item<T>& x, const bvh_build_item<T>& y) {
                    return x.centre[a] < y.centre[a] || (x.centre[a] == y.centre[a] && x.id < y.id);
                  });
        mid = tk.begin + (count + 1) / 2;
      }
    }
    if (mid == 0) {
      nodes[tk.node].first = std::uint32_t(tk.begin);
      nodes[tk.node].count = std::uint32_t(count);
      continue;
    }
    const auto left = std::uint32_t(nodes.size());
    nodes.push_back(bvh_node<T>{vec3<T>(T(0)), 0u, vec3<T>(T(0)), 0u});
    nodes.push_back(bvh_node<T>{vec3<T>(T(0)), 0u, vec3<T>(T(0)), 0u});
    nodes[tk.node].first = left;
    nodes[tk.node].count = 0u;
    work.push_back(task{left + 1, mid, tk.end, tk.depth + 1});
    work.push_back(task{left, tk.begin, mid, tk.depth + 1});  // the left subtree is built first
  }

  std::vector<bvh_triangle<T>> triangles(n);
  for (std::size_t s = 0; s < n; ++s) {
    const std::uint32_t t = items[s].id;
    triangles[s] = bvh_triangle<T>{vertex(t, 0), t, vertex(t, 1), 0u, vertex(t, 2), 0u};
  }
  return bvh<T>(std::move(nodes), std::move(triangles));
}

}  // namespace detail

// BVH over the index_count / 3 triangles of an indexed mesh. bvh_triangle::id is the triangle's
// position in `indices` divided by 3.
template <class T>
inline bvh<T> build_bvh(const vec3<T>* positions, std::size_t vertex_count, const std::uint32_t* indices,
                        std::size_t index_count, const bvh_build_params& params = bvh_build_params()) {
  validate_triangle_mesh(positions, vertex_count, indices, index_count, "build_bvh");
  detail::validate_bvh_build_params(params, "build_bvh");
  if (index_count / 3 > bvh_max_triangles)
    throw invalid_input("build_bvh: " + std::to_string(index_count / 3) + " triangles (at most 2^30)");
  return detail::build_bvh_core<T>(
      index_count / 3, [&](std::size_t t, int k) { return positions[indices[3 * t + std::size_t(k)]]; }, params);
}

// BVH over a triangle soup: triangle t has the vertices vertices[3t], vertices[3t + 1],
// vertices[3t + 2]; bvh_triangle::id is t.
template <class T>
inline bvh<T> build_bvh_soup(const vec3<T>* vertices, std::size_t triangle_count,
                             const bvh_build_params& params = bvh_build_params()) {
  if (triangle_count > 0 && vertices == nullptr) throw invalid_input("build_bvh_soup: null vertices");
  if (triangle_count > bvh_max_triangles)
    throw invalid_input("build_bvh_soup: " + std::to_string(triangle_count) + " triangles (at most 2^30)");
  detail::validate_bvh_build_params(params, "build_bvh_soup");
  for (std::size_t i = 0; i < 3 * triangle_count; ++i)
    if (!detail::bvh_vec3_finite(vertices[i]))
      throw invalid_input("build_bvh_soup: triangle " + std::to_string(i / 3) + " has a non-finite vertex (" +
                          std::to_string(i % 3) + ")");
  return detail::build_bvh_core<T>(
      triangle_count, [&](std::size_t t, int k) { return vertices[3 * t + std::size_t(k)]; }, params);
}

}  // namespace vplkit
