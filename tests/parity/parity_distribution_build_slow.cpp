// SPDX-License-Identifier: MIT
// cdf_build.comp at 2^24 and more weights (docs/math.md section 10: "2^24+ equal weights"), label
// `slow`: the block offsets and prefix maxima then span several chunks of passes 2 and 4 with the
// default block size (2^24 / 1024 = 16384 blocks, 17 chunks), and a float CDF can no longer resolve
// every step (n > 2^24). Same checks and bounds as parity_distribution_build_test.cpp.
#include <parity_distribution_support.hpp>

#include <vplkit/distribution/discrete_cdf.hpp>

#include <vector>

using namespace vplkit::parity;
using namespace vplkit::parity::dist;

namespace {

void check_large(const std::string& name, const std::vector<float>& w, bool float_float) {
  const u32 n = u32(w.size());
  build_options o;
  o.float_float = float_float;
  const build_result g = gpu_build(w, n, 1, o);
  const vplkit::discrete_cdf<float> c(w);
  INFO(name << " (" << o.text() << "), n = " << n);
  const cdf_difference d = check_build_bounds(g, w, c);
  std::size_t zero_width = 0;
  for (u32 i = 0; i < n; ++i) zero_width += g.cdf[i + 1] == g.cdf[i] ? 1 : 0;
  const std::vector<float> ref = near_exact_cdf(w.data(), n);
  std::cout << "cdf_build " << name << ", n = " << n << " (" << o.text() << "): " << g.ms
            << " ms\n  gpu vs C++ build:        " << describe(d)
            << "\n  gpu vs near-exact:       " << describe(compare_cdfs(g.cdf.data(), ref.data(), n))
            << "\n  C++ build vs near-exact: "
            << describe(compare_cdfs(c.cdf().data(), ref.data(), n))
            << "\n  zero-width bins (float CDF limit, same in C++): " << zero_width
            << "\n  total gpu " << show(g.info[0].total) << ", C++ " << show(c.total())
            << std::endl;
}

}  // namespace

TEST_CASE("cdf_build.comp: 2^24 + 1 equal weights with both accumulators") {
  const std::vector<float> w((1u << 24) + 1u, 1.0f);
  check_large("2^24 + 1 equal weights", w, false);
  check_large("2^24 + 1 equal weights", w, true);
}

TEST_CASE("cdf_build.comp: 2^24 + 12345 weights with zero runs with both accumulators") {
  const std::vector<float> w = zero_run_weights((1u << 24) + 12345u, 100000, 70);
  check_large("2^24 + 12345 zero-run weights", w, false);
  check_large("2^24 + 12345 zero-run weights", w, true);
}
