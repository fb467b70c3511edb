// A consumer of the installed package: the umbrella header, a distribution, the GLSL pack path.
#include <vplkit/vplkit.hpp>

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
  std::printf("find_package(vplkit) consumer OK\n");
  return 0;
}
