// SPDX-License-Identifier: MIT
#pragma once
// The BVH queries under the tests' GPU model of float arithmetic (gpu_model_float.hpp): a built
// hierarchy's arrays with gpu_float coordinates (the same values), so that bvh_closest_hit and
// bvh_occluded run with T = gpu_float, e.g. under reciprocal_division_scope (NVIDIA's division).
#include <gpu_model_float.hpp>

#include <vplkit/core/vector.hpp>
#include <vplkit/visibility/bvh_build.hpp>
#include <vplkit/visibility/bvh_layout.hpp>

#include <vector>

namespace vplkit_test {

inline vplkit::vec3<gpu_float> to_gpu_model(vplkit::vec3<float> v) {
  return vplkit::vec3<gpu_float>(gpu_float(v.x), gpu_float(v.y), gpu_float(v.z));
}
inline vplkit::vec3<float> of_gpu_model(vplkit::vec3<gpu_float> v) {
  return vplkit::vec3<float>(float(v.x), float(v.y), float(v.z));
}

struct gpu_model_bvh {
  std::vector<vplkit::bvh_node<gpu_float>> nodes;
  std::vector<vplkit::bvh_triangle<gpu_float>> triangles;
  explicit gpu_model_bvh(const vplkit::bvh<float>& b) {
    for (const auto& n : b.nodes())
      nodes.push_back({to_gpu_model(n.bounds_min), n.first, to_gpu_model(n.bounds_max), n.count});
    for (const auto& t : b.triangles())
      triangles.push_back({to_gpu_model(t.v0), t.id, to_gpu_model(t.v1), t.unused1, to_gpu_model(t.v2), t.unused2});
  }
  vplkit::bvh_view<gpu_float> view() const {
    vplkit::bvh_view<gpu_float> v;
    v.nodes = nodes.data();
    v.node_count = nodes.size();
    v.triangles = triangles.data();
    v.triangle_count = triangles.size();
    return v;
  }
};

}  // namespace vplkit_test
