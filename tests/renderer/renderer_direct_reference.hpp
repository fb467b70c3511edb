// SPDX-License-Identifier: MIT
#pragma once
// The direct light of the scene itself, for renderer tests that compare the DPRSM's shadow test
// against the truth (the camera ray's Embree hit, its normals, its albedo and an exact shadow ray),
// and the direct light a backend renders.
#include "renderer_gl_fixture.hpp"

#include "cli/render_options.hpp"
#include "render/cpu/cpu_backend.hpp"
#include "render/cpu/ray_scene.hpp"
#include "render/gpu/gpu_backend.hpp"
#include "scene/scene.hpp"

#include <vplkit/visibility/bvh_visibility.hpp>
#include <vplkit/vpl/direct_light.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace vplrender_test {

// The direct light at the surface point the camera sees through a G-buffer pixel, from the scene
// itself: Embree's hit on the ray from the eye through the G-buffer position, the triangle's normal
// turned to the eye, the interpolated shading normal turned to its side, the material's albedo and
// an exact shadow ray. 0 where the ray meets nothing near the G-buffer point.
inline vplrender::vec3 scene_direct_light(const vplrender::ray_scene& rs, const vplrender::scene& s,
                                          const vplkit::point_light<float>& light, vplrender::vec3 x) {
  using vplrender::vec3;
  const vec3 d = x - s.cam.eye;
  const float len = glm::length(d);
  const float slack = 1e-3f * rs.size();
  const vplrender::ray_scene::hit h = rs.intersect(s.cam.eye, d, 1.0f + slack / len);
  if (!h.hit || std::abs(h.t - 1.0f) * len > slack) return vec3(0.0f);
  vec3 ng = h.geometric_normal;
  if (glm::dot(ng, s.cam.eye - h.position) < 0.0f) ng = -ng;
  vec3 ns = rs.shading_normal(h);
  if (glm::dot(ns, ng) < 0.0f) ns = -ns;
  if (!(glm::dot(ng, light.position - h.position) > 0.0f)) return vec3(0.0f);
  const vec3 o = vplkit::bvh_offset_point(h.position, ng, rs.surface_offset());
  if (rs.occluded(o, light.position - o, 1.0f)) return vec3(0.0f);
  return vplkit::reflected_radiance(light.position, light.intensity, h.position, ns, rs.albedo_at(h));
}

// Direct light of a backend as the difference of --direct and plain renders of the deterministic
// global method (the same random numbers, so the indirect part cancels up to rounding).
inline vplrender::image_rgb direct_image(const gl_fixture& f, bool gpu) {
  using namespace vplrender;
  options o = f.o;
  o.meth = method::global;
  o.vpls = 1;
  render_settings es = make_render_settings(o, f.p.s);
  es.threads = 2;
  stage_timer t1, t2;
  es.direct = true;
  image_rgb with = gpu ? render_gpu(f.b, es, t1).image : render_cpu(f.b, es, t1).image;
  es.direct = false;
  const image_rgb without = gpu ? render_gpu(f.b, es, t2).image : render_cpu(f.b, es, t2).image;
  for (std::size_t i = 0; i < with.rgb.size(); ++i) with.rgb[i] = std::max(0.0f, with.rgb[i] - without.rgb[i]);
  return with;
}

}  // namespace vplrender_test
