// SPDX-License-Identifier: MIT
#include "raster/dprsm_check.hpp"

#include "scene/raycast.hpp"
#include "scene/texture.hpp"

#include <vplkit/vpl/dprsm_raycast.hpp>

#include <glm/geometric.hpp>

#include <optional>

namespace vplrender {

dprsm_data raycast_dprsm(const scene& s, const vplkit::point_light<float>& light, int R) {
  dprsm_data d;
  d.resolution = R;
  d.light = light;
  // render_dprsm casts every ray from the light (origin = light.position).
  const rays_from_point from_light(s.triangles, glm::dvec3(light.position));
  auto trace = [&](vec3 origin, vec3 dir) -> std::optional<vplkit::dprsm_hit<float>> {
    const glm::dvec3 o(origin), w(dir);
    const ray_hit h = o == glm::dvec3(light.position) ? from_light.cast(w) : cast_ray(s.triangles, o, w);
    if (!h.hit) return std::nullopt;
    const triangle& t = s.triangles[h.triangle];
    const glm::dvec3 p = o + h.t * w;
    // Barycentrics of p in t (p lies in its plane up to rounding).
    const glm::dvec3 a(t.p[0]), b(t.p[1]), c(t.p[2]);
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double nn = glm::dot(n, n);
    double b1 = 0.0, b2 = 0.0;
    if (nn > 0.0) {
      b1 = glm::dot(glm::cross(p - a, c - a), n) / nn;
      b2 = glm::dot(glm::cross(b - a, p - a), n) / nn;
    }
    const double b0 = 1.0 - b1 - b2;
    glm::dvec3 sn = b0 * glm::dvec3(t.n[0]) + b1 * glm::dvec3(t.n[1]) + b2 * glm::dvec3(t.n[2]);
    const double l = glm::length(sn);
    sn = l > 0.0 ? sn / l : glm::dvec3(facing_normal(t));
    if (glm::dot(sn, o - p) < 0.0) sn = -sn;
    const glm::dvec2 uv = b0 * glm::dvec2(t.uv[0]) + b1 * glm::dvec2(t.uv[1]) + b2 * glm::dvec2(t.uv[2]);
    vplkit::dprsm_hit<float> r;
    r.position = vec3(p);
    r.normal = vec3(sn);
    r.albedo = albedo(s, s.materials[t.material], vec2(uv));
    return r;
  };
  vplkit::render_dprsm<float>(light, R, trace, d.position, d.normal, d.albedo);
  return d;
}

dprsm_difference compare_dprsm(const dprsm_data& a, const dprsm_data& b, double tolerance) {
  dprsm_difference r;
  const int R = a.resolution;
  for (int i = 0; i < 2 * R * R; ++i) {
    const glm::ivec2 xy = vplkit::texel_coords(i, R);
    if (!vplkit::texel_is_valid(xy.x, xy.y, R)) continue;
    ++r.valid_texels;
    const std::size_t k = static_cast<std::size_t>(i);
    const bool sa = a.albedo[k] != vec3(0.0f) || a.normal[k] != vec3(0.0f);
    const bool sb = b.albedo[k] != vec3(0.0f) || b.normal[k] != vec3(0.0f);
    if (sa != sb) {
      ++r.coverage_diff;
    } else if (sa && glm::length(glm::dvec3(a.position[k]) - glm::dvec3(b.position[k])) > tolerance) {
      ++r.position_diff;
    }
  }
  return r;
}

}  // namespace vplrender
