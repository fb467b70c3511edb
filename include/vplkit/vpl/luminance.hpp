// SPDX-License-Identifier: MIT
#pragma once
// Scalar weight of an RGB quantity (paper eq. 6; ITU-R BT.601 luma weights).
#include <vplkit/core/vector.hpp>

namespace vplkit {

template <class T>
inline T luminance(vec3<T> rgb) {
  return T(0.299) * rgb.x + T(0.587) * rgb.y + T(0.114) * rgb.z;
}

}  // namespace vplkit
