// SPDX-License-Identifier: MIT
#pragma once
// C++ twins of the GLSL std430 element types the GPU tests and benchmarks upload and read back
// (not part of the library). std430 has no vec3 array element of 12 bytes: a vec3 travels as a
// float4 whose w is free (a fourth value, or padding).
#include <vplkit/core/vector.hpp>

#include <cstdint>
#include <vector>

namespace vplkit_test {

struct float4 {
  float x, y, z, w;
  float operator[](int k) const { return k == 0 ? x : k == 1 ? y : k == 2 ? z : w; }
};
struct int4 {
  std::int32_t x, y, z, w;
  std::int32_t operator[](int k) const { return k == 0 ? x : k == 1 ? y : k == 2 ? z : w; }
};
static_assert(sizeof(float4) == 16 && sizeof(int4) == 16, "std430 vec4 / ivec4");

inline float4 f4(vplkit::vec3<float> v, float w = 0.0f) { return {v.x, v.y, v.z, w}; }
inline vplkit::vec3<float> xyz(const float4& v) { return vplkit::vec3<float>(v.x, v.y, v.z); }

// Surface samples as the kernels read them: position, normal, albedo of element i at 3 i, 3 i + 1,
// 3 i + 2 (a G-buffer, a DPRSM, gather points); a gather point's shading normal, when given, in
// the three .w (vplkit_unpack_gather_point), else 0 there.
inline std::vector<float4> surfels(const std::vector<vplkit::vec3<float>>& p, const std::vector<vplkit::vec3<float>>& n,
                                   const std::vector<vplkit::vec3<float>>& a,
                                   const std::vector<vplkit::vec3<float>>* shading = nullptr) {
  std::vector<float4> out;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const vplkit::vec3<float> s = shading != nullptr ? (*shading)[i] : vplkit::vec3<float>(0.0f);
    out.push_back(f4(p[i], s.x));
    out.push_back(f4(n[i], s.y));
    out.push_back(f4(a[i], s.z));
  }
  return out;
}

}  // namespace vplkit_test
