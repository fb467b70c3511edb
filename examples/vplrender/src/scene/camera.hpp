// SPDX-License-Identifier: MIT
#pragma once
// Pinhole camera geometry shared by the CPU and GPU paths: the same frame, the same pixel-centre
// convention, so a CPU pixel and a GPU pixel look along the same ray.
#include "scene/scene.hpp"

namespace vplrender {

struct camera_frame {
  vec3 eye{0.0f};
  vec3 forward{0.0f, 0.0f, -1.0f};  // unit, towards the target
  vec3 right{1.0f, 0.0f, 0.0f};     // unit
  vec3 up{0.0f, 1.0f, 0.0f};        // unit, orthogonal to forward and right
  float tan_half_vfov = 1.0f;
};

// Throws input_error (via validate_camera) for a degenerate camera.
camera_frame make_camera_frame(const camera& c);

// Direction (unit) through image position (x, y) in pixels of a width x height image: x to the
// right, y DOWN (row 0 is the top row, as in the written images); pixel (i, j) has its centre
// at (i + 0.5, j + 0.5). Square pixels: the horizontal fov follows from the aspect ratio.
vec3 primary_ray_direction(const camera_frame& f, int width, int height, float x, float y);

}  // namespace vplrender
