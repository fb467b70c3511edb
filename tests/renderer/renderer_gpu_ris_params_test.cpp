// SPDX-License-Identifier: MIT
// --method ris's kernel interface (examples/vplrender/shaders/estimate_ris_params.h and the pack's
// vplkit/estimators/ris_params.h record) against the GL driver: in every pass of estimate_ris.comp
// the RIS parameters (the estimate block's member ris, the kernel's only uniform block) and the
// reservoir records lie where the C++ structs put them, at the bindings the headers name, and the
// estimate block keeps its layout (renderer_gpu_estimate_params_test).
#include "render/gpu/estimate_kernels.hpp"
#include "render/pipeline.hpp"

#include "estimate_params.h"
#include "estimate_ris_params.h"

#include <vplkit/estimators/ris_params.h>

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

GLuint ris_program(int pass, bool per_region) {
  pipeline_gl_context();
  std::string d = "#define VR_VISIBILITY 2\n#define VR_SPLIT 1\n#define VR_RIS_PASS " + std::to_string(pass) + "\n";
  if (per_region) d += "#define VR_RIS_PER_REGION\n";
  return gpu_kernel_program(gpu_kernel_for(method::ris).stages.front(), d).id();
}

}  // namespace

TEST_CASE("estimate_ris_params.h: the RIS parameters lie in the estimate block as in C++, the only block, in every pass") {
  using R = gpu::ris_params;
  const std::vector<member> members = {
      VR_MEMBER(R, candidates), VR_MEMBER(R, neighbours),     VR_MEMBER(R, radius),          VR_MEMBER(R, mis),
      VR_MEMBER(R, regions_x),  VR_MEMBER(R, regions_y),      VR_MEMBER(R, pool_size),       VR_MEMBER(R, pool_seed),
      VR_MEMBER(R, min_normal_cos), VR_MEMBER(R, max_plane_slope), VR_MEMBER(R, tile_block), VR_MEMBER(R, tile_guide_base),
      VR_MEMBER(R, tile_share_base), VR_MEMBER(R, pad1), VR_MEMBER(R, pad2), VR_MEMBER(R, pad3)};
  for (int pass : {ris_pass_estimate, ris_pass_candidates, ris_pass_reuse})
    for (bool per_region : {false, true}) {
      INFO("VR_RIS_PASS " << pass << (per_region ? " VR_RIS_PER_REGION" : ""));
      const GLuint prog = ris_program(pass, per_region);
      // The RIS parameters are the estimate block's member ris, and that block the kernel's only one.
      CHECK(vplkit_test::active_resources(prog, GL_UNIFORM_BLOCK) == 1);
      CHECK(resource_value(prog, GL_UNIFORM_BLOCK, "VrEstimateParams", GL_BUFFER_BINDING) ==
            VR_ESTIMATE_BINDING_PARAMS);
      for (const member& m : members) {
        INFO("vr_params.ris." << m.name);
        CHECK(std::size_t(resource_value(prog, GL_UNIFORM, "vr_params.ris." + m.name, GL_OFFSET)) ==
              offsetof(gpu::estimate_params, ris) + m.offset);
      }
      CHECK(std::size_t(resource_value(prog, GL_UNIFORM_BLOCK, "VrEstimateParams", GL_BUFFER_DATA_SIZE)) ==
            sizeof(gpu::estimate_params));
    }
}

TEST_CASE("estimate_ris_params.h: the reservoir records have the C++ layout in the passes that use them") {
  using Q = vplkit::gpu::ris_reservoir_record;
  const std::vector<member> members = {VR_MEMBER(Q, texel),  VR_MEMBER(Q, xi_x),       VR_MEMBER(Q, xi_y),
                                       VR_MEMBER(Q, weight_sum), VR_MEMBER(Q, target), VR_MEMBER(Q, confidence),
                                       VR_MEMBER(Q, pad0),   VR_MEMBER(Q, pad1)};
  for (int pass : {ris_pass_candidates, ris_pass_reuse}) {
    INFO("VR_RIS_PASS " << pass);
    const GLuint prog = ris_program(pass, false);
    CHECK(resource_value(prog, GL_SHADER_STORAGE_BLOCK, "VrRisReservoirs", GL_BUFFER_BINDING) ==
          VR_RIS_BINDING_RESERVOIRS);
    for (const member& m : members) {
      const std::string name = "vr_reservoirs[0]." + m.name;
      // The reuse pass never reads the padding: the driver may drop it from the active variables.
      if (m.name.rfind("pad", 0) == 0) continue;
      CHECK(std::size_t(resource_value(prog, GL_BUFFER_VARIABLE, name, GL_OFFSET)) == m.offset);
      CHECK(std::size_t(resource_value(prog, GL_BUFFER_VARIABLE, name, GL_TOP_LEVEL_ARRAY_STRIDE)) == sizeof(Q));
    }
  }
  // Without reuse the kernel has no reservoir buffer at all.
  const GLuint estimate = ris_program(ris_pass_estimate, false);
  CHECK(glGetProgramResourceIndex(estimate, GL_SHADER_STORAGE_BLOCK, "VrRisReservoirs") == GL_INVALID_INDEX);
}
