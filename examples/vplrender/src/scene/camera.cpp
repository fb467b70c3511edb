// SPDX-License-Identifier: MIT
#include "scene/camera.hpp"

#include <glm/geometric.hpp>

#include <cmath>

namespace vplrender {

camera_frame make_camera_frame(const camera& c) {
  validate_camera(c, "camera");
  camera_frame f;
  f.eye = c.eye;
  // Built in double: eye and target may be far apart relative to their difference.
  const glm::dvec3 fw = glm::normalize(glm::dvec3(c.target) - glm::dvec3(c.eye));
  const glm::dvec3 rt = glm::normalize(glm::cross(fw, glm::dvec3(c.up)));
  const glm::dvec3 up = glm::cross(rt, fw);
  f.forward = vec3(fw);
  f.right = vec3(rt);
  f.up = vec3(up);
  f.tan_half_vfov = static_cast<float>(std::tan(0.5 * static_cast<double>(c.vfov_deg) * 3.14159265358979323846 / 180.0));
  return f;
}

vec3 primary_ray_direction(const camera_frame& f, int width, int height, float x, float y) {
  const float aspect = static_cast<float>(width) / static_cast<float>(height);
  const float sx = (2.0f * x / static_cast<float>(width) - 1.0f) * aspect * f.tan_half_vfov;
  const float sy = (1.0f - 2.0f * y / static_cast<float>(height)) * f.tan_half_vfov;
  return glm::normalize(f.forward + sx * f.right + sy * f.up);
}

}  // namespace vplrender
