// SPDX-License-Identifier: MIT
#pragma once
// What builders and estimators know of the camera's visible points: a non-owning G-buffer view
// (the host renderer owns the image) and the result type of the host's ray-casting callable.
#include <vplkit/core/error.hpp>
#include <vplkit/core/unit_or_zero.hpp>
#include <vplkit/core/vector.hpp>

#include <cmath>
#include <string>

namespace vplkit {

template <class T>
struct gather_point {
  vec3<T> position;
  vec3<T> normal;  // need not be unit length; zero means "no surface" (background pixel)
  vec3<T> albedo;  // diffuse reflectance rho_x
  // The shading normal (e.g. interpolated vertex normals), on the geometric normal's side; zero
  // means "the same as normal". `normal` is the geometric normal: offsets, hemisphere tests and
  // visibility use it; only the receiver's cosine uses the shading normal (docs/math.md section 12).
  vec3<T> shading_normal{T(0)};
};

// The normal of the receiver's cosine: the shading normal, or the geometric one where none is set.
template <class T>
inline vec3<T> gather_point_shading_normal(const gather_point<T>& g) {
  const bool set = g.shading_normal.x != T(0) || g.shading_normal.y != T(0) || g.shading_normal.z != T(0);
  return set ? g.shading_normal : g.normal;
}

// True where the unit direction wd leaves x above its geometric surface. A receiver gets nothing
// from below it, whatever the shading normal says (decided with the cosine's own expression, so
// with one normal the test and the clamped cosine agree bit for bit).
template <class T>
inline bool gather_point_above(const gather_point<T>& g, vec3<T> wd) {
  return glm::dot(unit_or_zero(g.normal), wd) > T(0);
}

// Directions sampled in the shading normal's hemisphere that point below the geometric surface
// count as zero samples (docs/math.md section 12). With one normal the hemisphere sampled is the
// geometric one and nothing is rejected.
template <class T>
inline bool gather_point_accepts_direction(const gather_point<T>& g, vec3<T> wd) {
  const vec3<T> ns = gather_point_shading_normal(g);
  const bool one_normal = ns.x == g.normal.x && ns.y == g.normal.y && ns.z == g.normal.z;
  return one_normal || gather_point_above(g, wd);
}

// Background pixels (zero or non-finite normal) are skipped by every builder and estimator.
template <class T>
inline bool gather_point_valid(const gather_point<T>& g) {
  const T n2 = glm::dot(g.normal, g.normal);
  return n2 > T(0) && std::isfinite(n2) && std::isfinite(g.position.x) &&
         std::isfinite(g.position.y) && std::isfinite(g.position.z);
}

// Row-major width x height image of gather points (index = y * width + x), as three arrays the
// way a G-buffer read back from the GPU is laid out.
template <class T>
struct gbuffer_view {
  int width = 0;
  int height = 0;
  const vec3<T>* position = nullptr;
  const vec3<T>* normal = nullptr;
  const vec3<T>* albedo = nullptr;
  const vec3<T>* shading_normal = nullptr;  // optional: null = the geometric normals shade too

  int pixel_count() const { return width * height; }
  gather_point<T> at(int index) const {
    return gather_point<T>{position[index], normal[index], albedo[index],
                           shading_normal != nullptr ? shading_normal[index] : vec3<T>(T(0))};
  }
  gather_point<T> at(int x, int y) const { return at(y * width + x); }

  // Throws invalid_input for a bad size or null arrays. Non-finite entries are not an error:
  // such pixels are treated as background (gather_point_valid).
  void validate() const {
    if (width <= 0 || height <= 0 || width > (1 << 15) || height > (1 << 15))
      throw invalid_input("gbuffer_view: size " + std::to_string(width) + "x" + std::to_string(height) +
                          " is not in [1, 32768]^2");
    if (position == nullptr || normal == nullptr || albedo == nullptr)
      throw invalid_input("gbuffer_view: null position, normal or albedo array");
  }
};

// What a host's ray-casting callable returns: the first surface point along a ray, if any, and
// what the tracer knows of the surface there, with gather_point's conventions: `normal` the
// geometric normal (any length, either side; zero when the tracer cannot say, as the voxel-entry
// tracer), `shading_normal` the normal of the light's cosine (zero: the same as `normal`). With a
// normal the DPRSM look-up shades the hit as its own surface (dprsm_hit_radiance).
template <class T>
struct ray_hit {
  bool hit = false;
  vec3<T> position{T(0)};
  vec3<T> normal{T(0)};
  vec3<T> shading_normal{T(0)};
};

// Does the tracer say which surface it hit?
template <class T>
inline bool ray_hit_has_normal(const ray_hit<T>& h) {
  return h.normal.x != T(0) || h.normal.y != T(0) || h.normal.z != T(0);
}

// The hit's geometric normal turned to the side of point p (the light: the side it lights).
template <class T>
inline vec3<T> ray_hit_normal_towards(const ray_hit<T>& h, vec3<T> p) {
  return glm::dot(h.normal, p - h.position) < T(0) ? -h.normal : h.normal;
}

// The hit's shading normal on the side of n_g (its geometric normal turned as the caller needs),
// or n_g where none is set.
template <class T>
inline vec3<T> ray_hit_shading_normal(const ray_hit<T>& h, vec3<T> n_g) {
  const vec3<T> n_s = h.shading_normal;
  if (!(n_s.x != T(0) || n_s.y != T(0) || n_s.z != T(0))) return n_g;
  return glm::dot(n_s, n_g) < T(0) ? -n_s : n_s;
}

}  // namespace vplkit
