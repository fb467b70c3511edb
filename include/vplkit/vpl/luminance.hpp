// SPDX-License-Identifier: MIT
#pragma once
// Scalar weight of an RGB quantity (paper eq. 6; ITU-R BT.601 luma weights). A result below the
// smallest normal T is 0 (the normal-range contract, docs/math.md "GPU arithmetic model"); a GPU
// that flushes the denormal products of tiny channels may return up to 3 FLT_MIN less.
#include <vplkit/core/normal_range.hpp>
#include <vplkit/core/vector.hpp>

namespace vplkit {

template <class T>
inline T luminance(vec3<T> rgb) {
  return flush_denormal(T(0.299) * rgb.x + T(0.587) * rgb.y + T(0.114) * rgb.z);
}

}  // namespace vplkit
