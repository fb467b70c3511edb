#pragma once
// Splitting triangles before the paraboloid projection (docs/renderer.md, "DPRSM").
//
// The dual paraboloid map is a stereographic projection: a straight edge in 3D (an arc of a great
// circle seen from the light) becomes a circular arc of radius >= 1 in uv, but the rasteriser draws
// the straight chord between the projected corners. For an edge subtending the angle theta at the
// light, its uv length l is at most theta (du = (1 + r^2) / 2 dtheta <= dtheta on the unit disk),
// and the sagitta of the arc is at most l^2 / 8 <= theta^2 / 8. The rule: split every triangle
// into n^2 similar sub-triangles, n = ceil(max edge angle / theta_max), with
//     theta_max = sqrt(2 / R)  (radians; R = DPRSM resolution per face),
// so the chord deviates from the true edge by at most 1/(4R) in uv: an eighth of a texel (2/R).
// R = 512: theta_max = 3.6 degrees. n is capped (max_splits) so a huge triangle right next to the
// light cannot explode the mesh; the cap is reported.
#include "scene.hpp"

#include <cstddef>
#include <vector>

namespace vplrender {

struct tessellation_params {
  double max_angle = 0.0;  // radians; <= 0 disables tessellation (one sub-triangle per triangle)
  int max_splits = 64;     // n is clamped to [1, max_splits]
};

// theta_max = sqrt(2 / R) (see above).
double tessellation_angle_for_resolution(int R);

struct tessellation_stats {
  std::size_t input = 0;
  std::size_t output = 0;
  std::size_t capped = 0;  // triangles whose n hit max_splits
};

// Sub-triangles with barycentrically interpolated normals (renormalised) and texcoords, same
// material. The sub-triangles lie in the plane of their parent.
std::vector<triangle> tessellate_for_light(const std::vector<triangle>& tris, vec3 light,
                                           const tessellation_params& params,
                                           tessellation_stats* stats = nullptr);

}  // namespace vplrender
