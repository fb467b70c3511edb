// SPDX-License-Identifier: MIT
#include "render/cpu/exact_estimator.hpp"

#include <vplkit/core/unit_or_zero.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/sampling/cosine_hemisphere.hpp>
#include <vplkit/sampling/orthonormal_basis.hpp>
#include <vplkit/visibility/bvh_visibility.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <glm/geometric.hpp>

namespace vplrender {

vec3 exact_sample(const ray_scene& rs, const vplkit::point_light<float>& light, const vplkit::gather_point<float>& gp,
                  vec3 n_g, vec3 dir) {
  const float cos_g = glm::dot(n_g, dir);
  const float cos_s = glm::dot(vplkit::unit_or_zero(vplkit::gather_point_shading_normal(gp)), dir);
  if (!(cos_g > 0.0f) || !(cos_s > 0.0f)) return vec3(0.0f);
  const float offset = rs.surface_offset();
  const ray_scene::hit h = rs.intersect(vplkit::bvh_offset_point(gp.position, n_g, offset), dir);
  if (!h.hit) return vec3(0.0f);
  // A hit on x's own plane (x on a crease, coincident surfaces) is where the lifted origin crossed
  // a surface that x sees edge-on: it sends x nothing (vplkit::vpl_point_on_plane, the gathering
  // estimators' rule), whichever of a crease's two triangles was rasterised at x's pixel.
  if (vplkit::vpl_point_on_plane(gp.position, h.position, h.geometric_normal)) return vec3(0.0f);
  // y's lit side is the one facing the light; seen from the other side it reflects nothing. The
  // side is x's, not the lifted origin's: where x lies a hair behind the plane of a surface it
  // meets at a junction, the lift can cross that plane and see the front that x does not
  // (dprsm_hit_radiance's test, the gathering estimators' convention).
  const vec3 y = h.position;
  vec3 n_gy = h.geometric_normal;
  if (glm::dot(n_gy, light.position - y) < 0.0f) n_gy = -n_gy;
  if (!(glm::dot(n_gy, gp.position - y) > 0.0f)) return vec3(0.0f);
  vec3 n_sy = rs.shading_normal(h);
  if (glm::dot(n_sy, n_gy) < 0.0f) n_sy = -n_sy;
  const vec3 l_o = vplkit::reflected_radiance(light.position, light.intensity, y, n_sy, rs.albedo_at(h));
  if (!(l_o.x > 0.0f || l_o.y > 0.0f || l_o.z > 0.0f)) return vec3(0.0f);
  const vec3 o = vplkit::bvh_offset_point(y, n_gy, offset);
  if (rs.occluded(o, light.position - o, 1.0f)) return vec3(0.0f);
  return vplkit::estimator_finite_or_zero(gp.albedo * l_o * (cos_s / cos_g));
}

vec3 estimate_exact(const ray_scene& rs, const vplkit::point_light<float>& light, const vplkit::gather_point<float>& gp,
                    vplkit::counter_rng& rng, int n_dirs) {
  if (!vplkit::gather_point_valid(gp) || n_dirs <= 0) return vec3(0.0f);
  const vec3 n_g = vplkit::unit_or_zero(gp.normal);
  const vplkit::orthonormal_basis<float> frame = vplkit::make_orthonormal_basis(n_g);
  vec3 sum(0.0f);
  for (int k = 0; k < n_dirs; ++k) {
    const float u0 = vplkit::rng_next_unit<float>(rng);
    const float u1 = vplkit::rng_next_unit<float>(rng);
    const vec3 local = vplkit::sample_cosine_hemisphere(vplkit::vec2<float>(u0, u1));
    sum += exact_sample(rs, light, gp, n_g, vplkit::to_world(frame, local));
  }
  return sum / float(n_dirs);
}

}  // namespace vplrender
