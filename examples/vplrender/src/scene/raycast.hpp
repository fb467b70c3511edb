// SPDX-License-Identifier: MIT
#pragma once
// Brute-force ray casting against the scene triangles, in double precision. It serves setup-time
// questions (is the light inside a solid? is the box closed?), a few thousand rays at most, so
// O(triangles) per ray is fine and there is no acceleration structure to get wrong.
#include "scene/scene.hpp"

#include <cstddef>
#include <vector>

namespace vplrender {

struct ray_hit {
  bool hit = false;
  double t = 0.0;                // distance along the (unit) direction
  std::size_t triangle = 0;
  bool back_face = false;        // the ray met the side opposite to facing_normal()
};

// First hit with t > t_min. `dir` need not be unit; t is then in units of |dir|.
ray_hit cast_ray(const std::vector<triangle>& tris, const glm::dvec3& origin, const glm::dvec3& dir,
                 double t_min = 0.0);

// n directions spread evenly over the sphere (spherical Fibonacci lattice), unit length.
std::vector<glm::dvec3> sphere_directions(std::size_t n);

// Distance from p to triangle t (exact point-triangle distance).
double distance_to_triangle(const triangle& t, const glm::dvec3& p);

// Distance from p to the nearest triangle (exact point-triangle distance).
double distance_to_geometry(const std::vector<triangle>& tris, const glm::dvec3& p);

enum class point_class { free, inside_solid, on_surface };

struct point_classification {
  point_class kind = point_class::free;
  std::size_t rays = 0;        // rays cast
  std::size_t hits = 0;        // rays that hit something
  std::size_t back_hits = 0;   // hits whose first surface was a back face
  double nearest = 0.0;        // distance to the nearest triangle
};

// A point is inside a solid when most rays from it (>= 75% of those that hit anything) first
// meet a back face; on a surface when it lies within `surface_tolerance` of a triangle. This
// relies on authored facing (winding, or vn when present); with inconsistent winding it leans
// towards "free", never towards a false alarm on a well-modelled room.
point_classification classify_point(const std::vector<triangle>& tris, const glm::dvec3& p,
                                     double surface_tolerance, std::size_t rays = 256);

}  // namespace vplrender
