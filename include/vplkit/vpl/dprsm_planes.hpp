// SPDX-License-Identifier: MIT
#pragma once
// Builds the plane records (dprsm_plane.hpp) of every texel of a DPRSM, once per DPRSM and light:
// the C++ side of glsl/vplkit/vpl/dprsm_planes.comp. Point dprsm_view::planes at the result and
// the patch-sampled VPLs read one record per neighbour instead of a position, a normal and an
// albedo and a normalisation, with the same decisions and values as without it.
#include <vplkit/vpl/dprsm_plane.hpp>
#include <vplkit/vpl/dprsm_view.hpp>

#include <cstddef>
#include <vector>

namespace vplkit {

// records[t] = dprsm_plane_of(light, texel t) for every t < view.texel_count(); the view's own
// planes pointer is not read. Throws invalid_input for a view that fails validate().
template <class T>
inline std::vector<dprsm_plane<T>> build_dprsm_planes(const dprsm_view<T>& view) {
  view.validate();
  std::vector<dprsm_plane<T>> out(static_cast<std::size_t>(view.texel_count()));
  for (int t = 0; t < view.texel_count(); ++t)
    out[static_cast<std::size_t>(t)] =
        dprsm_plane_of(view.light.position, view.texel_valid(t), view.position[t], view.normal[t], view.albedo[t]);
  return out;
}

}  // namespace vplkit
