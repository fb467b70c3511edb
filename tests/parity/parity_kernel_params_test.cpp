// SPDX-License-Identifier: MIT
// The kernels' parameter headers (glsl/vplkit/<area>/<kernel>_params.h) compile as C++ here and
// as GLSL inside each kernel; this test asks the GL driver where every member of each kernel's
// uniform block (and of cdf_build.comp's std430 records) lies, and checks that the C++ struct puts
// it at the same byte offset, with the same block size. A member added on one side only, or a
// padding mistake, fails here instead of corrupting a dispatch.
#include <parity_harness.hpp>

#include <vplkit/builders/gather_subset_params.h>
#include <vplkit/builders/gbg_accumulate_params.h>
#include <vplkit/builders/gbg_finish_params.h>
#include <vplkit/builders/flux_weights_params.h>
#include <vplkit/builders/tile_blocks_params.h>
#include <vplkit/builders/tile_weights_params.h>
#include <vplkit/builders/global_weights_params.h>
#include <vplkit/distribution/cdf_build_params.h>
#include <vplkit/distribution/share_tree_build_params.h>
#include <vplkit/image/median_fill_params.h>
#include <vplkit/vpl/dprsm_planes_params.h>
#include <vplkit/visibility/prefix_sum_params.h>
#include <vplkit/visibility/voxelize_params.h>
#include <vplkit/vpl/light_params.h>

#include <catch2/catch.hpp>

#include "gl_program_resources.hpp"

#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace {

namespace gl = vplkit::gl;
namespace gpu = vplkit::gpu;

// A member: its GLSL name below the block's struct variable, and its C++ offsetof.
using member = vplkit_test::block_member;
using vplkit_test::resource_value;

// The light's five members inside a struct at `base`.
std::vector<member> light_members(const std::string& prefix, std::size_t base) {
  return {{prefix + "position", base + offsetof(gpu::light_params, position)},
          {prefix + "intensity", base + offsetof(gpu::light_params, intensity)},
          {prefix + "axis_x", base + offsetof(gpu::light_params, axis_x)},
          {prefix + "axis_y", base + offsetof(gpu::light_params, axis_y)},
          {prefix + "axis_z", base + offsetof(gpu::light_params, axis_z)}};
}

// `defines` (#define lines) select a kernel's variant.
const gl::program& kernel(const std::string& file, const std::string& defines = {}) {
  vplkit::parity::context();
  static auto* cache = new std::map<std::string, gl::program>();  // lives with the context
  const std::string source = "#version 430\n" + defines + "#include \"" + file + "\"\n";
  auto it = cache->find(source);
  if (it == cache->end()) it = cache->emplace(source, gl::program::compute_with_includes(source, file)).first;
  return it->second;
}

// Every listed member at its C++ offset, and the block's size equal to the struct's.
void check_block(const std::string& file, const std::string& block, const std::string& variable,
                 std::size_t cpp_size, const std::vector<member>& members, const std::string& defines = {}) {
  const GLuint prog = kernel(file, defines).id();
  INFO(file << " " << defines << ": uniform block " << block);
  CHECK(std::size_t(resource_value(prog, GL_UNIFORM_BLOCK, block, GL_BUFFER_DATA_SIZE)) == cpp_size);
  GLint active = 0;
  const GLenum count_property = GL_NUM_ACTIVE_VARIABLES;
  glGetProgramResourceiv(prog, GL_UNIFORM_BLOCK, glGetProgramResourceIndex(prog, GL_UNIFORM_BLOCK, block.c_str()), 1,
                         &count_property, 1, nullptr, &active);
  CHECK(std::size_t(active) == members.size());  // std140: every member is active, none missed here
  for (const member& m : members) {
    INFO(variable << "." << m.name);
    CHECK(std::size_t(resource_value(prog, GL_UNIFORM, variable + "." + m.name, GL_OFFSET)) == m.offset);
  }
}

#define VPLKIT_MEMBER(type, field) member{#field, offsetof(type, field)}

}  // namespace

TEST_CASE("kernel parameters: every C++ params struct has its kernel's std140 layout") {
  check_block("vplkit/builders/gather_subset.comp", "vplkit_gather_subset_uniforms", "vplkit_gather_subset",
              sizeof(gpu::gather_subset_params),
              {VPLKIT_MEMBER(gpu::gather_subset_params, x0), VPLKIT_MEMBER(gpu::gather_subset_params, y0),
               VPLKIT_MEMBER(gpu::gather_subset_params, width), VPLKIT_MEMBER(gpu::gather_subset_params, height),
               VPLKIT_MEMBER(gpu::gather_subset_params, count), VPLKIT_MEMBER(gpu::gather_subset_params, columns),
               VPLKIT_MEMBER(gpu::gather_subset_params, rows), VPLKIT_MEMBER(gpu::gather_subset_params, last_columns),
               VPLKIT_MEMBER(gpu::gather_subset_params, seed), VPLKIT_MEMBER(gpu::gather_subset_params, stream_offset),
               VPLKIT_MEMBER(gpu::gather_subset_params, max_attempts),
               VPLKIT_MEMBER(gpu::gather_subset_params, out_offset),
               VPLKIT_MEMBER(gpu::gather_subset_params, image_width),
               VPLKIT_MEMBER(gpu::gather_subset_params, image_height), VPLKIT_MEMBER(gpu::gather_subset_params, pad0),
               VPLKIT_MEMBER(gpu::gather_subset_params, pad1)});

  std::vector<member> gw = light_members("light.", offsetof(gpu::global_weights_params, light));
  for (const member& m :
       {VPLKIT_MEMBER(gpu::global_weights_params, resolution), VPLKIT_MEMBER(gpu::global_weights_params, regions),
        VPLKIT_MEMBER(gpu::global_weights_params, pixel_count), VPLKIT_MEMBER(gpu::global_weights_params, pad0),
        VPLKIT_MEMBER(gpu::global_weights_params, dmin), VPLKIT_MEMBER(gpu::global_weights_params, pad1),
        VPLKIT_MEMBER(gpu::global_weights_params, pad2), VPLKIT_MEMBER(gpu::global_weights_params, pad3)})
    gw.push_back(m);
  check_block("vplkit/builders/global_weights.comp", "vplkit_global_weights_uniforms", "vplkit_global_weights",
              sizeof(gpu::global_weights_params), gw);

  std::vector<member> fw = light_members("light.", offsetof(gpu::flux_weights_params, light));
  for (const member& m :
       {VPLKIT_MEMBER(gpu::flux_weights_params, resolution), VPLKIT_MEMBER(gpu::flux_weights_params, pad0),
        VPLKIT_MEMBER(gpu::flux_weights_params, pad1), VPLKIT_MEMBER(gpu::flux_weights_params, pad2)})
    fw.push_back(m);
  check_block("vplkit/builders/flux_weights.comp", "vplkit_flux_weights_uniforms", "vplkit_flux_weights",
              sizeof(gpu::flux_weights_params), fw);

  std::vector<member> tbp = light_members("light.", offsetof(gpu::tile_blocks_params, light));
  for (const member& m :
       {VPLKIT_MEMBER(gpu::tile_blocks_params, resolution), VPLKIT_MEMBER(gpu::tile_blocks_params, block),
        VPLKIT_MEMBER(gpu::tile_blocks_params, pad0), VPLKIT_MEMBER(gpu::tile_blocks_params, pad1)})
    tbp.push_back(m);
  check_block("vplkit/builders/tile_blocks.comp", "vplkit_tile_blocks_uniforms", "vplkit_tile_blocks",
              sizeof(gpu::tile_blocks_params), tbp);
  check_block("vplkit/builders/tile_weights.comp", "vplkit_tile_weights_uniforms", "vplkit_tile_weights",
              sizeof(gpu::tile_weights_params),
              {VPLKIT_MEMBER(gpu::tile_weights_params, blocks), VPLKIT_MEMBER(gpu::tile_weights_params, tiles),
               VPLKIT_MEMBER(gpu::tile_weights_params, pixel_count), VPLKIT_MEMBER(gpu::tile_weights_params, dmin)});

  using acc = gpu::gbg_accumulate_params;
  std::vector<member> ga = light_members("light.", offsetof(acc, light));
  for (const member& m :
       {VPLKIT_MEMBER(acc, grid_min), VPLKIT_MEMBER(acc, grid_max), VPLKIT_MEMBER(acc, grid_resolution),
        VPLKIT_MEMBER(acc, width), VPLKIT_MEMBER(acc, height), VPLKIT_MEMBER(acc, resolution),
        VPLKIT_MEMBER(acc, n_dirs), VPLKIT_MEMBER(acc, accumulator), VPLKIT_MEMBER(acc, dir_begin),
        VPLKIT_MEMBER(acc, dir_end), VPLKIT_MEMBER(acc, count_gather_points), VPLKIT_MEMBER(acc, seed),
        VPLKIT_MEMBER(acc, bvh_node_count), VPLKIT_MEMBER(acc, pad1), VPLKIT_MEMBER(acc, pad2), VPLKIT_MEMBER(acc, dmin),
        VPLKIT_MEMBER(acc, depth_tolerance), VPLKIT_MEMBER(acc, offset_voxels), VPLKIT_MEMBER(acc, end_tolerance_voxels),
        VPLKIT_MEMBER(acc, scale), VPLKIT_MEMBER(acc, max_units), VPLKIT_MEMBER(acc, pad4), VPLKIT_MEMBER(acc, pad5)})
    ga.push_back(m);
  check_block("vplkit/builders/gbg_accumulate.comp", "vplkit_gbg_accumulate_uniforms", "vplkit_gbg_accumulate",
              sizeof(acc), ga);
  check_block("vplkit/builders/gbg_accumulate.comp", "vplkit_gbg_accumulate_uniforms", "vplkit_gbg_accumulate",
              sizeof(acc), ga, "#define VPLKIT_GBG_TRIANGLE_VOXELS\n");

  using fin = gpu::gbg_finish_params;
  std::vector<member> gf = light_members("light.", offsetof(fin, light));
  for (const member& m : {VPLKIT_MEMBER(fin, resolution), VPLKIT_MEMBER(fin, n_dirs), VPLKIT_MEMBER(fin, fill_holes),
                          VPLKIT_MEMBER(fin, pad0), VPLKIT_MEMBER(fin, inv_scale), VPLKIT_MEMBER(fin, pad1),
                          VPLKIT_MEMBER(fin, pad2), VPLKIT_MEMBER(fin, pad3)})
    gf.push_back(m);
  check_block("vplkit/builders/gbg_finish.comp", "vplkit_gbg_finish_uniforms", "vplkit_gbg_finish", sizeof(fin), gf);

  using planes = gpu::dprsm_planes_params;
  std::vector<member> dpl = light_members("light.", offsetof(planes, light));
  for (const member& m : {VPLKIT_MEMBER(planes, resolution), VPLKIT_MEMBER(planes, pad0), VPLKIT_MEMBER(planes, pad1),
                          VPLKIT_MEMBER(planes, pad2)})
    dpl.push_back(m);
  check_block("vplkit/vpl/dprsm_planes.comp", "vplkit_dprsm_planes_uniforms", "vplkit_dprsm_planes", sizeof(planes),
              dpl);

  check_block("vplkit/distribution/cdf_build.comp", "vplkit_cdf_build_uniforms", "vplkit_cdf_build",
              sizeof(gpu::cdf_build_params),
              {VPLKIT_MEMBER(gpu::cdf_build_params, n), VPLKIT_MEMBER(gpu::cdf_build_params, pass),
               VPLKIT_MEMBER(gpu::cdf_build_params, pad0), VPLKIT_MEMBER(gpu::cdf_build_params, pad1)});

  check_block("vplkit/distribution/share_tree_build.comp", "vplkit_share_tree_build_uniforms",
              "vplkit_share_tree_build", sizeof(gpu::share_tree_build_params),
              {VPLKIT_MEMBER(gpu::share_tree_build_params, n), VPLKIT_MEMBER(gpu::share_tree_build_params, leaves),
               VPLKIT_MEMBER(gpu::share_tree_build_params, level), VPLKIT_MEMBER(gpu::share_tree_build_params, pad0)});

  check_block("vplkit/image/median_fill.comp", "vplkit_median_fill_uniforms", "vplkit_median_fill",
              sizeof(gpu::median_fill_params),
              {VPLKIT_MEMBER(gpu::median_fill_params, resolution), VPLKIT_MEMBER(gpu::median_fill_params, pad0),
               VPLKIT_MEMBER(gpu::median_fill_params, pad1), VPLKIT_MEMBER(gpu::median_fill_params, pad2)});

  const std::vector<member> vx = {
      VPLKIT_MEMBER(gpu::voxelize_params, bounds_min),     VPLKIT_MEMBER(gpu::voxelize_params, bounds_max),
      VPLKIT_MEMBER(gpu::voxelize_params, resolution),     VPLKIT_MEMBER(gpu::voxelize_params, triangle_count),
      VPLKIT_MEMBER(gpu::voxelize_params, margin_voxels), VPLKIT_MEMBER(gpu::voxelize_params, pad0),
      VPLKIT_MEMBER(gpu::voxelize_params, pad1)};
  // Mode 0 the occupancy; 1 and 2 the triangle voxel grid's count and fill.
  for (int mode = 0; mode <= 2; ++mode)
    check_block("vplkit/visibility/voxelize.comp", "vplkit_voxelize_uniforms", "vplkit_voxelize",
                sizeof(gpu::voxelize_params), vx, "#define VPLKIT_VOXELIZE_MODE " + std::to_string(mode) + "\n");

  check_block("vplkit/visibility/prefix_sum.comp", "vplkit_prefix_sum_uniforms", "vplkit_prefix_sum",
              sizeof(gpu::prefix_sum_params),
              {VPLKIT_MEMBER(gpu::prefix_sum_params, count), VPLKIT_MEMBER(gpu::prefix_sum_params, begin),
               VPLKIT_MEMBER(gpu::prefix_sum_params, bit_count), VPLKIT_MEMBER(gpu::prefix_sum_params, write_total)});
}

TEST_CASE("kernel parameters: cdf_build.comp's std430 records have the C++ layout") {
  const GLuint prog = kernel("vplkit/distribution/cdf_build.comp").id();
  auto offset = [&](const std::string& name) {
    return std::size_t(resource_value(prog, GL_BUFFER_VARIABLE, name, GL_OFFSET));
  };
  auto stride = [&](const std::string& name) {
    return std::size_t(resource_value(prog, GL_BUFFER_VARIABLE, name, GL_TOP_LEVEL_ARRAY_STRIDE));
  };
  using block = gpu::cdf_build_block;
  using info = gpu::cdf_build_info;
  CHECK(stride("vplkit_cdf_build_blocks[0].sum") == sizeof(block));
  CHECK(offset("vplkit_cdf_build_blocks[0].sum") == offsetof(block, sum));
  CHECK(offset("vplkit_cdf_build_blocks[0].offset") == offsetof(block, offset));
  CHECK(offset("vplkit_cdf_build_blocks[0].max_bits") == offsetof(block, max_bits));
  CHECK(offset("vplkit_cdf_build_blocks[0].prefix_max_bits") == offsetof(block, prefix_max_bits));
  CHECK(offset("vplkit_cdf_build_blocks[0].zeroed") == offsetof(block, zeroed));
  CHECK(stride("vplkit_cdf_build_infos[0].sum") == sizeof(info));
  CHECK(offset("vplkit_cdf_build_infos[0].sum") == offsetof(info, sum));
  CHECK(offset("vplkit_cdf_build_infos[0].total") == offsetof(info, total));
  CHECK(offset("vplkit_cdf_build_infos[0].zeroed") == offsetof(info, zeroed));
}

TEST_CASE("kernel parameters: make_light_params packs a point light as the kernels unpack it") {
  const auto light = vplkit::make_point_light(vplkit::vec3<float>(1, 2, 3), vplkit::vec3<float>(4, 5, 6),
                                              vplkit::vec3<float>(0.3f, -0.2f, 0.9f));
  const gpu::light_params p = gpu::make_light_params(light);
  CHECK(vplkit::vec3<float>(p.position) == light.position);
  CHECK(vplkit::vec3<float>(p.intensity) == light.intensity);
  CHECK(vplkit::vec3<float>(p.axis_x) == light.frame.axis_x);
  CHECK(vplkit::vec3<float>(p.axis_y) == light.frame.axis_y);
  CHECK(vplkit::vec3<float>(p.axis_z) == light.frame.axis_z);
  CHECK(light.frame.position == light.position);  // the kernels use position for both
}
