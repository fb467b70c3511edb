// SPDX-License-Identifier: MIT
// A consumer of vplkit (installed package, pkg-config, add_subdirectory with its own GLM, or
// FetchContent): the umbrella header, a distribution, the GLSL pack path, and a kernel's parameter
// header from the pack (every route puts the pack root on the include path).
#include <vplkit/builders/gbg_accumulate_params.h>
#include <vplkit/vplkit.hpp>

#if defined(EXPECT_PARENT_GLM) && !defined(PARENT_OWN_GLM)
#error "vplkit did not use the parent project's glm::glm target"
#endif
#if __cplusplus < 201703L
#error "vplkit::vplkit should have raised the language level to C++17"
#endif

#include <cstdio>
#include <fstream>
#include <vector>

int main() {
  const std::vector<double> weights = {0.0, 2.0, 0.0, 6.0};
  const vplkit::discrete_cdf<double> cdf(weights);
  const auto s = cdf.sample(0.5);
  if (s.index != 3 || s.pmf != 0.75) {
    std::fprintf(stderr, "unexpected sample %zu pmf %g\n", s.index, s.pmf);
    return 1;
  }
  vplkit::gpu::gbg_accumulate_params params{};
  params.light = vplkit::gpu::make_light_params(vplkit::make_point_light(vplkit::vec3<float>(0.0f),
                                                                         vplkit::vec3<float>(1.0f)));
  if (sizeof params != 208 || params.light.intensity.x != 1.0f || VPLKIT_GBG_BINDING_PARAMS != 5) {
    std::fprintf(stderr, "unexpected gbg_accumulate_params\n");
    return 1;
  }
  std::ifstream glsl(VPLKIT_GLSL_DIR "/vplkit/core/constants.glsl");
  if (!glsl) {
    std::fprintf(stderr, "installed GLSL pack not found under %s\n", VPLKIT_GLSL_DIR);
    return 1;
  }
  std::printf("vplkit consumer OK (%s)\n", VPLKIT_GLSL_DIR);
  return 0;
}
