// SPDX-License-Identifier: MIT
#pragma once
// The scene's triangles in Embree 3 (Debian's libembree-dev), for the CPU backend's exact
// visibility (--visibility exact) and the exact method (--method exact): first hits and shadow
// segments against the triangles themselves, and what a hit needs to be shaded (the interpolated
// shading normal, the material's albedo). The visibility and tracing contract is the pack BVH's
// (include/vplkit/visibility/bvh_visibility.hpp, docs/math.md "Exact visibility"): ends moved off
// their surfaces along their normals by the same offset, the segment between them tested whole,
// so --visibility exact means the same on both backends.
#include "scene/scene.hpp"

#include <vplkit/core/gather_point.hpp>

#include <cstdint>
#include <limits>
#include <memory>

namespace vplrender {

class ray_scene {
 public:
  struct hit {
    bool hit = false;
    float t = 0.0f;              // along the ray, in units of |dir|
    std::uint32_t triangle = 0;  // index into scene::triangles
    float u = 0.0f, v = 0.0f;    // barycentric weights of corners 1 and 2
    vec3 position{0.0f};         // the barycentric point on the triangle (exact to rounding)
    vec3 geometric_normal{0.0f}; // unit, the triangle's winding side (not oriented to the ray)
  };

  // Copies what shading needs (triangles, materials, textures, camera) and builds a robust
  // (watertight) Embree scene. Throws std::runtime_error when Embree fails.
  explicit ray_scene(const scene& s);
  ~ray_scene();
  ray_scene(const ray_scene&) = delete;
  ray_scene& operator=(const ray_scene&) = delete;

  // Closest hit with t in [0, t_max].
  hit intersect(vec3 origin, vec3 dir, float t_max = std::numeric_limits<float>::infinity()) const;
  // Any hit with t in [0, t_max].
  bool occluded(vec3 origin, vec3 dir, float t_max) const;

  // How far segment ends and ray origins are moved off their surface: vplkit::bvh_surface_offset's
  // formula over the triangles' box (1e-4 of its size + 2^-15 of its largest |coordinate|).
  float surface_offset() const { return offset_; }
  // The largest extent of the triangles' box.
  float size() const { return size_; }

  // vplkit::bvh_visible's contract: are surface points x (normal n_x) and y (normal n_y) mutually
  // visible? Non-finite x or y: no.
  bool visible(vec3 x, vec3 n_x, vec3 y, vec3 n_y) const;
  // vplkit::bvh_trace's contract: the first hit of the ray leaving surface x (normal n_x) along dir,
  // with the triangle's geometric normal and the interpolated shading normal there. A finite reach
  // (world distance from x) stops the ray beyond it: every hit within reach of x still comes back.
  vplkit::ray_hit<float> trace(vec3 x, vec3 n_x, vec3 dir, float reach = std::numeric_limits<float>::infinity()) const;

  // The shading normal at a hit (corner normals interpolated, unit) and the albedo there (the
  // material's Kd or its texture at the interpolated uv, as the rasteriser shades it).
  vec3 shading_normal(const hit& h) const;
  vec3 albedo_at(const hit& h) const;

  std::size_t triangle_count() const { return source_.triangles.size(); }

 private:
  struct embree;
  scene source_;
  float offset_ = 0.0f;
  float size_ = 0.0f;
  std::unique_ptr<embree> rt_;
};

}  // namespace vplrender
