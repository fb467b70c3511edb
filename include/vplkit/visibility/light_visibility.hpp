// SPDX-License-Identifier: MIT
#pragma once
// Gathering's lit test by a shadow ray: a tracer may also say whether the point light reaches a
// surface point, in place of the DPRSM's shadow-map test (docs/math.md section 4.1, "An exact lit
// test"). The shadow map decides per texel, with one plane per texel: within a texel's cone it
// cannot see a shadow boundary, and it darkens the far side of every convex edge the texel's
// plane passes over (-1.6 % of sponza's one-bounce light at R = 128, -1.4 % at R = 512). A host
// with exact rays removes that bias with one shadow ray per lit hit.
//
// The protocol, which the gathering estimator and MIS check at compile time (a plain callable,
// such as a lambda or the voxel tracers, keeps the shadow map):
//   tracer.answers_light_visibility() -> bool   whether this tracer (now) has a shadow ray
//   tracer.light_visible(y, n_y, c)   -> bool   does the light at c reach surface point y, whose
//                                               geometric normal n_y faces c?
// tracer_with_light_visibility adds both to any tracer from any visibility callable (the light is
// a point without a surface: visibility(y, n_y, c, 0)). The GLSL mirror is the tracer's
// light_exact flag (visibility_callables.glsl).
#include <vplkit/core/gather_point.hpp>
#include <vplkit/core/vector.hpp>

#include <type_traits>
#include <utility>

namespace vplkit {

// Does Tracer offer light_visible (and answers_light_visibility) for vectors of T?
template <class Tracer, class T, class = void>
struct tracer_has_light_visibility : std::false_type {};
template <class Tracer, class T>
struct tracer_has_light_visibility<
    Tracer, T,
    std::void_t<decltype(bool(std::declval<const Tracer&>().light_visible(vec3<T>(), vec3<T>(), vec3<T>()))),
                decltype(bool(std::declval<const Tracer&>().answers_light_visibility()))>> : std::true_type {};

// Any tracer, with the lit test answered by a visibility callable (e.g. bvh_visibility).
template <class Tracer, class Visibility>
struct tracer_with_light_visibility {
  Tracer tracer;
  Visibility visibility;
  template <class T>
  ray_hit<T> operator()(vec3<T> x, vec3<T> n_x, vec3<T> dir) const {
    return tracer(x, n_x, dir);
  }
  // The wrapped tracer's short rays and near-surface test, where it has them (visibility_callables.hpp).
  template <class T, class Tr = Tracer>
  auto trace_within(vec3<T> x, vec3<T> n_x, vec3<T> dir, T reach) const
      -> decltype(std::declval<const Tr&>().trace_within(x, n_x, dir, reach)) {
    return tracer.trace_within(x, n_x, dir, reach);
  }
  template <class T, class Tr = Tracer>
  auto surface_within(vec3<T> x, vec3<T> n_x, T reach, T plane_tolerance) const
      -> decltype(std::declval<const Tr&>().surface_within(x, n_x, reach, plane_tolerance)) {
    return tracer.surface_within(x, n_x, reach, plane_tolerance);
  }
  bool answers_light_visibility() const { return true; }
  template <class T>
  bool light_visible(vec3<T> y, vec3<T> n_y, vec3<T> c) const {
    return visibility(y, n_y, c, vec3<T>(T(0)));
  }
};

template <class Tracer, class Visibility>
inline tracer_with_light_visibility<Tracer, Visibility> with_light_visibility(Tracer tracer, Visibility visibility) {
  return {std::move(tracer), std::move(visibility)};
}

}  // namespace vplkit
