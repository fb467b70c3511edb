// SPDX-License-Identifier: MIT
// vplkit::gl::dispatch_linear: work-group ranges past GL_MAX_COMPUTE_WORK_GROUP_COUNT on x spread
// over y. GL guarantees only 65535 groups per axis (llvmpipe reports exactly that); a 2 x 2048^2
// DPRSM has 8.4M texels, 131072 groups of 64, and every --dprsm above 1448 used to fail on the GPU
// backend (global, local, gbg, mis). The end-to-end check at --dprsm 2048 is
// renderer_gpu_large_dprsm_test_slow.cpp.
#include "render/pipeline.hpp"

#include <headless_gl/compute.hpp>

#include <catch2/catch.hpp>

#include <cstdint>
#include <vector>

using namespace vplrender;
namespace gl = vplkit::gl;

TEST_CASE("split_groups keeps ranges that fit on x and spreads the others over y") {
  CHECK(gl::split_groups(1, 65535, 65535).x == 1);
  CHECK(gl::split_groups(0, 65535, 65535).x == 1);  // an empty range still dispatches one group
  const gl::group_grid fits = gl::split_groups(65535, 65535, 65535);
  CHECK((fits.x == 65535 && fits.y == 1));
  const gl::group_grid over = gl::split_groups(65536, 65535, 65535);
  CHECK((over.x == 65535 && over.y == 2));
  const gl::group_grid dprsm2048 = gl::split_groups(131072, 65535, 65535);
  CHECK((dprsm2048.x == 65535 && dprsm2048.y == 3));
  // Every group of the range exists, and no whole row of y is wasted.
  for (std::size_t groups : {7u, 100u, 101u, 9999u, 10000u, 10001u}) {
    const gl::group_grid g = gl::split_groups(groups, 100, 1000);
    CHECK(std::size_t(g.x) * g.y >= groups);
    CHECK(std::size_t(g.x) * (g.y - 1) < groups);
    CHECK(g.x <= 100);
  }
  CHECK_THROWS_WITH(gl::split_groups(100001, 100, 1000, "test kernel"),
                    Catch::Contains("test kernel: 100001 work groups exceed 100 x 1000"));
}

TEST_CASE("dispatch_linear reaches every group of a range past GL_MAX_COMPUTE_WORK_GROUP_COUNT on x") {
  pipeline_gl_context();
  const GLuint max_x = gl::max_work_group_count(0);
  REQUIRE(max_x >= 65535u);  // the GL 4.3 minimum
  // A range one past the axis limit plus a few (llvmpipe: 65535 + 5 groups of one invocation).
  // Drivers with 2^31 - 1 groups on x would need an 8 GiB buffer: there the helper is exercised
  // with a range that fits and the split itself is the pure test above.
  const std::size_t groups = max_x <= (1u << 22) ? std::size_t(max_x) + 5 : std::size_t(1) << 20;
  const gl::program prog = gl::program::compute(R"(#version 430
layout(local_size_x = 1) in;
layout(std430, binding = 0) buffer Out { uint hits[]; };
uniform uint u_groups;
void main() {
  uint g = gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x;
  if (g < u_groups) atomicAdd(hits[g], 1u);
})");
  gl::buffer out = gl::buffer::filled(groups * 4, 0);
  out.bind(0);
  prog.use();
  glUniform1ui(prog.uniform_location("u_groups"), static_cast<GLuint>(groups));
  gl::dispatch_linear(prog, groups);
  const std::vector<std::uint32_t> hits = out.read<std::uint32_t>(groups);
  std::size_t wrong = 0;
  for (std::uint32_t h : hits)
    if (h != 1u) ++wrong;
  INFO(groups << " groups, GL_MAX_COMPUTE_WORK_GROUP_COUNT x = " << max_x);
  CHECK(wrong == 0);
}
