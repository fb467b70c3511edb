// SPDX-License-Identifier: MIT
#pragma once
// The C++ reference of the visibility decisions whose GLSL is `precise`: triangle_box_overlap's
// separating-axis projections and the DDA walk that dda_walk_leave_brick must reproduce bit for bit.
// A GPU honours `precise` (no FMA contraction), so the faithful C++ reference rounds every product,
// which is also what the library asks of a C++ build that wants these answers bit for bit
// (docs/math.md, "GPU arithmetic model": compile with -ffp-contract=off where the target has FMA).
// uncontracted_reference.cpp is compiled with -ffp-contract=off in every parity program that links
// it, the [fma] programs included (tests/parity/CMakeLists.txt), while the rest of an [fma] program
// contracts as freely as NVIDIA's compiler does outside `precise`.
#include <vplkit/core/vector.hpp>
#include <vplkit/visibility/dda.hpp>
#include <vplkit/visibility/voxel_grid.hpp>

namespace vplkit_test {

// vplkit::triangle_box_overlap<float>, evaluated without contraction.
bool uncontracted_triangle_box_overlap(vplkit::vec3<float> box_center, vplkit::vec3<float> box_half,
                                       vplkit::vec3<float> a, vplkit::vec3<float> b, vplkit::vec3<float> c);

// A walk after `steps` dda_walk_next calls, then one dda_walk_leave_brick (jump), and the same walk
// stepped on voxel by voxel until it leaves the brick it was in (step); without contraction.
struct uncontracted_brick_exit {
  vplkit::dda_walk<float> jump, step;
};
uncontracted_brick_exit uncontracted_leave_brick(const vplkit::voxel_grid<float>& g, vplkit::vec3<float> origin,
                                                 vplkit::vec3<float> dir, float t_max, int steps);

// a * b + c as the translation unit evaluates it: the test that the flag took effect (0 for the
// inputs of the test case "uncontracted reference: ...", 2^-24 when contracted).
float uncontracted_multiply_add(float a, float b, float c);

}  // namespace vplkit_test
