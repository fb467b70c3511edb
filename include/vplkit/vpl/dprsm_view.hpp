// SPDX-License-Identifier: MIT
#pragma once
// Non-owning view of a Dual Paraboloid Reflective Shadow Map: what every builder and estimator
// reads. Three arrays of texel_count(R) = 2 R^2 entries indexed as in paraboloid/texel_grid.hpp
// (index = face * R * R + y * R + x). A texel that saw no geometry has albedo 0 (and any finite
// position and normal, conventionally 0). Optionally a fourth array, the texels' plane records
// (dprsm_plane.hpp, built by build_dprsm_planes for this light), that plane_at reads instead of
// computing them.
#include <vplkit/core/error.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/paraboloid/light_frame.hpp>
#include <vplkit/paraboloid/paraboloid.hpp>
#include <vplkit/paraboloid/texel_grid.hpp>
#include <vplkit/vpl/dprsm_plane.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <cmath>
#include <string>

namespace vplkit {

template <class T>
struct point_light {
  vec3<T> position;      // c (world); must equal frame.position
  vec3<T> intensity;     // I_s, RGB W/sr
  light_frame<T> frame;  // light space of the DPRSM
};

// A point light whose DPRSM front paraboloid looks along front_axis (default +z).
template <class T>
inline point_light<T> make_point_light(vec3<T> position, vec3<T> intensity,
                                       vec3<T> front_axis = vec3<T>(T(0), T(0), T(1))) {
  return point_light<T>{position, intensity, light_frame<T>(position, front_axis)};
}

namespace detail {
template <class T>
inline bool dprsm_finite(vec3<T> v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
}  // namespace detail

template <class T>
struct dprsm_view {
  int resolution = 0;  // R: each face is R x R
  const vec3<T>* position = nullptr;
  const vec3<T>* normal = nullptr;
  const vec3<T>* albedo = nullptr;
  point_light<T> light{};
  // Optional: the plane records of these texels for this light (build_dprsm_planes); null: plane_at
  // computes them. Not checked by validate(): rebuild them whenever the arrays or the light change.
  const dprsm_plane<T>* planes = nullptr;

  int texel_count() const { return vplkit::texel_count(resolution); }

  // Inside the unit disk of its face (texel_is_valid); only these carry VPLs.
  bool texel_valid(int index) const {
    const ivec2 xy = texel_coords(index, resolution);
    return texel_is_valid(xy.x, xy.y, resolution);
  }

  T solid_angle(int index) const {
    const ivec2 xy = texel_coords(index, resolution);
    return texel_solid_angle<T>(xy.x, xy.y, resolution);
  }

  // The VPL of texel `index` (0 <= index < texel_count(); not checked: hot path).
  // flux = vpl_flux(albedo, I_s, texel_solid_angle), and 0 when the texel is invalid (solid
  // angle 0), saw nothing (albedo 0), or shows a surface facing away from the light
  // (vpl_cos_alpha(c, y, n) = 0): such a point receives no direct light, so it reflects none.
  // This keeps the VPL sum consistent with reflected_radiance, which clamps cos(alpha) at 0.
  vpl<T> vpl_at(int index) const {
    vpl<T> v;
    v.position = position[index];
    v.normal = normal[index];
    v.flux = vpl_flux(albedo[index], light.intensity, solid_angle(index));
    if (!(vpl_cos_alpha(light.position, v.position, v.normal) > T(0))) v.flux = vec3<T>(T(0));
    return v;
  }

  // The plane record of texel `index` (0 <= index < texel_count(); not checked): planes[index], or
  // dprsm_plane_of computed from the arrays (the same value).
  dprsm_plane<T> plane_at(int index) const {
    if (planes != nullptr) return planes[index];
    return dprsm_plane_of(light.position, texel_valid(index), position[index], normal[index], albedo[index]);
  }

  // Texel through which the light sees world direction `dir` (any length): the valid texel that
  // owns its uv (texel_owner_from_uv). Near the rim that is not always the texel containing uv:
  // the parts of invalid rim squares inside the disk belong to a valid neighbour, so every
  // direction is filed under exactly one texel that carries a VPL.
  int texel_of_direction(vec3<T> dir) const {
    const paraboloid_point<T> p = paraboloid_from_direction(light.frame.to_light(dir));
    const ivec2 xy = texel_owner_from_uv(p.uv, resolution);
    return texel_index(p.face, xy.x, xy.y, resolution);
  }

  // Texel through which the light sees world point p (the projection of the GBG builder; the
  // caller still compares p with position[index] to decide whether this texel saw p).
  int texel_of_point(vec3<T> p) const { return texel_of_direction(p - light.position); }

  // Throws invalid_input for a non-finite light position, a negative or non-finite intensity,
  // a frame not at the light or with non-finite axes.
  void validate_light() const {
    if (!detail::dprsm_finite(light.position))
      throw invalid_input("dprsm_view: light position is not finite");
    if (!detail::dprsm_finite(light.intensity) || light.intensity.x < T(0) ||
        light.intensity.y < T(0) || light.intensity.z < T(0))
      throw invalid_input("dprsm_view: light intensity is negative or not finite");
    if (light.frame.position != light.position)
      throw invalid_input("dprsm_view: light.frame.position differs from light.position");
    if (!detail::dprsm_finite(light.frame.axis_x) || !detail::dprsm_finite(light.frame.axis_y) ||
        !detail::dprsm_finite(light.frame.axis_z))
      throw invalid_input("dprsm_view: light frame axes are not finite");
  }

  // Throws invalid_input naming the first problem: non-positive or too large resolution, a null
  // array, the light (validate_light), or the first texel (flat index, face, x, y) with a
  // non-finite position / normal / albedo or a negative albedo.
  void validate() const {
    if (resolution <= 0 || resolution > paraboloid_max_resolution)
      throw invalid_input("dprsm_view: resolution " + std::to_string(resolution) +
                          " is not in [1, " + std::to_string(paraboloid_max_resolution) + "]");
    if (position == nullptr || normal == nullptr || albedo == nullptr)
      throw invalid_input("dprsm_view: null position, normal or albedo array");
    validate_light();
    const int n = texel_count();
    for (int i = 0; i < n; ++i) {
      const char* what = nullptr;
      if (!detail::dprsm_finite(position[i]))
        what = "a non-finite position";
      else if (!detail::dprsm_finite(normal[i]))
        what = "a non-finite normal";
      else if (!detail::dprsm_finite(albedo[i]))
        what = "a non-finite albedo";
      else if (albedo[i].x < T(0) || albedo[i].y < T(0) || albedo[i].z < T(0))
        what = "a negative albedo";
      if (what != nullptr) {
        const ivec2 xy = texel_coords(i, resolution);
        throw invalid_input("dprsm_view: texel " + std::to_string(i) + " (face " +
                            std::to_string(texel_face(i, resolution)) + ", x " +
                            std::to_string(xy.x) + ", y " + std::to_string(xy.y) + ") has " + what);
      }
    }
  }
};

}  // namespace vplkit
