// SPDX-License-Identifier: MIT
// Compiled with -ffp-contract=off (tests/parity/CMakeLists.txt; uncontracted_reference.hpp says why).
//
// Every function here is `flatten`ed: the library's inline templates are compiled into it under this
// translation unit's flags. Without that, the linker keeps one out-of-line copy of, say,
// dda_walk_next<float> for the whole program, and in an [fma] program that may be the contracting
// copy of the test's own translation unit (seen: the [fma] program failed as before).
#include <uncontracted_reference.hpp>

#include <vplkit/visibility/triangle_box_overlap.hpp>
#include <vplkit/visibility/voxel_bricks.hpp>

namespace vplkit_test {

#define VPLKIT_TEST_FLATTEN __attribute__((flatten))

VPLKIT_TEST_FLATTEN bool uncontracted_triangle_box_overlap(vplkit::vec3<float> box_center, vplkit::vec3<float> box_half,
                                       vplkit::vec3<float> a, vplkit::vec3<float> b, vplkit::vec3<float> c) {
  return vplkit::triangle_box_overlap(box_center, box_half, a, b, c);
}

VPLKIT_TEST_FLATTEN uncontracted_brick_exit uncontracted_leave_brick(const vplkit::voxel_grid<float>& g, vplkit::vec3<float> origin,
                                                 vplkit::vec3<float> dir, float t_max, int steps) {
  const auto v = g.view();
  vplkit::dda_walk<float> w = vplkit::dda_walk_begin(v, origin, dir, t_max);
  for (int k = 0; k < steps && w.running; ++k) vplkit::dda_walk_next(v, w);
  uncontracted_brick_exit out{w, w};
  if (out.jump.running) vplkit::dda_walk_leave_brick(v, out.jump);
  const vplkit::ivec3 brick = w.voxel / vplkit::voxel_brick_edge;
  while (out.step.running && out.step.voxel / vplkit::voxel_brick_edge == brick) vplkit::dda_walk_next(v, out.step);
  return out;
}

VPLKIT_TEST_FLATTEN float uncontracted_multiply_add(float a, float b, float c) { return a * b + c; }

#undef VPLKIT_TEST_FLATTEN

}  // namespace vplkit_test
