// SPDX-License-Identifier: MIT
#pragma once
// Polygon triangulation for OBJ faces. We load with tinyobjloader's triangulation off and split
// polygons here, after our index validation, so that every triangle of a polygon gets the
// polygon's own (Newell) normal as its flat normal, straight-line vertices leave no slivers, and a
// huge polygon costs O(n) (a fan) instead of O(n^3).
#include <glm/vec3.hpp>

#include <array>
#include <cstddef>
#include <vector>

namespace vplrender {

struct triangulation {
  std::vector<std::array<std::size_t, 3>> triangles;  // indices into the polygon, CCW about normal
  glm::dvec3 normal{0.0};  // unit Newell normal (the polygon's winding), zero if degenerate
  bool fan_fallback = false;  // the polygon was self-intersecting or very large and was fanned
};

// Ear clipping in the plane of the Newell normal; vertices on a straight line are dropped, not
// turned into zero-area triangles. Polygons with more than `max_ear_clip` vertices, or where no ear
// can be found (self-intersecting input), are fanned from their first remaining vertex. A polygon
// with a zero Newell normal (all collinear, or repeated points) yields no triangles.
triangulation triangulate_polygon(const std::vector<glm::dvec3>& poly, std::size_t max_ear_clip = 256);

}  // namespace vplrender
