// SPDX-License-Identifier: MIT
// Unit tests of the BVH builder (include/vplkit/visibility/bvh_build.hpp): the invariants of the
// flat arrays, checked here independently of validate_bvh; determinism to the byte; the depth
// limit on inputs that defeat the SAH; the SAH doing better than an object-median tree; input
// validation; validate_bvh rejecting corrupted arrays; and the closest hit against brute force.
#include <bvh_test_scenes.hpp>

#include <vplkit/visibility/bvh_build.hpp>
#include <vplkit/visibility/bvh_traverse.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <iostream>
#include <limits>
#include <vector>

namespace {

using vplkit_test::random_source;
using vplkit_test::tri_mesh;
using vplkit_test::v3d;
using vplkit_test::v3f;

vplkit::bvh<float> build(const tri_mesh& m, const vplkit::bvh_build_params& p = {}) {
  return vplkit::build_bvh(m.positions.data(), m.positions.size(), m.indices.data(), m.indices.size(), p);
}

bool inside(v3f lo, v3f hi, v3f p) {
  return p.x >= lo.x && p.y >= lo.y && p.z >= lo.z && p.x <= hi.x && p.y <= hi.y && p.z <= hi.z;
}

// The invariants, walked recursively from the root (the library's validate_bvh walks with a
// stack; this is a second, separate implementation). Returns the depth in levels.
int check_subtree(const vplkit::bvh<float>& b, const tri_mesh& m, std::uint32_t node, int depth, int max_leaf,
                  std::vector<int>& id_count, std::vector<int>& node_count) {
  REQUIRE(node < b.node_count());
  ++node_count[node];
  const auto& n = b.nodes()[node];
  if (n.count == 0) {
    REQUIRE(n.first >= 1);
    REQUIRE(n.first + 1 < b.node_count());
    int d = 0;
    for (std::uint32_t c = n.first; c <= n.first + 1; ++c) {
      const auto& ch = b.nodes()[c];
      CHECK(inside(n.bounds_min, n.bounds_max, ch.bounds_min));
      CHECK(inside(n.bounds_min, n.bounds_max, ch.bounds_max));
      d = std::max(d, check_subtree(b, m, c, depth + 1, max_leaf, id_count, node_count));
    }
    return d + 1;
  }
  CHECK(int(n.count) <= max_leaf);
  v3f lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
  for (std::uint32_t s = n.first; s < n.first + n.count; ++s) {
    REQUIRE(s < b.triangle_count());
    const auto& t = b.triangles()[s];
    REQUIRE(t.id < m.triangle_count());
    ++id_count[t.id];
    // The slot holds the input triangle's vertices, in input order.
    CHECK(std::memcmp(&t.v0, &m.positions[m.indices[3 * t.id]], sizeof(v3f)) == 0);
    CHECK(std::memcmp(&t.v1, &m.positions[m.indices[3 * t.id + 1]], sizeof(v3f)) == 0);
    CHECK(std::memcmp(&t.v2, &m.positions[m.indices[3 * t.id + 2]], sizeof(v3f)) == 0);
    CHECK(t.unused1 == 0u);
    CHECK(t.unused2 == 0u);
    for (v3f v : {t.v0, t.v1, t.v2}) {
      CHECK(inside(n.bounds_min, n.bounds_max, v));
      lo = glm::min(lo, v);
      hi = glm::max(hi, v);
    }
  }
  // The box is exactly the triangles' box, not merely a box around them.
  CHECK(lo == n.bounds_min);
  CHECK(hi == n.bounds_max);
  return 1;
}

void check_invariants(const vplkit::bvh<float>& b, const tri_mesh& m, int max_leaf = 4) {
  REQUIRE(b.triangle_count() == m.triangle_count());
  std::vector<int> id_count(m.triangle_count(), 0), node_count(b.node_count(), 0);
  const int depth = check_subtree(b, m, 0, 0, max_leaf, id_count, node_count);
  CHECK(depth == b.depth());
  CHECK(depth <= vplkit::bvh_max_depth);
  CHECK(std::count(id_count.begin(), id_count.end(), 1) == std::ptrdiff_t(m.triangle_count()));  // each in one leaf
  CHECK(std::count(node_count.begin(), node_count.end(), 1) == std::ptrdiff_t(b.node_count()));  // a tree
  CHECK(b.node_count() <= 2 * m.triangle_count() - 1);
}

std::vector<unsigned char> bytes_of(const vplkit::bvh<float>& b) {
  std::vector<unsigned char> out(b.node_count() * sizeof(vplkit::bvh_node<float>) +
                                 b.triangle_count() * sizeof(vplkit::bvh_triangle<float>));
  std::memcpy(out.data(), b.nodes().data(), b.node_count() * sizeof(vplkit::bvh_node<float>));
  std::memcpy(out.data() + b.node_count() * sizeof(vplkit::bvh_node<float>), b.triangles().data(),
              b.triangle_count() * sizeof(vplkit::bvh_triangle<float>));
  return out;
}

// Sum over nodes of area(node) / area(root) * (traversal_cost for inner nodes, count for leaves).
double sah_cost(const vplkit::bvh<float>& b) {
  auto area = [](v3f lo, v3f hi) {
    const v3d e = v3d(hi) - v3d(lo);
    return e.x * e.y + e.y * e.z + e.z * e.x;
  };
  const double root = area(b.nodes()[0].bounds_min, b.nodes()[0].bounds_max);
  double cost = 0.0;
  for (const auto& n : b.nodes()) cost += area(n.bounds_min, n.bounds_max) / root * (n.count == 0 ? 1.0 : double(n.count));
  return cost;
}

}  // namespace

TEST_CASE("bvh build: invariants on random soups, a closed room, and every parameter range") {
  random_source rnd(7);
  const std::vector<tri_mesh> meshes = {vplkit_test::random_soup(rnd, 3000, 1e-3, 0.2),
                                        vplkit_test::random_soup(rnd, 500, 0.05, 2.0), vplkit_test::closed_room()};
  for (const tri_mesh& m : meshes) {
    for (int leaf : {1, 4, 16})
      for (int bins : {2, 32, 256}) {
        vplkit::bvh_build_params p;
        p.max_leaf_size = leaf;
        p.bin_count = bins;
        p.traversal_cost = leaf == 16 ? 0.0 : 1.0;
        const auto b = build(m, p);
        INFO("triangles " << m.triangle_count() << " leaf " << leaf << " bins " << bins);
        check_invariants(b, m, leaf);
      }
  }
}

TEST_CASE("bvh build: the same input gives the same bytes (twice, copied input, soup vs indexed)") {
  random_source rnd(11);
  tri_mesh m = vplkit_test::random_soup(rnd, 2000, 1e-3, 0.3);
  // Shared vertices and repeated centres too: ties in the SAH and in the median sort.
  const tri_mesh room = vplkit_test::closed_room();
  for (std::size_t i = 0; i < room.indices.size(); ++i) m.indices.push_back(room.indices[i] + std::uint32_t(m.positions.size()));
  m.positions.insert(m.positions.end(), room.positions.begin(), room.positions.end());
  for (int k = 0; k < 40; ++k) m.tri(v3f(0.5f), v3f(0.5f), v3f(0.5f));  // 40 identical points

  const auto a = bytes_of(build(m));
  const tri_mesh copy = m;
  const auto b = bytes_of(build(copy));
  CHECK(a == b);
  std::vector<v3f> soup;
  for (std::size_t t = 0; t < m.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k) soup.push_back(m.vertex(t, k));
  const auto s = vplkit::build_bvh_soup(soup.data(), m.triangle_count());
  CHECK(a == bytes_of(s));
  // A different parameter set gives a different tree (the bytes do depend on the input).
  vplkit::bvh_build_params p;
  p.max_leaf_size = 2;
  CHECK(a != bytes_of(build(m, p)));
}

TEST_CASE("bvh build: the depth limit holds on inputs that make the SAH peel one triangle at a time") {
  // Triangle i has size 8^(i - 20) and lies at distance ~ its size from the origin: every box's
  // area is 64 times that of the box of all smaller triangles, so the SAH's best split always
  // cuts off the largest triangle alone, which would give a chain 40 levels deep.
  tri_mesh m;
  for (int i = 0; i < 40; ++i) {
    const double s = std::pow(8.0, i - 20);
    m.tri(v3f(float(s), 0.0f, 0.0f), v3f(float(s * 1.5), float(s * 0.5), 0.0f), v3f(float(s), float(s * 0.5), 0.0f));
  }
  vplkit::bvh_build_params p;
  p.max_leaf_size = 1;
  const auto b = build(m, p);
  check_invariants(b, m, 1);
  std::cout << "  chain of 40 triangles, leaf size 1: depth " << b.depth() << " (limit " << vplkit::bvh_max_depth << ")\n";
  CHECK(b.depth() == vplkit::bvh_max_depth);  // the limit binds here, and holds
  // Every triangle is still found: a ray straight up z through each centroid, from 1 below.
  int found = 0;
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    const v3d c = (v3d(m.vertex(t, 0)) + v3d(m.vertex(t, 1)) + v3d(m.vertex(t, 2))) / 3.0;
    const auto h = vplkit::bvh_closest_hit(b.view(), v3f(float(c.x), float(c.y), -1.0f), v3f(0.0f, 0.0f, 1.0f));
    found += h.hit && h.triangle == t;
  }
  CHECK(found == 40);
  // 4000 identical triangles: no centre differs, the object median alone builds the tree.
  tri_mesh same;
  for (int i = 0; i < 4000; ++i) same.tri(v3f(0, 0, 0), v3f(1, 0, 0), v3f(0, 1, 0));
  const auto bs = build(same);
  check_invariants(bs, same);
  CHECK(bs.depth() == 1 + vplkit::detail::bvh_median_levels(4000, 4));
}

namespace {

// An object-median tree over the same triangles (sorted by centroid on the widest axis, halved),
// in the same layout, for comparison.
vplkit::bvh<float> median_tree(const tri_mesh& m, std::size_t leaf) {
  std::vector<std::uint32_t> order(m.triangle_count());
  for (std::size_t t = 0; t < order.size(); ++t) order[t] = std::uint32_t(t);
  std::vector<vplkit::bvh_node<float>> nodes(1);
  auto centroid = [&](std::uint32_t t) { return (v3d(m.vertex(t, 0)) + v3d(m.vertex(t, 1)) + v3d(m.vertex(t, 2))) / 3.0; };
  std::function<void(std::size_t, std::size_t, std::size_t)> split = [&](std::size_t node, std::size_t begin, std::size_t end) {
    v3f lo(INFINITY), hi(-INFINITY);
    v3d clo(INFINITY), chi(-INFINITY);
    for (std::size_t i = begin; i < end; ++i)
      for (int k = 0; k < 3; ++k) {
        lo = glm::min(lo, m.vertex(order[i], k));
        hi = glm::max(hi, m.vertex(order[i], k));
        clo = glm::min(clo, centroid(order[i]));
        chi = glm::max(chi, centroid(order[i]));
      }
    nodes[node].bounds_min = lo;
    nodes[node].bounds_max = hi;
    if (end - begin <= leaf) {
      nodes[node].first = std::uint32_t(begin);
      nodes[node].count = std::uint32_t(end - begin);
      return;
    }
    const v3d e = chi - clo;
    const int a = e.x >= e.y ? (e.x >= e.z ? 0 : 2) : (e.y >= e.z ? 1 : 2);
    std::sort(order.begin() + std::ptrdiff_t(begin), order.begin() + std::ptrdiff_t(end),
              [&](std::uint32_t x, std::uint32_t y) { return centroid(x)[a] < centroid(y)[a]; });
    const auto first = std::uint32_t(nodes.size());
    nodes.resize(nodes.size() + 2);
    nodes[node].first = first;
    nodes[node].count = 0;
    const std::size_t mid = (begin + end + 1) / 2;
    split(first, begin, mid);
    split(first + 1, mid, end);
  };
  split(0, 0, order.size());
  std::vector<vplkit::bvh_triangle<float>> tris;
  for (std::uint32_t t : order) tris.push_back({m.vertex(t, 0), t, m.vertex(t, 1), 0u, m.vertex(t, 2), 0u});
  return vplkit::bvh<float>(nodes, tris);
}

}  // namespace

TEST_CASE("bvh build: SAH beats an object-median tree on a clustered scene") {
  // Three tight clusters far apart and a large floor: a median split cuts clusters in half.
  random_source rnd(3);
  tri_mesh m;
  for (int c = 0; c < 3; ++c) {
    const v3d centre(c * 10.0, 0.0, c * 3.0);
    for (int i = 0; i < 600; ++i) {
      const v3d p = centre + v3d(rnd.uniform(-0.5, 0.5), rnd.uniform(-0.5, 0.5), rnd.uniform(-0.5, 0.5));
      m.tri(v3f(p), v3f(p + 0.05 * rnd.direction()), v3f(p + 0.05 * rnd.direction()));
    }
  }
  m.grid(v3d(-5, -1, -5), v3d(40, 0, 0), v3d(0, 0, 16), 8);
  const auto sah = build(m);
  const auto median = median_tree(m, 4);
  const double c_sah = sah_cost(sah), c_median = sah_cost(median);
  std::cout << "  SAH cost (area-weighted triangle tests + inner nodes): binned SAH " << c_sah << ", object median "
            << c_median << "\n";
  CHECK(c_sah < 0.8 * c_median);
}

TEST_CASE("bvh build: bad input is rejected with a message naming it") {
  std::vector<v3f> p = {v3f(0, 0, 0), v3f(1, 0, 0), v3f(0, 1, 0)};
  std::vector<std::uint32_t> idx = {0, 1, 2, 0, 2, 5};
  CHECK_THROWS_WITH(vplkit::build_bvh(p.data(), p.size(), idx.data(), idx.size()),
                    Catch::Contains("triangle 1 uses vertex index 5"));
  idx.resize(4);
  CHECK_THROWS_WITH(vplkit::build_bvh(p.data(), p.size(), idx.data(), idx.size()), Catch::Contains("multiple of 3"));
  idx = {0, 1, 2};
  p[1].y = std::numeric_limits<float>::quiet_NaN();
  CHECK_THROWS_WITH(vplkit::build_bvh(p.data(), p.size(), idx.data(), idx.size()), Catch::Contains("non-finite vertex"));
  CHECK_THROWS_WITH(vplkit::build_bvh_soup(p.data(), 1), Catch::Contains("triangle 0 has a non-finite vertex (1)"));
  p[1].y = 0.0f;
  vplkit::bvh_build_params bad;
  bad.bin_count = 1;
  CHECK_THROWS_WITH(vplkit::build_bvh(p.data(), p.size(), idx.data(), idx.size(), bad), Catch::Contains("bin_count 1"));
  bad = {};
  bad.max_leaf_size = 17;
  CHECK_THROWS_WITH(vplkit::build_bvh(p.data(), p.size(), idx.data(), idx.size(), bad), Catch::Contains("max_leaf_size 17"));
  bad = {};
  bad.traversal_cost = std::numeric_limits<double>::infinity();
  CHECK_THROWS_WITH(vplkit::build_bvh(p.data(), p.size(), idx.data(), idx.size(), bad), Catch::Contains("traversal_cost"));
  CHECK_THROWS_WITH(vplkit::build_bvh_soup<float>(nullptr, 2), Catch::Contains("null vertices"));
  // Empty input is not an error.
  const auto e = vplkit::build_bvh<float>(nullptr, 0, nullptr, 0);
  CHECK(e.empty());
  CHECK(e.depth() == 0);
}

TEST_CASE("bvh build: validate_bvh rejects corrupted arrays, naming the node") {
  random_source rnd(5);
  const tri_mesh m = vplkit_test::random_soup(rnd, 200, 0.01, 0.1);
  const auto good = build(m);
  CHECK(vplkit::validate_bvh(good.view()) == good.depth());
  auto corrupt = [&](auto edit) {
    auto nodes = good.nodes();
    auto tris = good.triangles();
    edit(nodes, tris);
    return vplkit::bvh<float>(nodes, tris);
  };
  // The root's children: index 1 and 2.
  CHECK_THROWS_WITH(corrupt([](auto& n, auto&) { n[0].first = std::uint32_t(n.size()); }),
                    Catch::Contains("node 0 has children"));
  CHECK_THROWS_WITH(corrupt([](auto& n, auto&) { n[0].first = 0; }), Catch::Contains("node 0 has children"));
  CHECK_THROWS_WITH(corrupt([](auto& n, auto&) {  // two parents of one pair of children
                      for (auto& x : n) x.bounds_min = n[0].bounds_min, x.bounds_max = n[0].bounds_max;
                      REQUIRE((n[1].count == 0 && n[2].count == 0));
                      n[2].first = n[1].first;
                    }),
                    Catch::Contains("reached twice"));
  CHECK_THROWS_WITH(corrupt([](auto& n, auto&) {
                      for (auto& x : n)
                        if (x.count > 0) {
                          x.count = 17;
                          break;
                        }
                    }),
                    Catch::Contains("is a leaf of 17"));
  CHECK_THROWS_WITH(corrupt([](auto& n, auto&) { n[1].bounds_max.x += 1000.0f; }),
                    Catch::Contains("node 0: the box of child 1 is not inside it"));
  CHECK_THROWS_WITH(corrupt([](auto& n, auto&) { n[0].bounds_min.y = std::numeric_limits<float>::quiet_NaN(); }),
                    Catch::Contains("node 0 has a non-finite or inverted box"));
  CHECK_THROWS_WITH(corrupt([](auto&, auto& t) { t[3].id = t[4].id; }), Catch::Contains("out of range or repeated"));
  CHECK_THROWS_WITH(corrupt([](auto&, auto& t) { t[0].v1.z += 100.0f; }), Catch::Contains("outside the leaf's box"));
  CHECK_THROWS_WITH(corrupt([](auto& n, auto&) {  // two leaves share slots: one slot is in no leaf
                      for (auto& x : n)
                        if (x.count > 1) {
                          x.count -= 1;
                          break;
                        }
                    }),
                    Catch::Contains("triangle slots are in no leaf"));
  CHECK_THROWS_WITH(corrupt([](auto& n, auto&) { n.push_back(n.back()); }), Catch::Contains("not reachable"));
  CHECK_THROWS_WITH(vplkit::make_bvh_view<float>(nullptr, 0, good.triangles().data(), 4), Catch::Contains("no nodes"));
  // A chain: node 2d (d < L) is inner with children 2d + 1 (a leaf) and 2d + 2; the last node,
  // 2L, is a leaf at depth L. L = 32 is one level too deep; L = 31 is the deepest legal tree.
  auto chain = [](int L, std::vector<vplkit::bvh_node<float>>& nodes, std::vector<vplkit::bvh_triangle<float>>& tris) {
    nodes.clear();
    tris.clear();
    for (int d = 0; d < L; ++d) {
      nodes.push_back({v3f(0), std::uint32_t(2 * d + 1), v3f(1), 0u});
      nodes.push_back({v3f(0), std::uint32_t(d), v3f(1), 1u});
    }
    nodes.push_back({v3f(0), std::uint32_t(L), v3f(1), 1u});
    for (int d = 0; d <= L; ++d) tris.push_back({v3f(0), std::uint32_t(d), v3f(1, 0, 0), 0u, v3f(0, 1, 0), 0u});
  };
  std::vector<vplkit::bvh_node<float>> nodes;
  std::vector<vplkit::bvh_triangle<float>> tris;
  chain(vplkit::bvh_max_depth, nodes, tris);
  CHECK_THROWS_WITH(vplkit::make_bvh_view(nodes.data(), nodes.size(), tris.data(), tris.size()),
                    Catch::Contains("node 64 lies at depth 32"));
  chain(vplkit::bvh_max_depth - 1, nodes, tris);
  CHECK(vplkit::validate_bvh(vplkit::make_bvh_view(nodes.data(), nodes.size(), tris.data(), tris.size())) ==
        vplkit::bvh_max_depth);
}

TEST_CASE("bvh traversal: closest hit and occlusion equal brute force over every triangle") {
  random_source rnd(17);
  const tri_mesh m = vplkit_test::random_soup(rnd, 1500, 1e-3, 0.2);
  const auto b = build(m);
  std::size_t hits = 0, occluded_segments = 0;
  for (int i = 0; i < 3000; ++i) {
    const v3f o = rnd.point_in(v3d(-0.2), v3d(1.2));
    const v3f d = v3f(rnd.direction() * std::pow(10.0, rnd.uniform(-2.0, 2.0)));
    const float t_max = i % 3 == 0 ? float(rnd.uniform(0.0, 1.0) / std::sqrt(glm::dot(v3d(d), v3d(d)))) : INFINITY;
    const auto r = vplkit::make_bvh_ray(o, d);
    float best = t_max;
    std::uint32_t best_id = ~0u;
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
      const auto h = vplkit::bvh_ray_triangle(r, m.vertex(t, 0), m.vertex(t, 1), m.vertex(t, 2), 0.0f, best);
      if (h.hit && (best_id == ~0u || h.t < best)) {
        best = h.t;
        best_id = std::uint32_t(t);
      }
    }
    const auto h = vplkit::bvh_closest_hit(b.view(), o, d, 0.0f, t_max);
    REQUIRE(h.hit == (best_id != ~0u));
    hits += h.hit;
    if (h.hit) {
      // Same t bit for bit (the same test on the same triangles); the triangle may differ only
      // when two triangles are hit at exactly the same t.
      CHECK(h.t == best);
      if (h.triangle != best_id) {
        const auto o2 = vplkit::bvh_ray_triangle(r, m.vertex(h.triangle, 0), m.vertex(h.triangle, 1),
                                                 m.vertex(h.triangle, 2), 0.0f, t_max);
        CHECK(o2.t == best);
      }
    }
    const bool occ = vplkit::bvh_occluded(b.view(), o, d, 0.0f, t_max);
    CHECK(occ == (best_id != ~0u));
    occluded_segments += occ;
  }
  std::cout << "  3000 rays, " << hits << " hit; occlusion agrees on all (" << occluded_segments << " occluded)\n";
  CHECK(hits > 300);
  CHECK(hits < 2700);
}
