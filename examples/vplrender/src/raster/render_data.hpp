// SPDX-License-Identifier: MIT
#pragma once
// What the rasterisation stages hand to the estimators: a G-buffer and a DPRSM, read back into
// CPU arrays in the layouts vplkit's views expect.
#include "scene/scene.hpp"

#include <vplkit/core/gather_point.hpp>
#include <vplkit/vpl/dprsm_view.hpp>

#include <vector>

namespace vplrender {

// width x height gather points, row 0 = TOP row (flipped from GL's bottom-up read-back), index
// y * width + x as vplkit::gbuffer_view wants. Background pixels: normal 0.
// `normal` is the geometric normal (the triangle's plane), unit and facing the camera (two-sided
// shading; docs/renderer.md); `shading_normal` the interpolated vertex normal, unit and on the
// geometric normal's side (equal to `normal` on flat triangles; docs/math.md section 12).
struct gbuffer_data {
  int width = 0, height = 0;
  std::vector<vec3> position, normal, albedo, shading_normal;
  vplkit::gbuffer_view<float> view() const {
    return vplkit::gbuffer_view<float>{width, height, position.data(), normal.data(), albedo.data(),
                                       shading_normal.size() == position.size() ? shading_normal.data() : nullptr};
  }
  std::size_t valid_count() const;
};

// 2 R^2 texels, index face * R * R + y * R + x (y along v, v = -1 at y = 0: GL's bottom-up rows
// are already in this order). Texels that saw nothing: albedo 0, position and normal 0. Normals
// face the light (a two-sided surface reflects from its lit side).
struct dprsm_data {
  int resolution = 0;
  vplkit::point_light<float> light{};
  std::vector<vec3> position, normal, albedo;
  vplkit::dprsm_view<float> view() const {
    vplkit::dprsm_view<float> v;
    v.resolution = resolution;
    v.position = position.data();
    v.normal = normal.data();
    v.albedo = albedo.data();
    v.light = light;
    return v;
  }
};

// The DPRSM's light: the scene light with the front paraboloid looking straight down (-Y): a
// light under a ceiling sees the room in the front map and the ceiling in the back one.
vplkit::point_light<float> dprsm_light(const scene& s);

}  // namespace vplrender
