// SPDX-License-Identifier: MIT
#include "scene/framing.hpp"

#include "io/errors.hpp"
#include "scene/raycast.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace vplrender {

namespace {
constexpr double pi = 3.14159265358979323846;
}

camera auto_camera(const aabb& box, int width, int height, float vfov_deg) {
  camera c;
  c.vfov_deg = vfov_deg;
  const double half_v = 0.5 * static_cast<double>(vfov_deg) * pi / 180.0;
  const double aspect = static_cast<double>(width) / static_cast<double>(height);
  const double half_h = std::atan(aspect * std::tan(half_v));
  const double half = std::min(half_v, half_h);
  const double r = 0.5 * static_cast<double>(box.diagonal());
  const double d = r / std::sin(half);
  const glm::dvec3 centre(box.center());
  c.target = vec3(centre);
  c.eye = vec3(centre + glm::dvec3(0.0, 0.0, d));
  c.up = vec3(0.0f, 1.0f, 0.0f);
  return c;
}

namespace {

struct emitters {
  double area = 0.0;
  glm::dvec3 centroid{0.0}, normal{0.0}, ke_area{0.0};
};

emitters find_emitters(const scene& s) {
  emitters e;
  for (const triangle& t : s.triangles) {
    const material& m = s.materials[t.material];
    if (!(std::max({m.ke.x, m.ke.y, m.ke.z}) > 0.0f)) continue;
    const double a = 0.5 * triangle_double_area(t);
    if (!(a > 0.0)) continue;
    e.area += a;
    e.centroid += a * (glm::dvec3(t.p[0]) + glm::dvec3(t.p[1]) + glm::dvec3(t.p[2])) / 3.0;
    e.normal += a * glm::dvec3(facing_normal(t));
    e.ke_area += a * glm::dvec3(m.ke);
  }
  if (e.area > 0.0) e.centroid /= e.area;
  return e;
}

}  // namespace

vec3 auto_light_intensity(const scene& s) {
  const emitters e = find_emitters(s);
  if (e.area > 0.0) return vec3(e.ke_area / 4.0);
  const double diag = static_cast<double>(bounds(s).diagonal());
  return vec3(static_cast<float>(0.25 * diag * diag));
}

auto_light_result auto_light(const scene& s) {
  const aabb box = bounds(s);
  const double diag = static_cast<double>(box.diagonal());
  const double clearance = 0.01 * diag;
  auto_light_result r;
  r.light.intensity = auto_light_intensity(s);
  const emitters e = find_emitters(s);
  const std::string intensity_rule = e.area > 0.0 ? ", flux-matched to the emitters" : ", intensity (diagonal/2)^2";

  std::string fallback_reason;
  if (e.area > 0.0) {
    glm::dvec3 dir = e.normal;
    if (glm::length(dir) < 1e-6 * e.area) dir = glm::dvec3(box.center()) - e.centroid;  // e.g. a closed emitter
    const double len = glm::length(dir);
    const glm::dvec3 pos = len > 0.0 ? e.centroid + dir / len * clearance : e.centroid;
    if (classify_point(s.triangles, pos, 0.1 * clearance).kind == point_class::free) {
      r.light.position = vec3(pos);
      r.rule = "at the centroid of the emitters (MTL Ke)" + intensity_rule;
      return r;
    }
    fallback_reason = " (the emitter centroid is inside geometry)";
  }

  const double fractions[] = {0.75, 0.5, 0.875, 0.625, 0.375, 0.25, 0.125};
  const glm::dvec3 lo(box.lo), ext(box.extent()), mid(box.center());
  for (double f : fractions) {
    const glm::dvec3 pos(mid.x, lo.y + f * ext.y, mid.z);
    if (classify_point(s.triangles, pos, clearance).kind != point_class::free) continue;
    r.light.position = vec3(pos);
    std::ostringstream rule;
    rule << "free point on the vertical centre line at " << f << " of the box height" << fallback_reason
         << intensity_rule;
    r.rule = rule.str();
    return r;
  }
  throw input_error(s.name + ": could not place a light automatically (every candidate on the "
                             "vertical centre line is inside or next to geometry); set one with --light");
}

}  // namespace vplrender
