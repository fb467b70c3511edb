// SPDX-License-Identifier: MIT
#pragma once
// Automatic camera and light for a scene that brings neither (an OBJ file). The rules are in
// docs/renderer.md; both results can be overridden with --camera and --light.
#include "scene/scene.hpp"

#include <string>

namespace vplrender {

// Looks along -Z (OBJ's habit: +Y up, the front faces +Z) at the centre of the box, from far
// enough that the bounding sphere fits in both the vertical and the horizontal field of view.
// The eye is therefore always outside the bounding box, never inside geometry.
camera auto_camera(const aabb& box, int width, int height, float vfov_deg = 45.0f);

struct auto_light_result {
  point_light light;
  std::string rule;  // which rule placed it, for the summary and the JSON report
};

// Intensity: with emissive materials (MTL Ke > 0) the one that emits the same total flux,
// I = sum(Ke * area) / 4 (Phi = pi * sum(Ke A) for one-sided Lambertian emitters, an isotropic
// point emits Phi = 4 pi I); otherwise I = (diagonal / 2)^2 per channel (irradiance 1 at half the
// diagonal, so previews need no exposure change with scene scale).
vec3 auto_light_intensity(const scene& s);

// Position:
// 1. with emitters, their area-weighted centroid moved 1% of the scene diagonal along their mean
//    facing normal, if that point is free (classify_point);
// 2. otherwise the first of the heights 3/4, 1/2, 7/8, 5/8, 3/8, 1/4, 1/8 of the box, on the
//    vertical line through its centre, that is free and at least 1% of the diagonal from any
//    triangle.
// Throws input_error if no candidate is free.
auto_light_result auto_light(const scene& s);

}  // namespace vplrender
