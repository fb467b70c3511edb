// SPDX-License-Identifier: MIT
#include "scene/scene.hpp"

#include "io/errors.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include <cmath>
#include <limits>
#include <sstream>

namespace vplrender {

namespace {

bool finite3(const vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

std::string str3(const vec3& v) {
  std::ostringstream s;
  s << "(" << v.x << ", " << v.y << ", " << v.z << ")";
  return s.str();
}

glm::dvec3 d3(const vec3& v) { return glm::dvec3(v); }

}  // namespace

float aabb::diagonal() const { return glm::length(hi - lo); }

aabb bounds(const std::vector<triangle>& triangles) {
  aabb b;
  if (triangles.empty()) return b;
  const float inf = std::numeric_limits<float>::infinity();
  b.lo = vec3(inf);
  b.hi = vec3(-inf);
  for (const triangle& t : triangles) {
    for (const vec3& p : t.p) {
      b.lo = glm::min(b.lo, p);
      b.hi = glm::max(b.hi, p);
    }
  }
  return b;
}

double triangle_double_area(const triangle& t) {
  const glm::dvec3 c = glm::cross(d3(t.p[1]) - d3(t.p[0]), d3(t.p[2]) - d3(t.p[0]));
  return glm::length(c);
}

vec3 facing_normal(const triangle& t) {
  const glm::dvec3 c = glm::cross(d3(t.p[1]) - d3(t.p[0]), d3(t.p[2]) - d3(t.p[0]));
  const double len = glm::length(c);
  if (!(len > 0.0) || !std::isfinite(len)) return vec3(0.0f);
  glm::dvec3 g = c / len;
  const glm::dvec3 shading = d3(t.n[0]) + d3(t.n[1]) + d3(t.n[2]);
  if (glm::dot(g, shading) < 0.0) g = -g;
  return vec3(g);
}

void validate_camera(const camera& c, const std::string& what) {
  if (!finite3(c.eye) || !finite3(c.target) || !finite3(c.up) || !std::isfinite(c.vfov_deg))
    throw input_error(what + ": camera has non-finite values");
  if (!(c.vfov_deg > 0.0f && c.vfov_deg < 180.0f))
    throw input_error(what + ": field of view " + std::to_string(c.vfov_deg) +
                      " degrees is outside (0, 180)");
  const glm::dvec3 f = d3(c.target) - d3(c.eye);
  const double fl = glm::length(f);
  if (!(fl > 0.0)) throw input_error(what + ": camera eye and target coincide at " + str3(c.eye));
  const double ul = glm::length(d3(c.up));
  if (!(ul > 0.0)) throw input_error(what + ": camera up vector is zero");
  // sin(angle between up and view) below ~1e-4 leaves no usable right vector.
  if (glm::length(glm::cross(f / fl, d3(c.up) / ul)) < 1e-4)
    throw input_error(what + ": camera up vector " + str3(c.up) + " is parallel to the view direction");
}

void validate_geometry(const scene& s) {
  const std::string& who = s.name;
  if (s.triangles.empty()) throw input_error(who + ": scene has no triangles");
  for (std::size_t i = 0; i < s.triangles.size(); ++i) {
    const triangle& t = s.triangles[i];
    const std::string at = who + ": triangle " + std::to_string(i);
    for (int k = 0; k < 3; ++k) {
      if (!finite3(t.p[k])) throw input_error(at + " has a non-finite position " + str3(t.p[k]));
      if (!finite3(t.n[k])) throw input_error(at + " has a non-finite normal " + str3(t.n[k]));
      if (std::abs(glm::length(t.n[k]) - 1.0f) > 1e-4f)
        throw input_error(at + " has a normal that is not unit: " + str3(t.n[k]));
      if (!std::isfinite(t.uv[k].x) || !std::isfinite(t.uv[k].y))
        throw input_error(at + " has a non-finite texture coordinate");
    }
    if (t.material >= s.materials.size())
      throw input_error(at + " uses material " + std::to_string(t.material) + " of " +
                        std::to_string(s.materials.size()));
  }
  for (std::size_t m = 0; m < s.materials.size(); ++m) {
    const material& mat = s.materials[m];
    if (!finite3(mat.kd) || glm::any(glm::lessThan(mat.kd, vec3(0.0f))) ||
        glm::any(glm::greaterThan(mat.kd, vec3(1.0f))))
      throw input_error(who + ": material '" + mat.name + "' has Kd " + str3(mat.kd) + " outside [0,1]");
    if (mat.texture >= static_cast<int>(s.textures.size()))
      throw input_error(who + ": material '" + mat.name + "' uses a missing texture");
  }
  for (const texture_rgb8& tex : s.textures) {
    if (tex.width <= 0 || tex.height <= 0 ||
        tex.texels.size() != static_cast<std::size_t>(tex.width) * static_cast<std::size_t>(tex.height) * 3u)
      throw input_error(tex.source + ": texture has inconsistent size");
  }
  const aabb b = bounds(s);
  if (!std::isfinite(b.diagonal()))
    throw input_error(who + ": scene bounds are not finite (coordinates too large)");
  if (b.lo == b.hi) throw input_error(who + ": degenerate scene: every vertex is at " + str3(b.lo));
  // Distinct vertices whose extent squares to 0 in float (coordinates near 1e-38 are denormal or
  // flush to zero): nothing downstream can resolve such a scene. Say so rather than call it a point.
  if (!(b.diagonal() > 1e-18f))
    throw input_error(who + ": the scene's extent " + str3(b.hi - b.lo) +
                      " is too small to render (coordinates this close to zero are denormal floats); scale the "
                      "model up (e.g. to metres)");
}

void validate_scene(const scene& s) {
  validate_geometry(s);
  const std::string& who = s.name;
  if (!finite3(s.light.position)) throw input_error(who + ": light position is not finite");
  if (!finite3(s.light.intensity) || glm::any(glm::lessThan(s.light.intensity, vec3(0.0f))))
    throw input_error(who + ": light intensity " + str3(s.light.intensity) + " must be finite and >= 0");
  validate_camera(s.cam, who);
}

}  // namespace vplrender
