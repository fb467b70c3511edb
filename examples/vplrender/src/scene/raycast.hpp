// SPDX-License-Identifier: MIT
#pragma once
// Brute-force ray casting against the scene triangles, in double precision. It serves setup-time
// questions (is the light inside a solid? is the box closed?), a few thousand rays at most, so
// O(triangles) per ray is fine and there is no acceleration structure to get wrong. Rays that all
// leave one point (classify_point, the ray-cast DPRSM) go through `rays_from_point`, which skips a
// triangle with one dot product where the ray cannot meet it and otherwise runs the same test.
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

// Rays that all leave `origin`: cast(dir, t_min) answers exactly what cast_ray(tris, origin, dir,
// t_min) answers (same hit, triangle, t and face, bit for bit; a negative t_min falls back to it). Each triangle is bounded once by the
// cone of directions from origin to its vertices; a ray outside a cone (by a margin of 1e-9 in its
// cosine, far above the test's rounding) cannot meet that triangle and is not tested against it.
// A cone of half-angle 90 degrees or more, or an origin within rounding of the triangle's plane
// (where the test's determinant is rounding noise), is never used to skip. On Sponza (292,256
// triangles) a ray from the light meets about 1 % of the cones.
class rays_from_point {
 public:
  rays_from_point(const std::vector<triangle>& tris, const glm::dvec3& origin);
  ray_hit cast(const glm::dvec3& dir, double t_min = 0.0) const;

 private:
  struct cone {
    glm::dvec3 axis{0.0};
    double cos_half = -2.0;  // below -1: every direction is tested
  };
  const std::vector<triangle>* tris_;
  glm::dvec3 origin_;
  std::vector<cone> cones_;
};

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
