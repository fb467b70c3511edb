// A consumer of vplkit (installed package, pkg-config, add_subdirectory with its own GLM, or
// FetchContent): the umbrella header, a distribution, the GLSL pack path.
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
  std::ifstream glsl(VPLKIT_GLSL_DIR "/vplkit/core/constants.glsl");
  if (!glsl) {
    std::fprintf(stderr, "installed GLSL pack not found under %s\n", VPLKIT_GLSL_DIR);
    return 1;
  }
  std::printf("vplkit consumer OK (%s)\n", VPLKIT_GLSL_DIR);
  return 0;
}
