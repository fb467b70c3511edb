// SPDX-License-Identifier: MIT
#include "raster/gpu_bvh.hpp"

#include <vplkit/visibility/bvh_build.hpp>

#include <algorithm>
#include <vector>

namespace vplrender {

gpu_bvh upload_scene_bvh(const scene& s) {
  std::vector<vec3> soup;
  soup.reserve(3 * s.triangles.size());
  for (const triangle& t : s.triangles) soup.insert(soup.end(), t.p.begin(), t.p.end());
  const vplkit::bvh<float> h = vplkit::build_bvh_soup(soup.data(), s.triangles.size());
  gpu_bvh g;
  g.node_count = static_cast<std::uint32_t>(h.node_count());
  g.triangle_count = static_cast<std::uint32_t>(h.triangle_count());
  g.depth = h.depth();
  std::vector<vplkit::bvh_node<float>> nodes = h.nodes();
  std::vector<vplkit::bvh_triangle<float>> tris = h.triangles();
  if (nodes.empty()) nodes.push_back(vplkit::bvh_node<float>{});
  if (tris.empty()) tris.push_back(vplkit::bvh_triangle<float>{});
  g.nodes = vplkit::gl::buffer::from_vector(nodes);
  g.triangles = vplkit::gl::buffer::from_vector(tris);
  g.query_cost = std::min<long long>(std::max<long long>(1, static_cast<long long>(g.node_count) + g.triangle_count), 1024);
  return g;
}

}  // namespace vplrender
