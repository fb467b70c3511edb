// SPDX-License-Identifier: MIT
#pragma once
// Splitting triangles before the paraboloid projection (docs/renderer.md, "DPRSM").
//
// The dual paraboloid map is a stereographic projection: a straight edge in 3D (an arc of a great
// circle seen from the light) becomes a circular arc of radius >= 1 in uv, but the rasteriser draws
// the straight chord between the projected corners. For an edge subtending the angle theta at the
// light, its uv length l is at most theta (du = (1 + r^2) / 2 dtheta <= dtheta on the unit disk),
// and the sagitta of the arc is at most l^2 / 8 <= theta^2 / 8. The rule: every OUTPUT edge
// subtends at most
//     theta_max = sqrt(2 / R)  (radians; R = DPRSM resolution per face),
// so the chord deviates from the true edge by at most 1/(4R) in uv: an eighth of a texel (2/R).
// R = 512: theta_max = 3.6 degrees.
//
// The bound is per sub-triangle, so the split is adaptive: an edge is halved at its midpoint while
// its angle exceeds theta_max (longest such edge of a triangle first, the triangle bisected
// through the opposite corner). Uniform n x n splitting of a whole triangle by its corner angles
// does not bound the angle of the sub-triangle nearest the light: a ceiling 0.1 above the light
// kept a sub-triangle spanning ~150 degrees around the light's zenith, whose corners all lay
// inside the rim margin of the other face, so its homogeneous interpolation wrapped over that
// face's pole and covered it with the ceiling (the DPRSM 2x8x8 all-zero gather image).
// The split decision depends on the edge's two end points only, and midpoints are computed
// symmetrically, so two triangles sharing an edge split it identically: no T-junction is created.
// An edge shorter than min_edge is never split (a surface through the light cannot be resolved),
// and a triangle bisected max_depth times is emitted as is; both are counted as capped.
#include "scene/scene.hpp"

#include <glm/vec3.hpp>

#include <cstddef>
#include <vector>

namespace vplrender {

struct tessellation_params {
  double max_angle = 0.0;  // radians; <= 0 disables tessellation (one sub-triangle per triangle)
  int max_depth = 48;      // bisections along any path from an input triangle
  double min_edge = 0.0;   // world length below which an edge is not split; <= 0: 1e-7 of the mesh's bounding diagonal
};

// The per-edge decision of the split: does the edge between the directions u and v from the light
// subtend more than max_angle, atan2(|u x v|, u . v) > max_angle? exceeds() gives exactly that
// decision, without the atan2 where the answer is clear (tessellate.cpp says why that is exact):
// most edges of a finely meshed scene are far below the angle, and the atan2 per edge was the
// split's largest cost.
struct edge_angle_test {
  explicit edge_angle_test(double max_angle);
  bool exceeds(const glm::dvec3& u, const glm::dvec3& v) const;
  // s = |u x v| and d = u . v known to give atan2(s, d) <= max_angle (false: not known).
  bool clearly_within(double s, double d) const;
  double max_angle;
  double tan_below;  // tan(max_angle) (1 - 1e-9) where the shortcut applies, else -1
};

// theta_max = sqrt(2 / R) (see above).
double tessellation_angle_for_resolution(int R);

struct tessellation_stats {
  std::size_t input = 0;
  std::size_t output = 0;
  std::size_t capped = 0;  // output triangles left with an edge over max_angle (min_edge or max_depth)
};

// 1e-7 of the bounding diagonal of the triangles' corners: the min_edge tessellate_for_light uses
// when params.min_edge <= 0.
double tessellation_min_edge(const std::vector<triangle>& tris);

// Sub-triangles with linearly interpolated normals (renormalised) and texcoords, same material and
// winding. The sub-triangles lie in the plane of their parent and tile it exactly. Each input
// triangle is split on its own (given min_edge), so the output of a list is the concatenation of
// its parts' outputs: tessellate_on_all_cores splits the work that way.
std::vector<triangle> tessellate_for_light(const std::vector<triangle>& tris, vec3 light,
                                           const tessellation_params& params,
                                           tessellation_stats* stats = nullptr);

// tessellate_for_light's split of the triangles [first, last), appended to out; stats' input and
// capped counts grow by this range's (output is left to the caller). params.min_edge is used as is:
// tessellate_for_light fixes it from the whole list first (<= 0 here: no edge is too short).
void tessellate_append(const triangle* first, const triangle* last, vec3 light, const tessellation_params& params,
                       std::vector<triangle>& out, tessellation_stats& stats);

// tessellate_for_light over the triangles in chunks on all cores, concatenated in order: the
// serial output, once min_edge is fixed from the whole mesh as the serial call fixes it. A moving
// light re-tessellates every frame (cornell at R = 512: 36 -> 22,742 triangles), which one core
// does in milliseconds. Rethrows what a chunk threw.
std::vector<triangle> tessellate_on_all_cores(const std::vector<triangle>& tris, vec3 light, tessellation_params params,
                                              tessellation_stats* stats = nullptr);

}  // namespace vplrender
