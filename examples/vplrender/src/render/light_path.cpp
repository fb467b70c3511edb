// SPDX-License-Identifier: MIT
#include "render/light_path.hpp"

#include <glm/vec3.hpp>

#include <cmath>
#include <sstream>

namespace vplrender {

vec3 light_path::at(int k) const {
  const double pi = 3.14159265358979323846;
  const double a = 2.0 * pi * static_cast<double>(k) / static_cast<double>(count > 0 ? count : 1);
  const double r = static_cast<double>(radius);
  const glm::dvec3 p = glm::dvec3(start) + glm::dvec3(r * (std::cos(a) - 1.0), 0.0, r * std::sin(a));
  return vec3(p);
}

std::string light_path::rule() const {
  std::ostringstream s;
  s.precision(9);
  s << "horizontal circle through the scene's light (" << start.x << ", " << start.y << ", " << start.z
    << "), radius " << radius << " (0.05 of the scene's diagonal), centre 'light - (radius, 0, 0)': frame k of "
    << count << " at light + radius (cos(2 pi k / " << count << ") - 1, 0, sin(2 pi k / " << count << "))";
  return s.str();
}

light_path make_light_path(const scene& s, int count) {
  light_path p;
  p.start = s.light.position;
  p.radius = static_cast<float>(0.05 * static_cast<double>(bounds(s).diagonal()));
  p.count = count > 0 ? count : 1;
  return p;
}

}  // namespace vplrender
