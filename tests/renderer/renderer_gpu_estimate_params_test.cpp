// SPDX-License-Identifier: MIT
// The estimate kernels' parameter header (examples/vplrender/shaders/estimate_params.h) compiles as
// C++ here and as GLSL inside every kernel: the GL driver says where each member of the parameter
// block and of the std430 records lies in a compiled kernel, and the C++ struct must put it at the
// same byte offset, with the same block size and array stride (as tests/parity/
// parity_kernel_params_test.cpp does for the pack's kernels). A member added on one side only, or
// a padding mistake, fails here instead of corrupting a render.
#include "render/gpu/estimate_kernels.hpp"
#include "render/pipeline.hpp"

#include "estimate_params.h"

#include <headless_gl/compute.hpp>

#include <catch2/catch.hpp>

#include "gl_program_resources.hpp"

#include <cstddef>
#include <string>
#include <vector>

using namespace vplrender;
namespace gl = vplkit::gl;

namespace {

using member = vplkit_test::block_member;
using vplkit_test::resource_value;
#define VR_MEMBER VPLKIT_TEST_BLOCK_MEMBER

// A kernel's variant, compiled as the GPU backend compiles it.
GLuint program(method m, const std::string& defines) {
  pipeline_gl_context();
  return gpu_kernel_program(gpu_kernel_for(m).stages.front(), defines).id();
}

std::vector<member> ris_members() {
  using R = gpu::ris_params;
  return {VR_MEMBER(R, candidates), VR_MEMBER(R, neighbours),     VR_MEMBER(R, radius),          VR_MEMBER(R, mis),
          VR_MEMBER(R, regions_x),  VR_MEMBER(R, regions_y),      VR_MEMBER(R, pool_size),       VR_MEMBER(R, pool_seed),
          VR_MEMBER(R, min_normal_cos), VR_MEMBER(R, max_plane_slope), VR_MEMBER(R, tile_block), VR_MEMBER(R, tile_guide_base),
          VR_MEMBER(R, tile_share_base), VR_MEMBER(R, pad1), VR_MEMBER(R, pad2), VR_MEMBER(R, pad3)};
}

std::vector<member> params_members() {
  using P = gpu::estimate_params;
  std::vector<member> v = {
      {"light.position", offsetof(P, light) + offsetof(gpu::light_params, position)},
      {"light.intensity", offsetof(P, light) + offsetof(gpu::light_params, intensity)},
      {"light.axis_x", offsetof(P, light) + offsetof(gpu::light_params, axis_x)},
      {"light.axis_y", offsetof(P, light) + offsetof(gpu::light_params, axis_y)},
      {"light.axis_z", offsetof(P, light) + offsetof(gpu::light_params, axis_z)},
      VR_MEMBER(P, grid_min),       VR_MEMBER(P, grid_max),     VR_MEMBER(P, grid_resolution),
      VR_MEMBER(P, width),        VR_MEMBER(P, height),
      VR_MEMBER(P, resolution),     VR_MEMBER(P, n_dirs),       VR_MEMBER(P, n_vpls),
      VR_MEMBER(P, n_samples),      VR_MEMBER(P, n_distributions), VR_MEMBER(P, strata),
      VR_MEMBER(P, begin),          VR_MEMBER(P, end),          VR_MEMBER(P, first_pass),
      VR_MEMBER(P, last_pass),      VR_MEMBER(P, seed),         VR_MEMBER(P, bvh_node_count),
      VR_MEMBER(P, cdf_stride),     VR_MEMBER(P, guide_base),   VR_MEMBER(P, guide_stride),
      VR_MEMBER(P, pad0),           VR_MEMBER(P, pad1),         VR_MEMBER(P, pad2),
      VR_MEMBER(P, dmin),           VR_MEMBER(P, depth_tolerance), VR_MEMBER(P, surface_offset),
      VR_MEMBER(P, pad3),
      VR_MEMBER(P, clamp_dirs),     VR_MEMBER(P, clamp_first_unit), VR_MEMBER(P, clamp_max_groups_x),
      VR_MEMBER(P, clamp_pad1)};
  // The RIS kernels' parameters, nested as ris (estimate_ris_params.h): active in every kernel (std140).
  for (const member& m : ris_members()) v.push_back({"ris." + m.name, offsetof(P, ris) + m.offset});
  return v;
}

void check_params_block(GLuint prog) {
  CHECK(std::size_t(resource_value(prog, GL_UNIFORM_BLOCK, "VrEstimateParams", GL_BUFFER_DATA_SIZE)) ==
        sizeof(gpu::estimate_params));
  CHECK(resource_value(prog, GL_UNIFORM_BLOCK, "VrEstimateParams", GL_BUFFER_BINDING) == VR_ESTIMATE_BINDING_PARAMS);
  // The kernel's only uniform block (a second one read as zeros on the H200: estimate_ris_params.h).
  CHECK(vplkit_test::active_resources(prog, GL_UNIFORM_BLOCK) == 1);
  const std::vector<member> members = params_members();
  CHECK(std::size_t(resource_value(prog, GL_UNIFORM_BLOCK, "VrEstimateParams", GL_NUM_ACTIVE_VARIABLES)) ==
        members.size());  // std140: every member is active, none missed here
  for (const member& m : members) {
    INFO("vr_params." << m.name);
    CHECK(std::size_t(resource_value(prog, GL_UNIFORM, "vr_params." + m.name, GL_OFFSET)) == m.offset);
  }
}

// An std430 array of records: its stride, binding and each member's offset.
void check_records(GLuint prog, const std::string& block, int binding, const std::string& array, std::size_t size,
                   const std::vector<member>& members) {
  INFO(block);
  CHECK(resource_value(prog, GL_SHADER_STORAGE_BLOCK, block, GL_BUFFER_BINDING) == binding);
  for (const member& m : members) {
    const std::string name = array + "[0]." + m.name;
    CHECK(std::size_t(resource_value(prog, GL_BUFFER_VARIABLE, name, GL_OFFSET)) == m.offset);
    CHECK(std::size_t(resource_value(prog, GL_BUFFER_VARIABLE, name, GL_TOP_LEVEL_ARRAY_STRIDE)) == size);
  }
}

}  // namespace

TEST_CASE("estimate_params.h: the C++ parameter block has every kernel's std140 layout") {
  // One variant of every kernel (the block is the same text in all; each compiles it).
  CHECK(sizeof(gpu::estimate_params) == 304);
  for (method m : {method::reference, method::global, method::local, method::gather, method::mis, method::exact}) {
    INFO(to_string(m));
    check_params_block(program(m, "#define VR_VISIBILITY 2\n#define VR_SPLIT 1\n"));
  }
  // The kernels that add the clamp's compensation, with it.
  for (method m : {method::reference, method::global, method::local}) {
    INFO(to_string(m) << " with VR_CLAMP_COMPENSATION");
    check_params_block(program(m, "#define VR_VISIBILITY 2\n#define VR_SPLIT 1\n#define VR_VPL_MODE 1\n#define VR_CLAMP_COMPENSATION\n"));
  }
}

TEST_CASE("estimate_params.h: the C++ records have the kernels' std430 layout") {
  const GLuint split = program(method::global, "#define VR_VISIBILITY 2\n#define VR_SPLIT 1\n");
  check_records(split, "VrMixtures", VR_ESTIMATE_BINDING_MIXTURES, "vr_mixture_records", sizeof(gpu::mixture_record),
                {VR_MEMBER(gpu::mixture_record, learned), VR_MEMBER(gpu::mixture_record, fallback),
                 VR_MEMBER(gpu::mixture_record, mix)});
  check_records(split, "VrState", VR_ESTIMATE_BINDING_STATE, "vr_states", sizeof(gpu::pixel_state),
                {VR_MEMBER(gpu::pixel_state, sum), VR_MEMBER(gpu::pixel_state, comp), VR_MEMBER(gpu::pixel_state, rng)});
  const std::vector<member> surfel = {VR_MEMBER(gpu::surfel, position), VR_MEMBER(gpu::surfel, normal),
                                      VR_MEMBER(gpu::surfel, albedo)};
  check_records(split, "VrGbuffer", VR_ESTIMATE_BINDING_GBUFFER, "vr_gbuffer", sizeof(gpu::surfel), surfel);
  check_records(split, "VrDprsm", VR_ESTIMATE_BINDING_DPRSM, "vr_dprsm", sizeof(gpu::surfel), surfel);
  CHECK(resource_value(split, GL_SHADER_STORAGE_BLOCK, "VrOut", GL_BUFFER_BINDING) == VR_ESTIMATE_BINDING_OUT);
  CHECK(resource_value(split, GL_SHADER_STORAGE_BLOCK, "VrCdfData", GL_BUFFER_BINDING) == VR_ESTIMATE_BINDING_CDF_DATA);
  CHECK(resource_value(split, GL_SHADER_STORAGE_BLOCK, "VrVoxels", GL_BUFFER_BINDING) == VR_ESTIMATE_BINDING_VOXELS);
}

TEST_CASE("estimate_params.h: a one-dispatch variant has no state buffer, a split one has") {
  // VR_SPLIT 0: the pixel's state stays in registers (no storage round trip at all).
  const GLuint one = program(method::global, "#define VR_VISIBILITY 2\n#define VR_SPLIT 0\n");
  CHECK(glGetProgramResourceIndex(one, GL_SHADER_STORAGE_BLOCK, "VrState") == GL_INVALID_INDEX);
  const GLuint split = program(method::global, "#define VR_VISIBILITY 2\n#define VR_SPLIT 1\n");
  CHECK(glGetProgramResourceIndex(split, GL_SHADER_STORAGE_BLOCK, "VrState") != GL_INVALID_INDEX);
}
