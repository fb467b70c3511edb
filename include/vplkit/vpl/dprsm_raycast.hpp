// SPDX-License-Identifier: MIT
#pragma once
// Builds a DPRSM on the CPU by casting one ray per valid texel centre from the light: for tests
// and for hosts without a rasteriser. A rasterised DPRSM samples texel centres the same way.
#include <vplkit/core/error.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/paraboloid/paraboloid.hpp>
#include <vplkit/paraboloid/texel_grid.hpp>
#include <vplkit/vpl/dprsm_view.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace vplkit {

// What trace_fn reports for the first surface along a ray.
template <class T>
struct dprsm_hit {
  vec3<T> position;
  vec3<T> normal;  // the side facing the light for two-sided surfaces is the caller's choice
  vec3<T> albedo;
};

// Fills positions / normals / albedos (resized to 2 R^2) and returns a view of them.
// trace_fn(origin, dir) is called once per valid texel with origin = light.position and dir the
// world-space unit direction of the texel centre; it returns something that converts to bool
// (hit or not) and dereferences to an object with .position, .normal and .albedo, e.g.
// std::optional<dprsm_hit<T>>. Invalid texels and misses get zeros (albedo 0: no VPL).
// Throws invalid_input for a bad resolution or light, or when trace_fn returns non-finite data
// (dprsm_view::validate names the texel).
template <class T, class TraceFn>
inline dprsm_view<T> render_dprsm(const point_light<T>& light, int R, TraceFn&& trace_fn,
                                  std::vector<vec3<T>>& positions, std::vector<vec3<T>>& normals,
                                  std::vector<vec3<T>>& albedos) {
  if (R <= 0 || R > paraboloid_max_resolution)
    throw invalid_input("render_dprsm: resolution " + std::to_string(R) + " is not in [1, " +
                        std::to_string(paraboloid_max_resolution) + "]");
  dprsm_view<T> view;
  view.light = light;
  view.validate_light();  // before tracing 2 R^2 rays with a broken frame
  const std::size_t n = std::size_t(texel_count(R));
  positions.assign(n, vec3<T>(T(0)));
  normals.assign(n, vec3<T>(T(0)));
  albedos.assign(n, vec3<T>(T(0)));
  view.resolution = R;
  view.position = positions.data();
  view.normal = normals.data();
  view.albedo = albedos.data();
  for (int face = 0; face < 2; ++face)
    for (int y = 0; y < R; ++y)
      for (int x = 0; x < R; ++x) {
        if (!texel_is_valid(x, y, R)) continue;
        const vec3<T> d_light = paraboloid_to_direction(face, texel_center_uv<T>(x, y, R));
        const vec3<T> dir = light.frame.to_world(d_light);
        const auto hit = trace_fn(light.position, dir);
        if (!hit) continue;
        const std::size_t i = std::size_t(texel_index(face, x, y, R));
        positions[i] = hit->position;
        normals[i] = hit->normal;
        albedos[i] = hit->albedo;
      }
  view.validate();
  return view;
}

}  // namespace vplkit
