// SPDX-License-Identifier: MIT
// cdf_build.comp on Vulkan (default bindings of cdf_build_params.h; the six passes in one command
// buffer, the pass chosen by the uniform block) against the C++ build vplkit::discrete_cdf<float>,
// with the bounds of the GL parity test (tests/parity/parity_distribution_build_test.cpp):
//  - structure exactly: cdf[0] = +0, cdf[n] = 1 (0 when empty), non-decreasing, a zero or rejected
//    weight repeats its left neighbour bit for bit, the guide is the C++ definition on the
//    kernel's own cdf;
//  - every cdf value within 1 ulp of the C++ one, at most 64 values differing, the measure of u
//    that sample a different index at most 64 * 2^-24; the guides equal where the cdfs are;
//  - total within 1 ulp of the C++ total(), zeroed = the weights sanitized() zeroes.
// Inputs are smaller than on GL (n <= 100003): the run stays at seconds on lavapipe.
#include "vulkan_test_support.hpp"

#include <vplkit/distribution/cdf_build_params.h>
#include <vplkit/distribution/discrete_cdf.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace vplkit::vk_test;
using u32 = std::uint32_t;

// ---- weights (splitmix64, fixed seeds) ------------------------------------------------------------
struct weight_rng {
  std::uint64_t s;
  explicit weight_rng(std::uint64_t seed) : s(seed * 0x9E3779B97F4A7C15ull + 1) {}
  double uniform() {
    std::uint64_t z = (s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return double((z ^ (z >> 31)) >> 11) * 0x1p-53;
  }
};

enum class shape { uniform, exponential, log_uniform, zero_runs };

// zero_runs: zero ends (n / 10 each), runs of 1..600 zeros and isolated zeros inside.
std::vector<float> weights(shape kind, std::size_t n, std::uint64_t seed) {
  weight_rng g(seed);
  std::vector<float> w(n);
  for (float& x : w) {
    const double u = g.uniform();
    x = kind == shape::exponential ? float(-std::log(1.0 - u))
        : kind == shape::log_uniform ? float(std::pow(10.0, -30.0 + 60.0 * u))
                                     : float(u) + (kind == shape::zero_runs ? 0.01f : 0.0f);
  }
  if (kind == shape::zero_runs) {
    const std::size_t edge = n / 10;
    for (std::size_t i = 0; i < n; ++i) {
      if (i < edge || i + edge >= n) {
        w[i] = 0.0f;
      } else if (g.uniform() < 0.002) {
        const std::size_t len = 1 + std::size_t(g.uniform() * 600);
        for (std::size_t k = i; k < i + len && k < n; ++k) w[k] = 0.0f;
        i += len;
      } else if (g.uniform() < 0.06) {
        w[i] = 0.0f;
      }
    }
  }
  return w;
}

// ---- the GPU build ------------------------------------------------------------------------------
struct variant {
  const char* spirv;        // the compiled kernel (tests/vulkan/CMakeLists.txt)
  u32 local_size, items;    // as compiled
  u32 max_groups = 65535;   // fewer than the blocks: passes 1, 3, 5, 6 stride
};
const variant double_acc{"cdf_build", VPLKIT_CDF_BUILD_LOCAL_SIZE, VPLKIT_CDF_BUILD_ITEMS};
const variant float_float{"cdf_build_float_float", VPLKIT_CDF_BUILD_LOCAL_SIZE, VPLKIT_CDF_BUILD_ITEMS};

struct build_result {
  std::vector<float> cdf;  // D (n + 1)
  std::vector<u32> guide;  // D (m + 1)
  std::vector<vplkit::gpu::cdf_build_info> info;
};

std::vector<slot> cdf_build_slots() {
  return {{VPLKIT_CDF_BUILD_BINDING_WEIGHTS, slot_kind::storage}, {VPLKIT_CDF_BUILD_BINDING_CDF, slot_kind::storage},
          {VPLKIT_CDF_BUILD_BINDING_GUIDE, slot_kind::storage},   {VPLKIT_CDF_BUILD_BINDING_BLOCKS, slot_kind::storage},
          {VPLKIT_CDF_BUILD_BINDING_INFO, slot_kind::storage},    {VPLKIT_CDF_BUILD_BINDING_PARAMS, slot_kind::uniform}};
}

// D distributions of n weights each; every buffer starts as 0xFF bytes (the kernel needs no
// clearing). One uniform block per pass, as a host that records all six passes at once needs.
build_result gpu_build(context& ctx, const kernel& k, const variant& v, const std::vector<float>& w, u32 n, u32 D) {
  const u32 m = u32(vplkit::discrete_guide_size(n));
  const u32 block = v.local_size * v.items;
  const u32 blocks = (n + block - 1) / block;
  const u32 groups = std::min(blocks, v.max_groups);
  const u32 guide_groups = std::min((m + block) / block, v.max_groups);
  const buffer wb = buffer::from_vector(ctx, w);
  const buffer cdf(ctx, std::size_t(D) * (n + 1) * 4, 0xFF);
  const buffer guide(ctx, std::size_t(D) * (m + 1) * 4, 0xFF);
  const buffer blk(ctx, std::size_t(D) * blocks * sizeof(vplkit::gpu::cdf_build_block), 0xFF);
  const buffer info(ctx, std::size_t(D) * sizeof(vplkit::gpu::cdf_build_info), 0xFF);
  std::vector<buffer> params;
  params.reserve(6);
  std::vector<dispatch_step> steps;
  for (u32 pass = 1; pass <= 6; ++pass) {
    vplkit::gpu::cdf_build_params p{};
    p.n = n;
    p.pass = pass;
    params.push_back(buffer::from_bytes(ctx, &p, sizeof p));
    steps.push_back({&k,
                     {{VPLKIT_CDF_BUILD_BINDING_WEIGHTS, &wb}, {VPLKIT_CDF_BUILD_BINDING_CDF, &cdf},
                      {VPLKIT_CDF_BUILD_BINDING_GUIDE, &guide}, {VPLKIT_CDF_BUILD_BINDING_BLOCKS, &blk},
                      {VPLKIT_CDF_BUILD_BINDING_INFO, &info}, {VPLKIT_CDF_BUILD_BINDING_PARAMS, &params.back()}},
                     pass == 2 || pass == 4 ? 1u : pass == 6 ? guide_groups : groups,
                     1,
                     D});
  }
  run(ctx, steps);
  return {cdf.read<float>(), guide.read<u32>(), info.read<vplkit::gpu::cdf_build_info>()};
}

// ---- checks -------------------------------------------------------------------------------------
// The structure the kernel promises; "" or the first violation.
std::string structure_problem(const float* cdf, const u32* guide, const float* w, u32 n, bool empty) {
  std::ostringstream s;
  if (bits_of(cdf[0]) != 0u) s << "cdf[0] = " << show(cdf[0]) << "; ";
  if (cdf[n] != (empty ? 0.0f : 1.0f)) s << "cdf[n] = " << show(cdf[n]) << "; ";
  for (u32 i = 0; i < n && s.str().empty(); ++i) {
    if (!(cdf[i + 1] >= cdf[i])) s << "decreases at " << i;
    const bool zero = !(w[i] > 0.0f && w[i] <= std::numeric_limits<float>::max());
    if (zero && bits_of(cdf[i + 1]) != bits_of(cdf[i])) s << "zero weight " << i << " has width";
  }
  const u32 m = u32(vplkit::discrete_guide_size(n));
  u32 i = 0;
  for (u32 j = 0; j <= m && s.str().empty(); ++j) {  // the largest i < n with cdf[i] <= j / m
    if (!empty)
      while (i + 1 < n && double(cdf[i + 1]) <= double(j) / double(m)) ++i;
    if (guide[j] != (empty ? 0u : i)) s << "guide[" << j << "] = " << guide[j] << ", expected " << i;
  }
  return s.str();
}

void check_build(const std::string& name, const build_result& g, std::size_t d, const float* w, u32 n) {
  const auto cpu = vplkit::discrete_cdf<float>::sanitized(w, n);
  const vplkit::discrete_cdf<float>& c = cpu.distribution;
  const u32 m = u32(vplkit::discrete_guide_size(n));
  const float* a = g.cdf.data() + d * (n + 1);
  const u32* guide = g.guide.data() + d * (m + 1);
  std::size_t differing = 0;
  double max_ulps = 0, disagreement = 0;
  for (u32 i = 0; i <= n; ++i) {
    differing += bits_of(a[i]) != bits_of(c.cdf()[i]);
    max_ulps = std::max(max_ulps, ulp_distance(a[i], c.cdf()[i]));
  }
  for (u32 i = 0; i < n; ++i) {  // the u in [a[i], a[i+1]) that the C++ maps elsewhere
    const double overlap = std::max(0.0, std::min(double(a[i + 1]), double(c.cdf()[i + 1])) -
                                             std::max(double(a[i]), double(c.cdf()[i])));
    disagreement += double(a[i + 1]) - double(a[i]) - overlap;
  }
  INFO(name << ", n = " << n << ", distribution " << d << ": " << differing << " cdf values differ (max " << max_ulps
            << " ulps), u mapped differently " << disagreement);
  CHECK(structure_problem(a, guide, w, n, c.empty()) == "");
  CHECK(g.info[d].zeroed == cpu.zeroed);
  CHECK(ulp_distance(g.info[d].total, c.total()) <= 1.0);
  CHECK(max_ulps <= 1.0);
  CHECK(differing <= 64u);
  CHECK(disagreement <= 64 * 0x1p-24);
  if (differing == 0) CHECK(std::vector<u32>(guide, guide + m + 1) == c.guide());
}

void check_single(context& ctx, const kernel& k, const variant& v, const std::string& name,
                  const std::vector<float>& w) {
  const build_result g = gpu_build(ctx, k, v, w, u32(w.size()), 1);
  check_build(name, g, 0, w.data(), u32(w.size()));
}

void build_cases(const variant& v) {
  with_vulkan([&](context& ctx) {
    if (std::string(v.spirv) != "cdf_build_float_float") {
      INFO("the default cdf_build.comp accumulates in double: the device needs shaderFloat64 (without it, "
           "compile the kernel with VPLKIT_CDF_BUILD_FLOAT_FLOAT)");
      REQUIRE(ctx.has_float64());
    }
    const kernel k(ctx, v.spirv, cdf_build_slots());
    const u32 big = 100003;  // not a multiple of a block: the last block is partial
    check_single(ctx, k, v, "uniform random", weights(shape::uniform, big, 1));
    check_single(ctx, k, v, "exponential", weights(shape::exponential, big, 2));
    check_single(ctx, k, v, "zero runs", weights(shape::zero_runs, big, 3));
    check_single(ctx, k, v, "log-uniform 1e-30 .. 1e30", weights(shape::log_uniform, big, 4));
    for (u32 n : {1u, 2u, 3u, 1023u, 1024u, 1025u, 4097u}) {
      check_single(ctx, k, v, "random, small n", weights(shape::uniform, n, 10 + n));
      check_single(ctx, k, v, "zero runs, small n", weights(shape::zero_runs, n, 20 + n));
    }
    check_single(ctx, k, v, "all zero (empty)", std::vector<float>(5000, 0.0f));
    {
      std::vector<float> w(1u << 16, 0.0f);
      w.back() = 7.0f;
      check_single(ctx, k, v, "one non-zero among 2^16, last", w);
    }
    {
      // Equal weights: exact in any summation order, so the cdf and guide are the C++ ones bit for bit.
      const std::vector<float> w(1u << 16, 3.0f);
      const build_result g = gpu_build(ctx, k, v, w, u32(w.size()), 1);
      const vplkit::discrete_cdf<float> c(w);
      CHECK(g.cdf == c.cdf());
      CHECK(g.guide == c.guide());
    }
    {
      // Rejected weights (the C++ sanitized() zeroes them) and valid oddities.
      std::vector<float> w = weights(shape::uniform, 3000, 30);
      w[0] = std::numeric_limits<float>::quiet_NaN();
      w[5] = -1.0f;
      w[6] = std::numeric_limits<float>::infinity();
      w[7] = -std::numeric_limits<float>::infinity();
      w[8] = -0.0f;
      w[1500] = std::numeric_limits<float>::denorm_min();
      w[2047] = 1e38f;
      w[2048] = 1e-38f;
      w[2999] = 2e38f;
      check_single(ctx, k, v, "NaN, -1, +-Inf, -0, a denormal, 1e38 and 1e-38", w);
    }
    {
      // Three distributions in one set of dispatches (work group z = distribution).
      const u32 n = 5000;
      std::vector<float> w = weights(shape::exponential, n, 50);
      const std::vector<float> b = weights(shape::zero_runs, n, 51);
      w.insert(w.end(), b.begin(), b.end());
      w.insert(w.end(), n, 0.0f);
      const build_result g = gpu_build(ctx, k, v, w, n, 3);
      for (std::size_t d = 0; d < 3; ++d) check_build("three at once", g, d, w.data() + d * n, n);
    }
  });
}

}  // namespace

TEST_CASE("cdf_build.comp on Vulkan (double accumulator): the C++ discrete_cdf<float> build") {
  build_cases(double_acc);
}

TEST_CASE("cdf_build.comp on Vulkan (VPLKIT_CDF_BUILD_FLOAT_FLOAT): the C++ discrete_cdf<float> build") {
  build_cases(float_float);
}

TEST_CASE("cdf_build.comp on Vulkan with blocks of 32 x 2 weights and 7 groups: chunk and stride loops") {
  // 2^15 weights in blocks of 64: 512 blocks, 8 chunks in passes 2 and 4; 7 groups make passes 1,
  // 3, 5 and 6 stride.
  const variant small{"cdf_build_small", 32, 2, 7};
  with_vulkan([&](context& ctx) {
    INFO("the default cdf_build.comp accumulates in double: the device needs shaderFloat64");
    REQUIRE(ctx.has_float64());
    const kernel k(ctx, small.spirv, cdf_build_slots());
    check_single(ctx, k, small, "zero runs, small blocks, 7 groups", weights(shape::zero_runs, 1u << 15, 40));
    check_single(ctx, k, small, "exponential, small blocks, 7 groups", weights(shape::exponential, 20000, 41));
  });
}
