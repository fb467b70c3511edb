// SPDX-License-Identifier: MIT
// median_fill.comp and voxelize.comp on Vulkan (default bindings of their parameter headers)
// against the C++, with the bounds of the GL parity tests:
//  - median_fill.comp: BIT FOR BIT vplkit::median_fill_dprsm (the fill selects, it does no
//    arithmetic), R = 1, 2, 7, 32, 33, ~35 % holes, texels outside the disk included.
//  - voxelize.comp: vplkit::voxelize with the default margin. Exact inputs (voxel size 0.25,
//    triangles on voxel planes: no rounding anywhere) give the same grid; the synthetic scene's
//    room and random triangles may differ only in voxels whose overlap flips within 2e-5 voxel of
//    the margin, at most 8 of them (tests/parity/parity_visibility_test.cpp).
#include "vulkan_test_support.hpp"

#include "bvh_test_scenes.hpp"
#include "synthetic_scene.hpp"
#include "voxel_cells.hpp"

#include <vplkit/image/median_fill.hpp>
#include <vplkit/image/median_fill_params.h>
#include <vplkit/visibility/triangle_box_overlap.hpp>
#include <vplkit/visibility/voxel_grid.hpp>
#include <vplkit/visibility/voxelize.hpp>
#include <vplkit/visibility/voxelize_params.h>

#include <glm/vec4.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace vplkit::vk_test;
using v3f = vplkit::vec3<float>;
using v3d = vplkit::vec3<double>;
constexpr slot_kind S = slot_kind::storage;
constexpr slot_kind U = slot_kind::uniform;

}  // namespace

TEST_CASE("median_fill.comp on Vulkan: bit for bit the C++ median_fill_dprsm") {
  std::mt19937 g(7);
  with_vulkan([&](context& ctx) {
    const kernel k(ctx, "median_fill",
                   {{VPLKIT_MEDIAN_FILL_BINDING_IN, S}, {VPLKIT_MEDIAN_FILL_BINDING_OUT, S},
                    {VPLKIT_MEDIAN_FILL_BINDING_PARAMS, U}});
    for (int R : {1, 2, 7, 32, 33}) {
      std::vector<float> in(std::size_t(2 * R * R));
      std::size_t holes = 0;
      for (float& w : in) {
        const std::uint32_t r = g();
        // Holes, repeated values (ties in the median) and values spanning many magnitudes.
        w = r % 100 < 35 ? 0.0f : r % 7 == 0 ? 0.5f : std::ldexp(float(g() >> 8) * 0x1p-24f + 0.5f, int(g() % 40) - 20);
        holes += w == 0.0f;
      }
      vplkit::gpu::median_fill_params p{};
      p.resolution = R;
      const buffer ib = buffer::from_vector(ctx, in);
      const buffer ob(ctx, in.size() * 4, 0xFF);
      const buffer ub = buffer::from_bytes(ctx, &p, sizeof p);
      const std::uint32_t groups = groups_for(std::size_t(R), VPLKIT_MEDIAN_FILL_LOCAL_SIZE);
      run(ctx, k,
          {{VPLKIT_MEDIAN_FILL_BINDING_IN, &ib}, {VPLKIT_MEDIAN_FILL_BINDING_OUT, &ob},
           {VPLKIT_MEDIAN_FILL_BINDING_PARAMS, &ub}},
          groups, groups, 2);
      std::vector<float> cpu(in.size());
      vplkit::median_fill_dprsm(in.data(), cpu.data(), R);
      const std::vector<std::uint32_t> gpu_bits = bits_of(ob.read<float>()), cpu_bits = bits_of(cpu);
      std::size_t filled = 0;
      for (std::size_t i = 0; i < in.size(); ++i) filled += in[i] == 0.0f && cpu[i] != 0.0f;
      std::cout << "  median fill R = " << R << ": " << holes << " holes, " << filled << " filled\n";
      INFO("R = " << R << ", first differing texel " << first_difference(gpu_bits, cpu_bits));
      CHECK(gpu_bits == cpu_bits);
    }
  });
}

namespace {

using mesh = vplkit_test::tri_mesh;

std::vector<std::uint32_t> gpu_voxelize(context& ctx, const kernel& k, const vplkit::voxel_grid<float>& shape,
                                        const mesh& m, float margin) {
  std::vector<glm::vec4> positions;
  for (const v3f& p : m.positions) positions.emplace_back(p, 1.0f);
  const vplkit::gpu::voxelize_params p = vplkit_test::voxelize_block(shape, m.indices.size() / 3, margin);
  const buffer pb = buffer::from_vector(ctx, positions);
  const buffer ib = buffer::from_vector(ctx, m.indices);
  const buffer wb(ctx, shape.word_count() * 4, 0);
  const buffer ub = buffer::from_bytes(ctx, &p, sizeof p);
  run(ctx, k,
      {{VPLKIT_VOXELIZE_BINDING_POSITIONS, &pb}, {VPLKIT_VOXELIZE_BINDING_INDICES, &ib},
       {VPLKIT_VOXELIZE_BINDING_WORDS, &wb}, {VPLKIT_VOXELIZE_BINDING_PARAMS, &ub}},
      p.triangle_count);  // one work group per triangle (fewer than 65535 here)
  return wb.read<std::uint32_t>();
}

void check_voxelize(context& ctx, const kernel& k, const vplkit::voxel_grid<float>& shape, const mesh& m,
                    const std::string& what, std::size_t max_diff) {
  const double margin = vplkit::voxelize_default_margin;
  vplkit::voxel_grid<float> cpu(shape.bounds_min(), shape.bounds_max(), shape.resolution());
  vplkit::voxelize(cpu, m.positions.data(), m.positions.size(), m.indices.data(), m.indices.size(), margin);
  const std::vector<std::uint32_t> words = gpu_voxelize(ctx, k, shape, m, float(margin));
  REQUIRE(words.size() == cpu.word_count());
  const vplkit::voxel_grid<float> gpu(shape.bounds_min(), shape.bounds_max(), shape.resolution(), words);
  CHECK(words == gpu.words());  // no bit past the last voxel
  std::size_t differ = 0, far = 0;
  double worst = 0;
  const vplkit::ivec3 r = shape.resolution();
  for (int z = 0; z < r.z; ++z)
    for (int y = 0; y < r.y; ++y)
      for (int x = 0; x < r.x; ++x) {
        const vplkit::ivec3 c(x, y, z);
        if (gpu.test(c) == cpu.test(c)) continue;
        ++differ;
        const double off = std::fabs(vplkit_test::voxel_flip_margin(shape, m, c, 0.01) - margin);
        worst = std::max(worst, off);
        far += off > 2e-5;
      }
  std::cout << "  voxelize " << what << ": " << cpu.count() << " voxels (C++), " << gpu.count() << " (GPU), " << differ
            << " differ (bound " << max_diff << "), worst |flip margin - margin| " << worst << " voxel\n";
  CHECK(cpu.count() > 0);
  CHECK(differ <= max_diff);
  CHECK(far == 0u);
}

}  // namespace

TEST_CASE("voxelize.comp on Vulkan: the C++ voxelize grid") {
  with_vulkan([&](context& ctx) {
    const kernel k(ctx, "voxelize",
                   {{VPLKIT_VOXELIZE_BINDING_POSITIONS, S}, {VPLKIT_VOXELIZE_BINDING_INDICES, S},
                    {VPLKIT_VOXELIZE_BINDING_WORDS, S}, {VPLKIT_VOXELIZE_BINDING_PARAMS, U}});
    {
      // Exact inputs: voxel size 0.25, triangles on voxel planes with quarter-voxel vertices.
      const vplkit::voxel_grid<float> shape(v3f(-4.0f, 0.0f, 8.0f), v3f(4.0f, 4.0f, 16.0f), vplkit::ivec3(32, 16, 32));
      std::mt19937 g(31);
      mesh m;
      for (int i = 0; i < 300; ++i) {
        const int a = int(g() % 3), b = (a + 1) % 3, c = (a + 2) % 3;
        const v3f lo = shape.bounds_min();
        auto lattice = [&](int axis) {
          return lo[axis] + float(int(g() % std::uint32_t(4 * shape.resolution()[axis] + 9)) - 4) * 0.0625f;
        };
        const float plane = lo[a] + float(g() % std::uint32_t(shape.resolution()[a] + 1)) * 0.25f;
        v3f p[3];
        for (v3f& q : p) {
          q[a] = plane;
          q[b] = lattice(b);
          q[c] = lattice(c);
        }
        m.tri(p[0], p[1], p[2]);
      }
      check_voxelize(ctx, k, shape, m, "axis-aligned triangles on voxel planes", 0);
    }
    {
      const vplkit_test::synthetic_scene<float> scene;
      const vplkit::voxel_grid<float> shape = scene.make_voxel_grid(32);
      mesh m;
      m.positions = scene.positions;
      m.indices = scene.indices;
      check_voxelize(ctx, k, shape, m, "the synthetic scene, 32^3", 8);
    }
    {
      // Random triangles from tiny to grid-sized, in a grid with non-cubic voxels.
      const vplkit::voxel_grid<float> shape(v3f(-1.3f, 0.2f, 2.0f), v3f(2.1f, 3.0f, 4.5f), vplkit::ivec3(48, 40, 36));
      std::mt19937 g(21);
      auto uniform = [&](double a, double b) { return a + (b - a) * double(g() >> 5) * (1.0 / 134217728.0); };
      mesh m;
      for (int i = 0; i < 400; ++i) {
        const double size = i % 10 == 0 ? 3.0 : (i % 3 == 0 ? 0.02 : 0.25);
        const v3d base(uniform(-1.6, 2.4), uniform(-0.1, 3.3), uniform(1.7, 4.8));
        v3f p[3];
        for (v3f& q : p) q = v3f(base + size * v3d(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)));
        m.tri(p[0], p[1], p[2]);
      }
      check_voxelize(ctx, k, shape, m, "400 random triangles, 48x40x36", 8);
    }
  });
}
