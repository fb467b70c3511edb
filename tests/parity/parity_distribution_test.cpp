// SPDX-License-Identifier: MIT
// Parity of the sampling side of glsl/vplkit/distribution/*.glsl with
// include/vplkit/distribution/*.hpp (T = float): discrete CDF sampling by the guide table and by
// plain binary search, pmf from the stored CDF, the clamp of u, the alias table, the defensive
// mixture, the face roulette, the mixture split and mixtures over alias tables and flat
// roulettes. (The GPU CDF build kernel: parity_distribution_build_test.cpp.)
//
// Why exact answers are expected: given the same stored arrays, every sampler uses only float
// comparisons, u * 2^k (exact), u * n and x - j (one rounding each, `precise` where a fused
// multiply-add could skip one), and the subtraction cdf[i + 1] - cdf[i]; GLSL 4.30 rounds + - *
// correctly (4.7.1). So indices must match exactly, and pmfs too; the pmf of the mixture and the
// roulette is checked within 1 ulp as the brief asks, and the measured worst is printed (0 here).
// Where a device may legitimately differ: one that flushes denormals (llvmpipe keeps them) turns a
// pmf or product below 2^-126 into 0 where the C++ keeps it (docs/glsl/distribution.md).
#include <parity_distribution_support.hpp>

#include <vplkit/distribution/alias_table.hpp>
#include <vplkit/distribution/defensive_mixture.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/distribution/face_roulette.hpp>
#include <vplkit/distribution/flat_face_roulette.hpp>
#include <vplkit/distribution/mixture_split.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace {

using namespace vplkit::parity;
using namespace vplkit::parity::dist;
using vplkit_test::flt_inf;
using vplkit_test::flt_nan;

constexpr float u_max = 0x1.fffffep-1f;  // the largest float below 1

// u that every sampler must survive (docs/math.md section 10: 0, the largest float below 1, exactly
// 1, NaN).
std::vector<float> special_us() {
  return {0.0f,  -0.0f, std::numeric_limits<float>::denorm_min(), std::numeric_limits<float>::min(),
          u_max, 1.0f,  std::nextafter(1.0f, 2.0f), 2.0f, flt_inf, -flt_inf, flt_nan, -flt_nan,
          -1.0f, -std::numeric_limits<float>::denorm_min(), 0.5f, 0x1p-24f, 1e-30f};
}

// 10^5 u on the RNG's 2^-24 grid, 2 10^4 with random exponents (tiny values too), every stored
// CDF value of up to 2 10^4 random bins with its two float neighbours, and the specials.
std::vector<float> test_us(const std::vector<float>& cdf, std::uint64_t seed) {
  splitmix_rng g(seed);
  std::vector<float> u;
  for (int k = 0; k < 100000; ++k) u.push_back(g.grid_float());
  for (int k = 0; k < 20000; ++k) u.push_back(g.any_unit_float());
  const std::size_t n = cdf.size() - 1;
  const std::size_t picks = std::min<std::size_t>(n + 1, 20000);
  for (std::size_t k = 0; k < picks; ++k) {
    const std::size_t i = picks == n + 1 ? k : std::size_t(g.next() % (n + 1));
    u.push_back(cdf[i]);
    u.push_back(std::nextafter(cdf[i], 0.0f));
    u.push_back(std::nextafter(cdf[i], 1.0f));
  }
  for (float s : special_us()) u.push_back(s);
  return u;
}

struct query {
  float u;
  u32 d;
};

struct cdf_result {
  u32 guided;
  float guided_pmf;
  u32 binary;
  float binary_pmf;
};

// The distributions of the CDF tests (docs/math.md section 10 hard cases among them).
struct named_cdf {
  std::string name;
  vplkit::discrete_cdf<float> cdf;
};

std::vector<named_cdf> test_cdfs() {
  std::vector<named_cdf> v;
  v.push_back({"random, n = 100003", vplkit::discrete_cdf<float>(random_weights(100003, 11))});
  v.push_back({"zero runs at both ends, n = 60000",
               vplkit::discrete_cdf<float>(zero_run_weights(60000, 10000, 12))});
  {
    std::vector<float> w(1000000, 0.0f);
    w[0] = 0.75f;
    v.push_back({"one non-zero among 10^6, first", vplkit::discrete_cdf<float>(w)});
    w[0] = 0.0f;
    w[999999] = 3.0f;
    v.push_back({"one non-zero among 10^6, last", vplkit::discrete_cdf<float>(w)});
  }
  v.push_back({"2^20 equal weights",
               vplkit::discrete_cdf<float>(std::vector<float>(std::size_t(1) << 20, 1.0f))});
  v.push_back({"log-uniform 1e-38 .. 1e33, n = 65536",
               vplkit::discrete_cdf<float>(log_uniform_weights(65536, -38, 33, 13))});
  v.push_back({"exponential, n = 200000",
               vplkit::discrete_cdf<float>(exponential_weights(200000, 14))});
  {
    // Denormal weights beside normal ones (llvmpipe keeps denormals; see the file comment).
    std::vector<float> w = random_weights(1000, 15);
    for (std::size_t i = 0; i < w.size(); i += 3) w[i] *= 1e-39f;
    w[7] = std::numeric_limits<float>::denorm_min();
    v.push_back({"denormal weights among normal ones, n = 1000", vplkit::discrete_cdf<float>(w)});
  }
  {
    // 1e-38 .. 1e38 (docs/math.md section 10): two 1e38 among tiny ones (the sum stays below
    // FLT_MAX).
    std::vector<float> w = log_uniform_weights(5000, -38, 0, 16);
    w[100] = 1e38f;
    w[4000] = 1e38f;
    v.push_back({"weights 1e-38 .. 1e38, n = 5000", vplkit::discrete_cdf<float>(w)});
  }
  {
    // Finite weights summing past FLT_MAX: total() is +Inf, the CDF is normalised in double.
    std::vector<float> w = random_weights(3000, 17);
    for (float& x : w) x *= 3e36f;
    v.push_back({"weights summing past FLT_MAX (total +Inf), n = 3000", vplkit::discrete_cdf<float>(w)});
  }
  v.push_back({"n = 1", vplkit::discrete_cdf<float>(std::vector<float>{2.5f})});
  v.push_back({"n = 3, middle zero", vplkit::discrete_cdf<float>(std::vector<float>{1.0f, 0.0f, 3.0f})});
  return v;
}

// The CDFs of a test, on the host and packed for the GPU (distribution d is cdfs[d]).
struct cdf_set {
  std::vector<named_cdf> cdfs;
  packed_cdfs packed;
  explicit cdf_set(std::vector<named_cdf> list) : cdfs(std::move(list)) {
    for (const auto& c : cdfs) packed.add(c.cdf);
  }
};

void check_cdf_sampling(const cdf_set& set, const std::vector<query>& q, const std::string& what) {
  kernel_call call = cdf_kernel(set.packed, "vplkit/distribution/discrete_cdf.glsl", R"(
struct Q { float u; uint d; };
struct R { uint guided; float guided_pmf; uint binary; float binary_pmf; };
)",
                                {input(0, q, "Q queries")}, "R results", R"(
  vplkit_discrete_cdf d = descs[queries[i].d];
  vplkit_discrete_sample a = vplkit_discrete_cdf_sample(d, queries[i].u);
  vplkit_discrete_sample b = vplkit_discrete_cdf_sample_binary_search(d, queries[i].u);
  results[i] = R(a.index, a.pmf, b.index, b.pmf);)");
  call.name = "cdf_sample.comp";
  const auto gpu = run_compute<cdf_result>(call, q.size());
  series<u32> guided, binary, guided_pmf, binary_pmf;
  for (std::size_t k = 0; k < q.size(); ++k) {
    const auto& c = set.cdfs[q[k].d].cdf;
    const auto a = c.sample(q[k].u);
    const auto b = c.sample_binary_search(q[k].u);
    REQUIRE(a.index == b.index);  // the C++ promise the GPU is held to
    guided.add(gpu[k].guided, a.index);
    binary.add(gpu[k].binary, b.index);
    guided_pmf.add(bits_of(gpu[k].guided_pmf), bits_of(a.pmf));
    binary_pmf.add(bits_of(gpu[k].binary_pmf), bits_of(b.pmf));
  }
  auto describe = [&](std::size_t k) {
    return set.cdfs[q[k].d].name + ", u = " + show(q[k].u);
  };
  VPLKIT_CHECK_PARITY(compare_exact(guided, describe, what + ": guided index"));
  VPLKIT_CHECK_PARITY(compare_exact(binary, describe, what + ": binary-search index"));
  VPLKIT_CHECK_PARITY(compare_exact(guided_pmf, describe, what + ": guided pmf bits"));
  VPLKIT_CHECK_PARITY(compare_exact(binary_pmf, describe, what + ": binary-search pmf bits"));
}

}  // namespace

// =================================================================================================
// discrete_cdf.glsl
// =================================================================================================

TEST_CASE("discrete_cdf.glsl: both searches return the C++ index and pmf on 11 CDFs") {
  const cdf_set set(test_cdfs());
  std::vector<query> q;
  for (u32 id = 0; id < set.cdfs.size(); ++id) {
    for (float u : test_us(set.cdfs[id].cdf.cdf(), 100 + id)) q.push_back({u, id});
  }
  std::cout << "parity: " << q.size() << " (u, distribution) queries on " << set.cdfs.size()
            << " CDFs" << std::endl;
  check_cdf_sampling(set, q, "discrete_cdf sample");
}

TEST_CASE("discrete_cdf.glsl: u = 0 - the largest float below 1 - exactly 1 - NaN") {
  // Every special u on every test CDF, with the clamp rules spelled out: u >= 1 (and +Inf) acts
  // as the largest float below 1, NaN and negative u as 0.
  const cdf_set set(test_cdfs());
  std::vector<query> q;
  for (u32 id = 0; id < set.cdfs.size(); ++id) {
    const named_cdf& c = set.cdfs[id];
    for (float u : special_us()) q.push_back({u, id});
    const auto top = c.cdf.sample(u_max).index;
    const auto bottom = c.cdf.sample(0.0f).index;
    CHECK(c.cdf.sample(1.0f).index == top);
    CHECK(c.cdf.sample(flt_inf).index == top);
    CHECK(c.cdf.sample(flt_nan).index == bottom);
    CHECK(c.cdf.sample(-1.0f).index == bottom);
  }
  check_cdf_sampling(set, q, "discrete_cdf special u");
}

TEST_CASE("discrete_cdf.glsl: pmf(i) bit for bit - i >= size and empty distributions give 0") {
  auto cdfs = test_cdfs();
  cdfs.push_back({"empty (default-constructed)", vplkit::discrete_cdf<float>()});
  cdfs.push_back({"empty (1000 zero weights)",
                  vplkit::discrete_cdf<float>(std::vector<float>(1000, 0.0f))});
  packed_cdfs packed;
  std::vector<u32> pairs;  // (i, d)
  splitmix_rng g(21);
  for (const auto& c : cdfs) {
    const u32 id = packed.add(c.cdf);
    const u32 n = u32(c.cdf.size());
    if (n <= 70000) {
      for (u32 i = 0; i < n + 3; ++i) pairs.insert(pairs.end(), {i, id});
    } else {
      for (int k = 0; k < 50000; ++k) pairs.insert(pairs.end(), {u32(g.next() % n), id});
      for (u32 i : {0u, 1u, n - 2, n - 1, n, n + 1, 0xFFFFFFFFu}) pairs.insert(pairs.end(), {i, id});
    }
  }
  const std::size_t count = pairs.size() / 2;
  const kernel_call call =
      cdf_kernel(packed, "vplkit/distribution/discrete_cdf.glsl", "", {input(0, pairs, "uvec2 index_dist")},
                 "float pmf", "pmf[i] = vplkit_discrete_cdf_pmf(descs[index_dist[i].y], index_dist[i].x);");
  const auto gpu = run_compute<float>(call, count);
  series<u32> pmf_bits;
  for (std::size_t k = 0; k < count; ++k) {
    pmf_bits.add(bits_of(gpu[k]), bits_of(cdfs[pairs[2 * k + 1]].cdf.pmf(pairs[2 * k])));
  }
  VPLKIT_CHECK_PARITY(compare_exact(
      pmf_bits,
      [&](std::size_t k) { return cdfs[pairs[2 * k + 1]].name + ", i = " + show(pairs[2 * k]); },
      "discrete_cdf pmf bits"));

  // Empty distributions: sample() gives {0, 0} for every u on both sides.
  const cdf_set empties({{"empty (default)", vplkit::discrete_cdf<float>()},
                         {"empty (zeros)", vplkit::discrete_cdf<float>(std::vector<float>(1000, 0.0f))}});
  std::vector<query> q;
  for (u32 d = 0; d < 2; ++d) {
    for (float u : special_us()) q.push_back({u, d});
  }
  check_cdf_sampling(empties, q, "empty discrete_cdf");
  for (const auto& c : empties.cdfs) {
    CHECK(c.cdf.sample(0.3f).pmf == 0.0f);
    CHECK(c.cdf.sample(0.3f).index == 0u);
  }
}

TEST_CASE("weights.glsl: discrete_clamp_u and probability_product bit for bit") {
  splitmix_rng g(31);
  std::vector<float> in = special_us();
  for (int k = 0; k < 100000; ++k) in.push_back(float_of(g.next_u32()));  // any bit pattern
  for (int k = 0; k < 100000; ++k) in.push_back(g.any_unit_float());
  // pairs for the product: probabilities, tiny ones included (underflow -> 2^-149)
  std::vector<float> ab;
  for (int k = 0; k < 100000; ++k) {
    ab.push_back(g.any_unit_float());
    ab.push_back(g.any_unit_float());
  }
  for (float a : {0.0f, 1e-30f, 1e-20f, 1.0f, 0x1p-75f}) {
    for (float b : {0.0f, 1e-30f, 1e-20f, 1.0f, 0x1p-75f}) ab.insert(ab.end(), {a, b});
  }
  // Two outputs of their own lengths, one invocation per element of the longer.
  kernel_call call;
  call.source = R"(#include "vplkit/distribution/weights.glsl")";
  call.inputs = {input(0, in, "float v"), input(2, ab, "vec2 ab")};
  call.output_glsl = "uint clamped";
  call.more_outputs = {output_of<u32>(3, "uint product", ab.size() / 2)};
  call.body = R"(
  clamped[i] = i < uint(v.length()) ? floatBitsToUint(vplkit_discrete_clamp_u(v[i])) : 0u;
  if (i < uint(ab.length())) product[i] = floatBitsToUint(vplkit_probability_product(ab[i].x, ab[i].y));)";
  const auto gpu = run_kernel(call, std::max(in.size(), ab.size() / 2), sizeof(u32));
  const auto clamped = gpu.get<u32>(1), product = gpu.get<u32>(3);
  series<u32> gc, gp;
  for (std::size_t k = 0; k < in.size(); ++k) {
    // GLSL returns +0 where the C++ keeps -0 (documented; no index depends on it).
    const float c = vplkit::discrete_clamp_u(in[k]);
    gc.add(clamped[k], bits_of(c == 0.0f ? 0.0f : c));
  }
  for (std::size_t k = 0; k < ab.size() / 2; ++k) {
    gp.add(product[k], bits_of(vplkit::detail::probability_product(ab[2 * k], ab[2 * k + 1])));
  }
  VPLKIT_CHECK_PARITY(compare_exact(gc, [&](std::size_t k) { return "u = " + show(in[k]); },
                                    "vplkit_discrete_clamp_u bits"));
  VPLKIT_CHECK_PARITY(compare_exact(
      gp, [&](std::size_t k) { return "a = " + show(ab[2 * k]) + ", b = " + show(ab[2 * k + 1]); },
      "vplkit_probability_product bits"));
}

// =================================================================================================
// alias_table.glsl
// =================================================================================================

TEST_CASE("alias_table.glsl: one-u and two-u sampling return the C++ index and pmf") {
  struct named_table {
    std::string name;
    vplkit::alias_table<float> table;
  };
  std::vector<named_table> tables;
  tables.push_back({"zero runs, n = 100003",
                    vplkit::alias_table<float>(zero_run_weights(100003, 5000, 41))});
  {
    std::vector<float> w(100000, 0.0f);
    w[31337] = 2.0f;
    tables.push_back({"one non-zero among 10^5", vplkit::alias_table<float>(w)});
  }
  tables.push_back({"exponential, n = 65536", vplkit::alias_table<float>(exponential_weights(65536, 42))});
  tables.push_back({"log-uniform 1e-30 .. 1e30, n = 4097",
                    vplkit::alias_table<float>(log_uniform_weights(4097, -30, 30, 43))});
  tables.push_back({"n = 3", vplkit::alias_table<float>(std::vector<float>{1.0f, 0.0f, 2.0f})});
  // w / total rounds to 0 while n w / total would be a denormal threshold: never returned.
  tables.push_back({"{2, 2^-149}: pmf rounds to 0",
                    vplkit::alias_table<float>(std::vector<float>{2.0f, std::numeric_limits<float>::denorm_min()})});
  tables.push_back({"{1, 1e-40}: denormal pmf and threshold",
                    vplkit::alias_table<float>(std::vector<float>{1.0f, 1e-40f})});
  tables.push_back({"{3e38, 3e38, 1}: sum past FLT_MAX (total +Inf)",
                    vplkit::alias_table<float>(std::vector<float>{3e38f, 3e38f, 1.0f})});
  tables.push_back({"empty (zeros)", vplkit::alias_table<float>(std::vector<float>(17, 0.0f))});
  tables.push_back({"empty (default)", vplkit::alias_table<float>()});

  struct bin {
    float threshold, pmf;
    u32 alias;
  };
  static_assert(sizeof(bin) == 12, "std430 vplkit_alias_bin");
  std::vector<bin> bins;
  std::vector<u32> offsets;
  struct desc {
    u32 id, size;
    float total;
  };
  std::vector<desc> descs;
  for (const auto& t : tables) {
    offsets.push_back(u32(bins.size()));
    for (const auto& b : t.table.bins()) bins.push_back({b.threshold, b.pmf, b.alias});
    descs.push_back({u32(descs.size()), u32(t.table.size()), t.table.total()});
  }
  bins.push_back({0, 0, 0});  // keep the buffer non-empty
  struct q3 {
    float u1, u2;
    u32 d;
  };
  std::vector<q3> q;
  splitmix_rng g(44);
  for (u32 d = 0; d < tables.size(); ++d) {
    for (int k = 0; k < 100000; ++k) q.push_back({g.grid_float(), g.grid_float(), d});
    for (int k = 0; k < 10000; ++k) q.push_back({g.any_unit_float(), g.any_unit_float(), d});
    // u right at bucket edges and thresholds: u = (j + threshold_j) / n and its neighbours.
    const auto& b = tables[d].table.bins();
    for (std::size_t k = 0; k < std::min<std::size_t>(b.size(), 5000); ++k) {
      const std::size_t j = std::size_t(g.next() % b.size());
      const float u = float((double(j) + double(b[j].threshold)) / double(b.size()));
      for (float v : {u, std::nextafter(u, 0.0f), std::nextafter(u, 1.0f)}) q.push_back({v, b[j].threshold, d});
    }
    for (float s : special_us()) {
      for (float s2 : {0.0f, 0.5f, u_max, 1.0f, flt_nan}) q.push_back({s, s2, d});
    }
  }
  kernel_call call;
  call.source = R"(
#include "vplkit/distribution/alias_table.glsl"
struct Q { float u1; float u2; uint d; };
struct R { uint one_index; float one_pmf; uint two_index; float two_pmf; };
layout(std430, binding = 2) readonly buffer Bins { vplkit_alias_bin bins[]; };
layout(std430, binding = 3) readonly buffer Offsets { uint offsets[]; };
vplkit_alias_bin vplkit_load_alias_bin(uint t, uint j) { return bins[offsets[t] + j]; }
)";
  call.inputs = {input(0, q, "Q queries"), input(2, bins), input(3, offsets), input(4, descs, "vplkit_alias_table descs")};
  call.output_glsl = "R results";
  call.body = R"(
  vplkit_alias_table t = descs[queries[i].d];
  vplkit_discrete_sample a = vplkit_alias_table_sample(t, queries[i].u1);
  vplkit_discrete_sample b = vplkit_alias_table_sample(t, queries[i].u1, queries[i].u2);
  results[i] = R(a.index, a.pmf, b.index, b.pmf);)";
  const auto gpu = run_compute<cdf_result>(call, q.size());
  series<u32> g1, g2, gp1, gp2;
  for (std::size_t k = 0; k < q.size(); ++k) {
    const auto& t = tables[q[k].d].table;
    const auto a = t.sample(q[k].u1);
    const auto b = t.sample(q[k].u1, q[k].u2);
    g1.add(gpu[k].guided, a.index);
    g2.add(gpu[k].binary, b.index);
    gp1.add(bits_of(gpu[k].guided_pmf), bits_of(a.pmf));
    gp2.add(bits_of(gpu[k].binary_pmf), bits_of(b.pmf));
  }
  auto describe = [&](std::size_t k) {
    return tables[q[k].d].name + ", u1 = " + show(q[k].u1) + ", u2 = " + show(q[k].u2);
  };
  std::cout << "parity: " << q.size() << " alias-table queries" << std::endl;
  VPLKIT_CHECK_PARITY(compare_exact(g1, describe, "alias sample(u) index"));
  VPLKIT_CHECK_PARITY(compare_exact(gp1, describe, "alias sample(u) pmf bits"));
  VPLKIT_CHECK_PARITY(compare_exact(g2, describe, "alias sample(u1, u2) index"));
  VPLKIT_CHECK_PARITY(compare_exact(gp2, describe, "alias sample(u1, u2) pmf bits"));
}

// =================================================================================================
// defensive_mixture.glsl
// =================================================================================================

namespace {

// Exact 1 / p as the C++ computes it (double, rounded once), for the host-supplied scales.
float host_reciprocal(float p) { return p > 0.0f ? float(1.0 / double(p)) : 0.0f; }

}  // namespace

TEST_CASE("defensive_mixture.glsl: index exact and pmf within 1 ulp for eps from 0 to 1 and empty parts") {
  const u32 n = 50000;
  splitmix_rng g(52);
  const auto mixtures = test_mixtures(n, 51, g, {0.0f, 1e-7f, 0.05f, 0.5f, 1.0f});
  packed_cdfs packed;
  std::vector<gpu_mixture> gm;
  std::vector<float> eps_in;
  for (const auto& nm : mixtures) {
    gm.push_back(packed.add(nm.m));
    eps_in.push_back(nm.m.eps());
  }
  // Queries: (u, mixture) and (i, mixture) in one struct; u near eps on purpose.
  struct q3 {
    float u;
    u32 i, d;
  };
  std::vector<q3> q;
  for (u32 d = 0; d < mixtures.size(); ++d) {
    const float e = mixtures[d].m.effective_eps();
    for (int k = 0; k < 100000; ++k) q.push_back({g.grid_float(), u32(g.next() % (n + 2)), d});
    for (int k = 0; k < 5000; ++k) q.push_back({g.any_unit_float(), u32(g.next() % n), d});
    for (float u : {e, std::nextafter(e, 0.0f), std::nextafter(e, 1.0f)}) q.push_back({u, 0, d});
    for (float s : special_us()) q.push_back({s, n - 1, d});
  }
  // eps[0..7]: the requested eps; eps[8 + 2d], eps[9 + 2d]: host reciprocals of eps and 1 - eps.
  REQUIRE(mixtures.size() == 8);
  std::vector<float> eps_buf = eps_in;
  for (float e : eps_in) {
    eps_buf.push_back(host_reciprocal(e));
    eps_buf.push_back(host_reciprocal(1.0f - e));
  }
  const kernel_call call = cdf_kernel(packed, "vplkit/distribution/defensive_mixture.glsl", R"(
struct Q { float u; uint i; uint d; };
struct R { uint index; float pmf; float pmf_of_i; uint fields_equal; float fallback_scale3; float learned_scale3; };
)",
      {input(0, q, "Q queries"), input(6, gm, "vplkit_defensive_mixture mixtures"), input(7, eps_buf, "float eps")},
      "R results", R"(
  uint d = queries[i].d;
  vplkit_defensive_mixture m = mixtures[d];
  vplkit_discrete_sample s = vplkit_defensive_mixture_sample(m, queries[i].u);
  // The constructor's logic on the GPU, with the host's reciprocals of eps and 1 - eps ...
  float e = eps[d];
  vplkit_defensive_mixture made = vplkit_make_defensive_mixture(m.learned, m.fallback, e,
      eps[8u + 2u * d], eps[9u + 2u * d]);
  uint same = uint(floatBitsToUint(made.effective_eps) == floatBitsToUint(m.effective_eps)) +
              2u * uint(floatBitsToUint(made.fallback_scale) == floatBitsToUint(m.fallback_scale)) +
              4u * uint(floatBitsToUint(made.learned_scale) == floatBitsToUint(m.learned_scale));
  // ... and with its own (GLSL division).
  vplkit_defensive_mixture made3 = vplkit_make_defensive_mixture(m.learned, m.fallback, e);
  results[i] = R(s.index, s.pmf, vplkit_defensive_mixture_pmf(m, queries[i].i), same,
                 made3.fallback_scale, made3.learned_scale);)");
  struct r6 {
    u32 index;
    float pmf, pmf_of_i;
    u32 same;
    float fallback_scale3, learned_scale3;
  };
  const auto gpu = run_compute<r6>(call, q.size());
  series<u32> gi, gs;
  series<float> gp, gpi, g3;
  for (std::size_t k = 0; k < q.size(); ++k) {
    const auto& m = mixtures[q[k].d].m;
    const auto s = m.sample(q[k].u);
    gi.add(gpu[k].index, s.index);
    gp.add(gpu[k].pmf, s.pmf);
    gpi.add(gpu[k].pmf_of_i, m.pmf(q[k].i));
    gs.add(gpu[k].same, 7u);
    g3.add(gpu[k].fallback_scale3, m.fallback_scale());
    g3.add(gpu[k].learned_scale3, m.learned_scale());
    if (!m.empty()) CHECK(s.pmf > 0.0f);
  }
  auto describe = [&](std::size_t k) {
    return mixtures[q[k].d].name + ", u = " + show(q[k].u) + ", i = " + show(q[k].i);
  };
  std::cout << "parity: " << q.size() << " defensive-mixture queries" << std::endl;
  VPLKIT_CHECK_PARITY(compare_exact(gi, describe, "mixture sample index"));
  // 1 ulp (the brief's bound): the pmf is (1 - e) * p_l + e * p_f, both products and the sum
  // `precise`; a conforming implementation gives the C++ bits (measured worst: printed).
  VPLKIT_CHECK_PARITY(compare_floats(gp, within_ulps(1), describe, "mixture sample pmf"));
  VPLKIT_CHECK_PARITY(compare_floats(gpi, within_ulps(1), describe, "mixture pmf(i)"));
  VPLKIT_CHECK_PARITY(compare_exact(gs, describe,
                                    "vplkit_make_defensive_mixture fields == C++ (bit mask 7)"));
  // The 3-argument constructor divides in GLSL (<= 2.5 ulp allowed; the C++ rounds a double
  // quotient once): 3 ulps.
  VPLKIT_CHECK_PARITY(compare_floats(
      g3, within_ulps(3), [&](std::size_t k) { return describe(k / 2); },
      "vplkit_make_defensive_mixture(l, f, eps) scales vs C++"));
}

// =================================================================================================
// face_roulette.glsl
// =================================================================================================

TEST_CASE("face_roulette.glsl: face and index exact and pmf within 1 ulp with empty faces and v_F + v_B = 0") {
  const vplkit::discrete_cdf<float> front(zero_run_weights(40000, 1000, 61));
  const vplkit::discrete_cdf<float> back(exponential_weights(30000, 62));
  const vplkit::discrete_cdf<float> zeros(std::vector<float>(500, 0.0f)), none;
  std::vector<float> huge_w = random_weights(1000, 63), tiny_w = random_weights(700, 64);
  for (float& w : huge_w) w *= 1e30f;
  for (float& w : tiny_w) w *= 1e-30f;
  const vplkit::discrete_cdf<float> huge(huge_w), tiny(tiny_w);

  struct named_roulette {
    std::string name;
    vplkit::face_roulette<float> r;
  };
  std::vector<named_roulette> rs;
  rs.push_back({"both faces", vplkit::face_roulette<float>(front, back)});
  rs.push_back({"back empty", vplkit::face_roulette<float>(front, zeros)});
  rs.push_back({"front empty (default)", vplkit::face_roulette<float>(none, back)});
  rs.push_back({"v_F + v_B = 0", vplkit::face_roulette<float>(zeros, none)});
  rs.push_back({"back share rounds to 0", vplkit::face_roulette<float>(huge, tiny)});
  rs.push_back({"front share tiny", vplkit::face_roulette<float>(tiny, huge)});
  // A front face whose float total is +Inf (weights summing past FLT_MAX) against a finite back:
  // b_F rounds to 1 in C++ (double sums) and vplkit_make_face_roulette gives 1 as well.
  std::vector<float> over_w = random_weights(800, 66);
  for (float& w : over_w) w *= 3e36f;
  const vplkit::discrete_cdf<float> over(over_w);
  REQUIRE(std::isinf(over.total()));
  rs.push_back({"front total +Inf", vplkit::face_roulette<float>(over, back)});
  CHECK(rs[4].r.back_probability() == 0.0f);

  packed_cdfs packed;
  const std::vector<gpu_roulette> gr = packed.add_each(rs, &named_roulette::r);
  struct q4 {
    float u;
    int face;
    u32 i, d;
  };
  std::vector<q4> q;
  splitmix_rng g(65);
  for (u32 d = 0; d < rs.size(); ++d) {
    const float b = rs[d].r.front_probability();
    for (int k = 0; k < 100000; ++k) {
      q.push_back({g.grid_float(), int(g.next_u32() % 3u), u32(g.next() % 41000), d});
    }
    for (int k = 0; k < 5000; ++k) q.push_back({g.any_unit_float(), 0, 0, d});
    for (float u : {b, std::nextafter(b, 0.0f), std::nextafter(b, 1.0f)}) q.push_back({u, 1, 5, d});
    for (float s : special_us()) q.push_back({s, -1, 0, d});
  }
  const kernel_call call = cdf_kernel(packed, "vplkit/distribution/face_roulette.glsl", R"(
struct Q { float u; int face; uint i; uint d; };
struct R { int face; uint index; float pmf; float pmf_of; float b_made; uint made_flags; };
)",
      {input(0, q, "Q queries"), input(6, gr, "vplkit_face_roulette roulettes")}, "R results", R"(
  vplkit_face_roulette r = roulettes[queries[i].d];
  vplkit_face_sample s = vplkit_face_roulette_sample(r, queries[i].u);
  vplkit_face_roulette made = vplkit_make_face_roulette(r.front, r.back);
  uint flags = uint(made.b_back == 0.0) + 2u * uint(made.back_scale == 0.0) +
               4u * uint(made.front_scale == 0.0);
  results[i] = R(s.face, s.index, s.pmf, vplkit_face_roulette_pmf(r, queries[i].face, queries[i].i),
                 made.b_front, flags);)");
  struct r6 {
    int face;
    u32 index;
    float pmf, pmf_of, b_made;
    u32 flags;
  };
  const auto gpu = run_compute<r6>(call, q.size());
  series<u32> gf, gi, gflags;
  series<float> gp, gpo, gb;
  for (std::size_t k = 0; k < q.size(); ++k) {
    const auto& r = rs[q[k].d].r;
    const auto s = r.sample(q[k].u);
    gf.add(gpu[k].face, s.face);
    gi.add(gpu[k].index, s.index);
    gp.add(gpu[k].pmf, s.pmf);
    gpo.add(gpu[k].pmf_of, r.pmf(q[k].face, q[k].i));
    if (!r.empty()) CHECK(s.pmf > 0.0f);
    gb.add(gpu[k].b_made, r.front_probability());
    gflags.add(gpu[k].flags, u32(r.back_probability() == 0.0f) + 2u * u32(r.back_scale() == 0.0f) +
                                 4u * u32(r.front_scale() == 0.0f));
  }
  auto describe = [&](std::size_t k) {
    return rs[q[k].d].name + ", u = " + show(q[k].u) + ", (face, i) = (" +
           std::to_string(q[k].face) + ", " + show(q[k].i) + ")";
  };
  std::cout << "parity: " << q.size() << " face-roulette queries" << std::endl;
  VPLKIT_CHECK_PARITY(compare_exact(gf, describe, "roulette face"));
  VPLKIT_CHECK_PARITY(compare_exact(gi, describe, "roulette index"));
  VPLKIT_CHECK_PARITY(compare_floats(gp, within_ulps(1), describe, "roulette sample pmf"));
  VPLKIT_CHECK_PARITY(compare_floats(gpo, within_ulps(1), describe, "roulette pmf(face, i)"));
  // vplkit_make_face_roulette computes b_F in float (GLSL division, <= 2.5 ulp; the C++ divides
  // in double): 3 ulps. Which of b_B and the scales are zero must agree exactly.
  VPLKIT_CHECK_PARITY(compare_floats(gb, within_ulps(3), describe,
                                     "vplkit_make_face_roulette b_front vs C++"));
  VPLKIT_CHECK_PARITY(compare_exact(gflags, describe, "vplkit_make_face_roulette zero flags"));
}

// =================================================================================================
// mixture_split.glsl, and defensive mixtures over alias_table.glsl and flat_face_roulette.glsl
// =================================================================================================

namespace {

// std430 of vplkit_mixture_split (three floats).
struct gpu_split {
  float effective_eps, fallback_scale, learned_scale;
};
static_assert(sizeof(gpu_split) == 12, "std430 vplkit_mixture_split");

gpu_split to_gpu(const vplkit::mixture_split<float>& s) {
  return {s.effective_eps(), s.fallback_scale(), s.learned_scale()};
}

}  // namespace

TEST_CASE("mixture_split.glsl: component, remapped u and pmf bit for bit, the GPU constructor field for field") {
  // Every eps the rule treats apart, with each emptiness of the two components.
  const std::vector<float> eps_list = {0.0f, 1e-40f, std::numeric_limits<float>::min(), 1e-7f, 0.05f,
                                       1.0f / 3.0f, 0.5f, std::nextafter(1.0f, 0.0f), 1.0f};
  struct case_t {
    float eps;
    u32 learned_empty, fallback_empty;
  };
  std::vector<case_t> cases;
  std::vector<vplkit::mixture_split<float>> splits;
  for (float e : eps_list)
    for (u32 flags = 0; flags < 4; ++flags) {
      cases.push_back({e, flags & 1u, flags >> 1});
      splits.emplace_back(e, (flags & 1u) != 0, (flags >> 1) != 0);
    }
  std::vector<gpu_split> gs;
  std::vector<float> host_scales;  // per case: C++ reciprocal_or_zero of eps and of 1 - eps
  for (std::size_t c = 0; c < cases.size(); ++c) {
    gs.push_back(to_gpu(splits[c]));
    host_scales.push_back(host_reciprocal(cases[c].eps));
    host_scales.push_back(host_reciprocal(1.0f - cases[c].eps));
  }
  struct q4 {
    float u, p_learned, p_fallback;
    u32 c;
  };
  std::vector<q4> q;
  splitmix_rng g(71);
  const std::vector<float> ps = {0.0f, 1e-40f, std::numeric_limits<float>::min(), 1e-30f, 0.25f, 1.0f};
  for (u32 c = 0; c < cases.size(); ++c) {
    const float e = splits[c].effective_eps();
    for (int k = 0; k < 20000; ++k) q.push_back({g.grid_float(), g.grid_float(), g.any_unit_float(), c});
    for (int k = 0; k < 2000; ++k) q.push_back({g.any_unit_float(), g.any_unit_float(), g.grid_float(), c});
    for (float u : {e, std::nextafter(e, 0.0f), std::nextafter(e, 1.0f)})
      for (float p : ps) q.push_back({u, p, ps[std::size_t(g.next() % ps.size())], c});
    for (float s : special_us()) q.push_back({s, s, s, c});
  }
  const kernel_call call = per_item(R"(
#include "vplkit/distribution/mixture_split.glsl"
struct Q { float u; float p_learned; float p_fallback; uint c; };
struct C { float eps; uint learned_empty; uint fallback_empty; };
struct R { uint component; float u; float pmf; uint made_equal; float fallback_scale3; float learned_scale3; };
)",
      {input(0, q, "Q queries"), input(6, gs, "vplkit_mixture_split splits"), input(7, cases, "C cases"),
       input(8, host_scales, "float host_scales")},
      "R results", R"(
  uint c = queries[i].c;
  vplkit_mixture_split s = splits[c];
  vplkit_mixture_choice ch = vplkit_mixture_split_choose(s, queries[i].u);
  float p = vplkit_mixture_split_pmf(s, queries[i].p_learned, queries[i].p_fallback);
  // The constructor's logic on the GPU, with the host's reciprocals ...
  bool le = cases[c].learned_empty != 0u, fe = cases[c].fallback_empty != 0u;
  vplkit_mixture_split made = vplkit_make_mixture_split(cases[c].eps, le, fe, host_scales[2u * c],
                                                        host_scales[2u * c + 1u]);
  uint same = uint(floatBitsToUint(made.effective_eps) == floatBitsToUint(s.effective_eps)) +
              2u * uint(floatBitsToUint(made.fallback_scale) == floatBitsToUint(s.fallback_scale)) +
              4u * uint(floatBitsToUint(made.learned_scale) == floatBitsToUint(s.learned_scale));
  // ... and with its own (GLSL division).
  vplkit_mixture_split made3 = vplkit_make_mixture_split(cases[c].eps, le, fe);
  results[i] = R(ch.component, ch.u, p, same, made3.fallback_scale, made3.learned_scale);)");
  struct r6 {
    u32 component;
    float u, pmf;
    u32 same;
    float fallback_scale3, learned_scale3;
  };
  const auto gpu = run_compute<r6>(call, q.size());
  series<u32> gc, gu, gp, gsame;
  series<float> g3;
  for (std::size_t k = 0; k < q.size(); ++k) {
    const auto& s = splits[q[k].c];
    const auto ch = s.choose(q[k].u);
    gc.add(gpu[k].component, u32(ch.component));
    gu.add(bits_of(gpu[k].u), bits_of(ch.u));
    gp.add(bits_of(gpu[k].pmf), bits_of(s.pmf(q[k].p_learned, q[k].p_fallback)));
    gsame.add(gpu[k].same, 7u);
    g3.add(gpu[k].fallback_scale3, s.fallback_scale());
    g3.add(gpu[k].learned_scale3, s.learned_scale());
  }
  auto describe = [&](std::size_t k) {
    const case_t& c = cases[q[k].c];
    return "eps = " + show(c.eps) + (c.learned_empty ? ", learned empty" : "") +
           (c.fallback_empty ? ", fallback empty" : "") + ", u = " + show(q[k].u) +
           ", p = (" + show(q[k].p_learned) + ", " + show(q[k].p_fallback) + ")";
  };
  std::cout << "parity: " << q.size() << " mixture-split queries" << std::endl;
  VPLKIT_CHECK_PARITY(compare_exact(gc, describe, "split component"));
  VPLKIT_CHECK_PARITY(compare_exact(gu, describe, "split remapped u bits"));
  // Both products are 0 or normal and the sum `precise`: the C++ bits on every device.
  VPLKIT_CHECK_PARITY(compare_exact(gp, describe, "split pmf bits"));
  VPLKIT_CHECK_PARITY(compare_exact(gsame, describe, "vplkit_make_mixture_split fields == C++ (bit mask 7)"));
  // GLSL division (<= 2.5 ulp) against the C++ double quotient rounded once: 3 ulps.
  VPLKIT_CHECK_PARITY(compare_floats(
      g3, within_ulps(3), [&](std::size_t k) { return describe(k / 2); },
      "vplkit_make_mixture_split(eps, ...) scales vs C++"));
}

TEST_CASE("mixture_split.glsl over alias_table.glsl and flat_face_roulette.glsl: the C++ generic "
          "defensive_mixture's index and pmf") {
  const int R = 64;  // faces of R^2 texels
  const u32 n = 2u * u32(R) * u32(R), face = n / 2;
  splitmix_rng g(81);
  const std::vector<float> learned_w = zero_run_weights(n, 300, 82);
  std::vector<float> valid(n), front_empty = learned_w;
  for (float& v : valid) v = (g.next_u32() % 100u) < 78u ? 1.0f : 0.0f;
  for (u32 i = 0; i < face; ++i) front_empty[i] = 0.0f;
  const std::vector<float> zeros(n, 0.0f);
  struct spec {
    std::string name;
    const std::vector<float>* learned;
    const std::vector<float>* fallback;
    float eps;
  };
  std::vector<spec> specs;
  for (float e : {0.0f, 1e-7f, 0.05f, 0.5f, 1.0f}) specs.push_back({"eps = " + show(e), &learned_w, &valid, e});
  specs.push_back({"front face empty, eps = 0.1", &front_empty, &valid, 0.1f});
  specs.push_back({"learned empty, eps = 0.1", &zeros, &valid, 0.1f});
  specs.push_back({"fallback empty, eps = 0.1", &learned_w, &zeros, 0.1f});
  specs.push_back({"both empty", &zeros, &zeros, 0.3f});

  using alias_mixture = vplkit::defensive_mixture<float, vplkit::alias_table<float>>;
  using flat_mixture = vplkit::defensive_mixture<float, vplkit::flat_face_roulette<float>>;
  std::vector<vplkit::face_roulette<float>> roulettes;
  roulettes.reserve(2 * specs.size());  // the flat views point into it
  std::vector<alias_mixture> alias;
  std::vector<flat_mixture> flat;
  packed_cdfs packed;
  struct alias_desc {
    u32 id, size;
    float total;
  };
  struct bin {
    float threshold, pmf;
    u32 alias;
  };
  static_assert(sizeof(bin) == 12, "std430 vplkit_alias_bin");
  std::vector<bin> bins;
  std::vector<u32> bin_offsets;
  std::vector<alias_desc> alias_descs;  // table 2d + c
  std::vector<gpu_roulette> gpu_roulettes;  // roulette 2d + c
  std::vector<gpu_split> gsplits;
  for (const spec& s : specs) {
    alias.emplace_back(vplkit::alias_table<float>(*s.learned), vplkit::alias_table<float>(*s.fallback), s.eps);
    for (const std::vector<float>* w : {s.learned, s.fallback}) {
      roulettes.emplace_back(vplkit::discrete_cdf<float>(w->data(), face),
                             vplkit::discrete_cdf<float>(w->data() + face, face));
      gpu_roulettes.push_back(packed.add(roulettes.back()));
    }
    flat.emplace_back(vplkit::flat_face_roulette<float>(roulettes[roulettes.size() - 2], R),
                      vplkit::flat_face_roulette<float>(roulettes.back(), R), s.eps);
    for (const vplkit::alias_table<float>* t : {&alias.back().learned(), &alias.back().fallback()}) {
      bin_offsets.push_back(u32(bins.size()));
      for (const auto& b : t->bins()) bins.push_back({b.threshold, b.pmf, b.alias});
      alias_descs.push_back({u32(alias_descs.size()), u32(t->size()), t->total()});
    }
    const vplkit::defensive_mixture<float> joint(vplkit::discrete_cdf<float>(*s.learned),
                                                 vplkit::discrete_cdf<float>(*s.fallback), s.eps);
    // All three mixtures split u alike: the split uploaded is the joint CDF mixture's.
    REQUIRE(bits_of(alias.back().effective_eps()) == bits_of(joint.effective_eps()));
    REQUIRE(bits_of(flat.back().learned_scale()) == bits_of(joint.learned_scale()));
    REQUIRE(bits_of(flat.back().fallback_scale()) == bits_of(joint.fallback_scale()));
    gsplits.push_back(to_gpu(joint.split()));
  }
  bins.push_back({0, 0, 0});  // keep the buffer non-empty
  struct q3 {
    float u;
    u32 i, d;
  };
  std::vector<q3> q;
  for (u32 d = 0; d < specs.size(); ++d) {
    const float e = alias[d].effective_eps();
    for (int k = 0; k < 30000; ++k) q.push_back({g.grid_float(), u32(g.next() % (n + 2)), d});
    for (int k = 0; k < 3000; ++k) q.push_back({g.any_unit_float(), u32(g.next() % n), d});
    for (float u : {e, std::nextafter(e, 0.0f), std::nextafter(e, 1.0f)}) q.push_back({u, 0, d});
    for (float s : special_us()) q.push_back({s, n - 1, d});
  }
  const kernel_call call = cdf_kernel(packed, "vplkit/distribution/flat_face_roulette.glsl", R"(
#include "vplkit/distribution/alias_table.glsl"
#include "vplkit/distribution/mixture_split.glsl"
struct Q { float u; uint i; uint d; };
struct R { uint alias_index; float alias_pmf; float alias_pmf_of_i; uint flat_index; float flat_pmf; float flat_pmf_of_i; };
layout(std430, binding = 8) readonly buffer Bins { vplkit_alias_bin bins[]; };
layout(std430, binding = 9) readonly buffer BinOffsets { uint bin_offsets[]; };
vplkit_alias_bin vplkit_load_alias_bin(uint t, uint j) { return bins[bin_offsets[t] + j]; }
)",
      {input(0, q, "Q queries"), input(6, gsplits, "vplkit_mixture_split splits"),
       input(7, alias_descs, "vplkit_alias_table tables"), input(8, bins), input(9, bin_offsets),
       input(10, gpu_roulettes, "vplkit_face_roulette roulettes")},
      "R results", R"(
  uint d = queries[i].d;
  vplkit_mixture_split s = splits[d];
  vplkit_mixture_choice c = vplkit_mixture_split_choose(s, queries[i].u);
  // The pattern of mixture_split.glsl: component 2d + c.component sampled with c.u, the pmf from
  // both components' pmfs. Both empty: the C++ returns {0, 0} before choosing.
  bool empty = vplkit_alias_table_empty(tables[2u * d]) && vplkit_alias_table_empty(tables[2u * d + 1u]);
  uint ai = empty ? 0u : vplkit_alias_table_sample(tables[2u * d + c.component], c.u).index;
  uint j = queries[i].i;
  float ap = vplkit_mixture_split_pmf(s, vplkit_alias_table_pmf(tables[2u * d], ai),
                                      vplkit_alias_table_pmf(tables[2u * d + 1u], ai));
  float apj = vplkit_mixture_split_pmf(s, vplkit_alias_table_pmf(tables[2u * d], j),
                                       vplkit_alias_table_pmf(tables[2u * d + 1u], j));
  vplkit_flat_face_roulette fl = vplkit_make_flat_face_roulette(roulettes[2u * d], )" + std::to_string(R) + R"();
  vplkit_flat_face_roulette ff = vplkit_make_flat_face_roulette(roulettes[2u * d + 1u], )" + std::to_string(R) + R"();
  uint fi = empty ? 0u : vplkit_flat_face_roulette_sample(c.component == VPLKIT_MIXTURE_FALLBACK ? ff : fl, c.u).index;
  float fp = vplkit_mixture_split_pmf(s, vplkit_flat_face_roulette_pmf(fl, fi), vplkit_flat_face_roulette_pmf(ff, fi));
  float fpj = vplkit_mixture_split_pmf(s, vplkit_flat_face_roulette_pmf(fl, j), vplkit_flat_face_roulette_pmf(ff, j));
  results[i] = R(ai, empty ? 0.0 : ap, apj, fi, empty ? 0.0 : fp, fpj);)");
  struct r6 {
    u32 alias_index;
    float alias_pmf, alias_pmf_of_i;
    u32 flat_index;
    float flat_pmf, flat_pmf_of_i;
  };
  const auto gpu = run_compute<r6>(call, q.size());
  series<u32> gai, gfi, gap, gfp;
  for (std::size_t k = 0; k < q.size(); ++k) {
    const auto& a = alias[q[k].d];
    const auto& f = flat[q[k].d];
    const auto sa = a.sample(q[k].u), sf = f.sample(q[k].u);
    gai.add(gpu[k].alias_index, u32(sa.index));
    gfi.add(gpu[k].flat_index, u32(sf.index));
    gap.add(bits_of(gpu[k].alias_pmf), bits_of(sa.pmf));
    gap.add(bits_of(gpu[k].alias_pmf_of_i), bits_of(a.pmf(q[k].i)));
    gfp.add(bits_of(gpu[k].flat_pmf), bits_of(sf.pmf));
    gfp.add(bits_of(gpu[k].flat_pmf_of_i), bits_of(f.pmf(q[k].i)));
    if (!a.empty()) {
      CHECK(sa.pmf > 0.0f);
      CHECK(sf.pmf > 0.0f);
    }
  }
  auto describe = [&](std::size_t k) {
    return specs[q[k].d].name + ", u = " + show(q[k].u) + ", i = " + show(q[k].i);
  };
  std::cout << "parity: " << q.size() << " component-mixture queries (alias and flat roulette)" << std::endl;
  VPLKIT_CHECK_PARITY(compare_exact(gai, describe, "alias mixture index"));
  VPLKIT_CHECK_PARITY(compare_exact(gfi, describe, "flat-roulette mixture index"));
  // Components' pmfs are exact (their parity tests) and the mixture's sum is `precise`: the C++
  // bits on every device.
  VPLKIT_CHECK_PARITY(compare_exact(gap, [&](std::size_t k) { return describe(k / 2); }, "alias mixture pmf bits"));
  VPLKIT_CHECK_PARITY(compare_exact(gfp, [&](std::size_t k) { return describe(k / 2); }, "flat-roulette mixture pmf bits"));
}
