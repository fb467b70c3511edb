// SPDX-License-Identifier: MIT
// The GPU CDF build, glsl/vplkit/distribution/cdf_build.comp, against the C++ build
// vplkit::discrete_cdf<float> (float weights accumulated in double, 4 sequential lanes).
//
// What is required, and why these bounds:
// - Structure, exactly: cdf[0] = +0, cdf[n] = 1 (0 when empty), non-decreasing, a zero (or
//   rejected) weight repeats its left neighbour bit for bit, and the guide is exactly the C++
//   definition evaluated on the kernel's own cdf (check_invariants). These hold by construction
//   (prefix max, ceil(cdf * m) with exact arithmetic), not by luck of rounding.
// - Values against the C++ build: the kernel's partial sums (a two-level scan in double, or in
//   pairs of floats) and the C++ ones (sequential double lanes) are both within ~2^-35 (C++, worst
//   case at n = 2^20; typically ~2^-44) and ~2^-46 (GPU) relative of the exact sums, far below a
//   float ulp (2^-24), so a cdf value can differ by at most 1 ulp, and only where the exact
//   quotient lies that close to a float rounding tie: for 2^20 weights a handful of values at
//   most (measured: none, on all four weight sets, both accumulators). Bounds with margin:
//   every value within 1 ulp, at most 64 values differing, and the measure of u in [0, 1) that
//   sample a different index (>= the total-variation distance of the two pmfs) at most
//   64 * 2^-24 = 3.8e-6. The test prints the measured figures, also against a near-exact reference
//   (Neumaier-compensated double sums, discrete_cdf<double>, rounded to float).
// - total within 1 ulp of the C++ total(); zeroed counts the weights the C++ sanitized() zeroes.
// Time per build is printed (llvmpipe on a shared 2-core machine: indicative only).
#include <parity_distribution_support.hpp>

#include <vplkit/distribution/discrete_cdf.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

using namespace vplkit::parity;
using namespace vplkit::parity::dist;

namespace {

struct weight_set {
  std::string name;
  std::vector<float> w;
};

std::vector<weight_set> accuracy_sets(u32 n) {
  std::vector<weight_set> v;
  v.push_back({"uniform random", random_weights(n, 1)});
  v.push_back({"exponential", exponential_weights(n, 2)});
  v.push_back({"zero runs (10% at each end, runs inside)", zero_run_weights(n, n / 10, 3)});
  v.push_back({"log-uniform 1e-30 .. 1e30", log_uniform_weights(n, -30, 30, 4)});
  return v;
}

// Builds on the GPU, compares with the C++ build, checks the structure and the bounds above.
void check_build(const std::string& name, const std::vector<float>& w, const build_options& o,
                 bool print = true) {
  const u32 n = u32(w.size());
  const build_result g = gpu_build(w, n, 1, o);
  const auto cpu = vplkit::discrete_cdf<float>::sanitized(w);
  const vplkit::discrete_cdf<float>& c = cpu.distribution;
  INFO(name << " (" << o.text() << "), n = " << n);
  CHECK(g.info[0].zeroed == cpu.zeroed);
  const cdf_difference d = check_build_bounds(g, w, c);
  CHECK(d.tv <= d.disagreement + 1e-15);
  if (print) {
    const std::vector<float> ref = near_exact_cdf(w.data(), n);
    std::cout << "cdf_build " << name << ", n = " << n << " (" << o.text() << "): "
              << std::setprecision(4) << g.ms << " ms\n  gpu vs C++ build:       "
              << describe(d) << "\n  gpu vs near-exact:      "
              << describe(compare_cdfs(g.cdf.data(), ref.data(), n))
              << "\n  C++ build vs near-exact: "
              << describe(compare_cdfs(c.cdf().data(), ref.data(), n)) << "\n  total gpu "
              << show(g.info[0].total) << ", C++ " << show(c.total()) << std::endl;
  }
}

void accuracy_test(bool float_float) {
  const u32 n = (1u << 20) + 3u;  // not a multiple of a block: the last block is partial
  build_options o;
  o.float_float = float_float;
  for (const auto& s : accuracy_sets(n)) check_build(s.name, s.w, o);
}

void edge_case_test(bool float_float) {
  build_options o;
  o.float_float = float_float;
  for (u32 n : {1u, 2u, 3u, 1023u, 1024u, 1025u, 4097u}) {
    check_build("random, small n", random_weights(n, 10 + n), o, false);
    check_build("zero runs, small n", zero_run_weights(n, n / 4, 20 + n), o, false);
  }
  check_build("all zero (empty)", std::vector<float>(5000, 0.0f), o);
  {
    std::vector<float> w(1u << 20, 0.0f);
    w[0] = 0.25f;
    check_build("one non-zero among 2^20, first", w, o);
    w[0] = 0.0f;
    w.back() = 7.0f;
    check_build("one non-zero among 2^20, last", w, o);
  }
  {
    // 2^20 equal weights: exact in any summation order, so the GPU must give the C++ cdf
    // (i * 2^-20) and guide bit for bit.
    const std::vector<float> w(1u << 20, 3.0f);
    const build_result g = gpu_build(w, u32(w.size()), 1, o);
    const vplkit::discrete_cdf<float> c(w);
    CHECK(g.cdf == c.cdf());
    CHECK(g.guide == c.guide());
  }
  {
    // Rejected weights (C++: the constructor throws, sanitized() zeroes them) and valid oddities:
    // -0, denormals, FLT_MAX-sized weights whose sum stays finite, 1e-38 beside 1e38 (docs/math.md
    // section 10).
    std::vector<float> w = random_weights(3000, 30);
    w[0] = std::numeric_limits<float>::quiet_NaN();
    w[5] = -1.0f;
    w[6] = std::numeric_limits<float>::infinity();
    w[7] = -std::numeric_limits<float>::infinity();
    w[8] = -0.0f;
    w[1024] = -std::numeric_limits<float>::quiet_NaN();
    w[1500] = std::numeric_limits<float>::denorm_min();
    w[1501] = 1e-40f;
    w[2047] = 1e38f;
    w[2048] = 1e-38f;
    w[2999] = 2e38f;
    check_build("NaN, -1, +-Inf, -0, denormals, 1e38 and 1e-38", w, o);
  }
  {
    // Stride loops and multi-chunk passes 2 and 4: blocks of 32 x 2 = 64 weights give
    // 2^18 / 64 = 4096 blocks, 64 chunks in passes 2 and 4; at most 7 groups make passes 1, 3,
    // 5, 6 stride. One program per pass (VPLKIT_CDF_BUILD_PASS) as well.
    build_options small = o;
    small.local_size = 32;
    small.items = 2;
    small.max_groups = 7;
    check_build("zero runs, small blocks, 7 groups", zero_run_weights(1u << 18, 3000, 40), small);
    small.program_per_pass = true;
    small.max_groups = 65535;
    check_build("exponential, small blocks, program per pass", exponential_weights(100000, 41), small);
  }
  {
    // Three distributions in one dispatch (z = distribution) give the three single builds.
    const u32 n = 70001;
    std::vector<float> all;
    std::vector<std::vector<float>> parts = {random_weights(n, 50), zero_run_weights(n, 9000, 51),
                                             std::vector<float>(n, 0.0f)};
    for (const auto& p : parts) all.insert(all.end(), p.begin(), p.end());
    const build_result batch = gpu_build(all, n, 3, o);
    const u32 m = u32(vplkit::discrete_guide_size(n));
    for (u32 d = 0; d < 3; ++d) {
      const build_result single = gpu_build(parts[d], n, 1, o);
      CHECK(std::vector<float>(batch.cdf.begin() + d * (n + 1), batch.cdf.begin() + (d + 1) * (n + 1)) ==
            single.cdf);
      CHECK(std::vector<u32>(batch.guide.begin() + d * (m + 1), batch.guide.begin() + (d + 1) * (m + 1)) ==
            single.guide);
      CHECK(bits_of(batch.info[d].total) == bits_of(single.info[0].total));
    }
    CHECK(batch.info[2].total == 0.0f);
  }
}

}  // namespace

TEST_CASE("cdf_build.comp (double): 2^20 + 3 weights of four kinds against the C++ build") {
  accuracy_test(false);
}

TEST_CASE("cdf_build.comp (float-float): 2^20 + 3 weights of four kinds against the C++ build") {
  accuracy_test(true);
}

TEST_CASE("cdf_build.comp (double): small n - empty - lone weights - rejected weights - batches") {
  edge_case_test(false);
}

TEST_CASE("cdf_build.comp (float-float): small n - empty - lone weights - rejected weights - batches") {
  edge_case_test(true);
}

TEST_CASE("cdf_build.comp output sampled on the GPU gives the C++ samplers' index on the same arrays") {
  // discrete_cdf.glsl reading the kernel's arrays; the C++ free functions on the same arrays.
  const u32 n = 300007;
  const std::vector<float> w = zero_run_weights(n, 20000, 60);
  const build_result g = gpu_build(w, n, 1);
  const u32 m = u32(vplkit::discrete_guide_size(n));
  packed_cdfs packed;
  packed.add_arrays(g.cdf, g.guide, n, m, g.info[0].total);
  std::vector<float> us;
  splitmix_rng r(61);
  for (int k = 0; k < 200000; ++k) us.push_back(r.grid_float());
  for (u32 k = 0; k < 30000; ++k) {
    const float c = g.cdf[r.next() % (n + 1)];
    us.insert(us.end(), {c, std::nextafter(c, 0.0f), std::nextafter(c, 1.0f)});
  }
  for (float u : {0.0f, 0x1.fffffep-1f, 1.0f, std::numeric_limits<float>::quiet_NaN()}) us.push_back(u);
  kernel_call call = cdf_kernel(packed, "vplkit/distribution/discrete_cdf.glsl", "",
                                {input(0, us, "float us")}, "uvec2 r", R"(
  r[i] = uvec2(vplkit_discrete_cdf_sample(descs[0], us[i]).index,
               vplkit_discrete_cdf_sample_binary_search(descs[0], us[i]).index);)");
  struct u2 {
    u32 guided, binary;
  };
  const auto gpu = run_compute<u2>(call, us.size());
  series<u32> guided, binary, guided_vs_binary;
  for (std::size_t k = 0; k < us.size(); ++k) {
    const float u = vplkit::discrete_clamp_u(us[k]);
    const u32 cg = u32(vplkit::discrete_cdf_sample_guided(g.cdf.data(), g.guide.data(), m, u));
    const u32 cb = u32(vplkit::discrete_cdf_search(g.cdf.data(), 0, n - 1, u));
    guided.add(gpu[k].guided, cg);
    binary.add(gpu[k].binary, cb);
    guided_vs_binary.add(gpu[k].guided, cb);
  }
  auto describe = [&](std::size_t k) { return "u = " + show(us[k]); };
  VPLKIT_CHECK_PARITY(compare_exact(guided, describe, "guided index on the GPU-built arrays"));
  VPLKIT_CHECK_PARITY(compare_exact(binary, describe, "binary-search index on the GPU-built arrays"));
  VPLKIT_CHECK_PARITY(compare_exact(guided_vs_binary, describe, "guided == binary search on the GPU-built arrays"));
}
