// SPDX-License-Identifier: MIT
// add_subdirectory(vplkit) users reach the kernels' parameter headers through vplkit::vplkit.
#include <vplkit/distribution/cdf_build_params.h>
#include <vplkit/visibility/voxelize_params.h>

int main() {
  vplkit::gpu::cdf_build_params p{};
  p.n = 16;
  p.pass = 1;
  vplkit::gpu::voxelize_params v{};
  v.triangle_count = 1;
  return p.n == 16 && v.triangle_count == 1 && VPLKIT_CDF_BUILD_BLOCK == 1024 ? 0 : 1;
}
