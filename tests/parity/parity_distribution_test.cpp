// Parity of the sampling side of glsl/vplkit/distribution/*.glsl with
// include/vplkit/distribution/*.hpp (T = float): discrete CDF sampling by the guide table and by
// plain binary search, pmf from the stored CDF, the clamp of u, the alias table, the defensive
// mixture and the face roulette. (The GPU CDF build kernel: parity_distribution_build_test.cpp.)
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

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace {

using namespace vplkit::parity::dist;
using vplkit::parity::compare_exact;
using vplkit::parity::compare_floats;
using vplkit::parity::input;
using vplkit::parity::show;
using vplkit::parity::within_ulps;

constexpr float flt_inf = std::numeric_limits<float>::infinity();
constexpr float flt_nan = std::numeric_limits<float>::quiet_NaN();
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
  test_rng g(seed);
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

const std::string cdf_sample_kernel = std::string(R"(
#include "vplkit/distribution/discrete_cdf.glsl"
)") + cdf_accessors() + R"(
struct Q { float u; uint d; };
struct R { uint guided; float guided_pmf; uint binary; float binary_pmf; };
layout(std430, binding = 0) readonly buffer In { Q queries[]; };
layout(std430, binding = 1) writeonly buffer Out { R results[]; };
void main() {
  uint k = gl_GlobalInvocationID.x;
  if (k >= VPLKIT_PARITY_COUNT) return;
  vplkit_discrete_cdf d = descs[queries[k].d];
  vplkit_discrete_sample a = vplkit_discrete_cdf_sample(d, queries[k].u);
  vplkit_discrete_sample b = vplkit_discrete_cdf_sample_binary_search(d, queries[k].u);
  results[k] = R(a.index, a.pmf, b.index, b.pmf);
})";

void check_cdf_sampling(const packed_cdfs& packed, const std::vector<query>& q,
                        const std::vector<const vplkit::discrete_cdf<float>*>& cpu_cdfs,
                        const std::vector<std::string>& names, const std::string& what) {
  vplkit::parity::kernel_call call;
  call.name = "cdf_sample.comp";
  call.source = cdf_sample_kernel;
  call.inputs = packed.inputs();
  call.inputs.push_back(input(0, q));
  call.output_binding = 1;
  const auto gpu = vplkit::parity::run_compute<cdf_result>(call, q.size());
  std::vector<u32> gi, ci, gb, cb, gpmf, cpmf, gbpmf, cbpmf;
  for (std::size_t k = 0; k < q.size(); ++k) {
    const auto& c = *cpu_cdfs[q[k].d];
    const auto a = c.sample(q[k].u);
    const auto b = c.sample_binary_search(q[k].u);
    REQUIRE(a.index == b.index);  // the C++ promise the GPU is held to
    gi.push_back(gpu[k].guided);
    ci.push_back(u32(a.index));
    gb.push_back(gpu[k].binary);
    cb.push_back(u32(b.index));
    gpmf.push_back(bits_of(gpu[k].guided_pmf));
    cpmf.push_back(bits_of(a.pmf));
    gbpmf.push_back(bits_of(gpu[k].binary_pmf));
    cbpmf.push_back(bits_of(b.pmf));
  }
  auto describe = [&](std::size_t k) {
    return names[q[k].d] + ", u = " + show(q[k].u);
  };
  VPLKIT_CHECK_PARITY(compare_exact(gi, ci, describe, what + ": guided index"));
  VPLKIT_CHECK_PARITY(compare_exact(gb, cb, describe, what + ": binary-search index"));
  VPLKIT_CHECK_PARITY(compare_exact(gpmf, cpmf, describe, what + ": guided pmf bits"));
  VPLKIT_CHECK_PARITY(compare_exact(gbpmf, cbpmf, describe, what + ": binary-search pmf bits"));
}

}  // namespace

// =================================================================================================
// discrete_cdf.glsl
// =================================================================================================

TEST_CASE("discrete_cdf.glsl: both searches return the C++ index and pmf on 11 CDFs") {
  const auto cdfs = test_cdfs();
  packed_cdfs packed;
  std::vector<const vplkit::discrete_cdf<float>*> cpu;
  std::vector<std::string> names;
  std::vector<query> q;
  for (const auto& c : cdfs) {
    const u32 id = packed.add(c.cdf);
    cpu.push_back(&c.cdf);
    names.push_back(c.name);
    for (float u : test_us(c.cdf.cdf(), 100 + id)) q.push_back({u, id});
  }
  std::cout << "parity: " << q.size() << " (u, distribution) queries on " << cdfs.size()
            << " CDFs" << std::endl;
  check_cdf_sampling(packed, q, cpu, names, "discrete_cdf sample");
}

TEST_CASE("discrete_cdf.glsl: u = 0 - the largest float below 1 - exactly 1 - NaN") {
  // Every special u on every test CDF, with the clamp rules spelled out: u >= 1 (and +Inf) acts
  // as the largest float below 1, NaN and negative u as 0.
  const auto cdfs = test_cdfs();
  packed_cdfs packed;
  std::vector<const vplkit::discrete_cdf<float>*> cpu;
  std::vector<std::string> names;
  std::vector<query> q;
  for (const auto& c : cdfs) {
    const u32 id = packed.add(c.cdf);
    cpu.push_back(&c.cdf);
    names.push_back(c.name);
    for (float u : special_us()) q.push_back({u, id});
    const auto top = c.cdf.sample(u_max).index;
    const auto bottom = c.cdf.sample(0.0f).index;
    CHECK(c.cdf.sample(1.0f).index == top);
    CHECK(c.cdf.sample(flt_inf).index == top);
    CHECK(c.cdf.sample(flt_nan).index == bottom);
    CHECK(c.cdf.sample(-1.0f).index == bottom);
  }
  check_cdf_sampling(packed, q, cpu, names, "discrete_cdf special u");
}

TEST_CASE("discrete_cdf.glsl: pmf(i) bit for bit - i >= size and empty distributions give 0") {
  auto cdfs = test_cdfs();
  cdfs.push_back({"empty (default-constructed)", vplkit::discrete_cdf<float>()});
  cdfs.push_back({"empty (1000 zero weights)",
                  vplkit::discrete_cdf<float>(std::vector<float>(1000, 0.0f))});
  packed_cdfs packed;
  std::vector<u32> pairs;  // (i, d)
  test_rng g(21);
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
  const std::string kernel = std::string(R"(
#include "vplkit/distribution/discrete_cdf.glsl"
)") + cdf_accessors() + R"(
layout(std430, binding = 0) readonly buffer In { uvec2 index_dist[]; };
layout(std430, binding = 1) writeonly buffer Out { float pmf[]; };
void main() {
  uint k = gl_GlobalInvocationID.x;
  if (k >= VPLKIT_PARITY_COUNT) return;
  pmf[k] = vplkit_discrete_cdf_pmf(descs[index_dist[k].y], index_dist[k].x);
})";
  vplkit::parity::kernel_call call;
  call.source = kernel;
  call.inputs = packed.inputs();
  call.inputs.push_back(input(0, pairs));
  call.output_binding = 1;
  const auto gpu = vplkit::parity::run_compute<float>(call, count);
  std::vector<u32> gb, cb;
  for (std::size_t k = 0; k < count; ++k) {
    gb.push_back(bits_of(gpu[k]));
    cb.push_back(bits_of(cdfs[pairs[2 * k + 1]].cdf.pmf(pairs[2 * k])));
  }
  VPLKIT_CHECK_PARITY(compare_exact(
      gb, cb,
      [&](std::size_t k) { return cdfs[pairs[2 * k + 1]].name + ", i = " + show(pairs[2 * k]); },
      "discrete_cdf pmf bits"));

  // Empty distributions: sample() gives {0, 0} for every u on both sides.
  packed_cdfs empties;
  const vplkit::discrete_cdf<float> e0;
  const vplkit::discrete_cdf<float> e1(std::vector<float>(1000, 0.0f));
  empties.add(e0);
  empties.add(e1);
  std::vector<query> q;
  for (u32 d = 0; d < 2; ++d) {
    for (float u : special_us()) q.push_back({u, d});
  }
  check_cdf_sampling(empties, q, {&e0, &e1}, {"empty (default)", "empty (zeros)"},
                     "empty discrete_cdf");
  for (const auto& c : {e0, e1}) {
    CHECK(c.sample(0.3f).pmf == 0.0f);
    CHECK(c.sample(0.3f).index == 0u);
  }
}

TEST_CASE("weights.glsl: discrete_clamp_u and probability_product bit for bit") {
  test_rng g(31);
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
  const std::string kernel = R"(
#include "vplkit/distribution/weights.glsl"
layout(std430, binding = 0) readonly buffer In { float v[]; };
layout(std430, binding = 2) readonly buffer Pairs { vec2 ab[]; };
layout(std430, binding = 1) writeonly buffer Out { uvec2 r[]; };
void main() {
  uint k = gl_GlobalInvocationID.x;
  if (k >= VPLKIT_PARITY_COUNT) return;
  uint clamped = k < uint(v.length()) ? floatBitsToUint(vplkit_discrete_clamp_u(v[k])) : 0u;
  uint product = k < uint(ab.length()) ? floatBitsToUint(vplkit_probability_product(ab[k].x, ab[k].y)) : 0u;
  r[k] = uvec2(clamped, product);
})";
  const std::size_t count = std::max(in.size(), ab.size() / 2);
  struct u2 {
    u32 clamped, product;
  };
  const auto gpu = vplkit::parity::run_compute<u2>(kernel, {64, 1, 1},
                                                   {input(0, in), input(2, ab)}, 1, count);
  std::vector<u32> gc, cc, gp, cp;
  for (std::size_t k = 0; k < in.size(); ++k) {
    gc.push_back(gpu[k].clamped);
    // GLSL returns +0 where the C++ keeps -0 (documented; no index depends on it).
    const float c = vplkit::discrete_clamp_u(in[k]);
    cc.push_back(bits_of(c == 0.0f ? 0.0f : c));
  }
  for (std::size_t k = 0; k < ab.size() / 2; ++k) {
    gp.push_back(gpu[k].product);
    cp.push_back(bits_of(vplkit::detail::probability_product(ab[2 * k], ab[2 * k + 1])));
  }
  VPLKIT_CHECK_PARITY(compare_exact(gc, cc, [&](std::size_t k) { return "u = " + show(in[k]); },
                                    "vplkit_discrete_clamp_u bits"));
  VPLKIT_CHECK_PARITY(compare_exact(
      gp, cp,
      [&](std::size_t k) { return "a = " + show(ab[2 * k]) + ", b = " + show(ab[2 * k + 1]); },
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
  test_rng g(44);
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
  const std::string kernel = R"(
#include "vplkit/distribution/alias_table.glsl"
struct Q { float u1; float u2; uint d; };
struct R { uint one_index; float one_pmf; uint two_index; float two_pmf; };
layout(std430, binding = 0) readonly buffer In { Q queries[]; };
layout(std430, binding = 1) writeonly buffer Out { R results[]; };
layout(std430, binding = 2) readonly buffer Bins { vplkit_alias_bin bins[]; };
layout(std430, binding = 3) readonly buffer Offsets { uint offsets[]; };
layout(std430, binding = 4) readonly buffer Descs { vplkit_alias_table descs[]; };
vplkit_alias_bin vplkit_load_alias_bin(uint t, uint j) { return bins[offsets[t] + j]; }
void main() {
  uint k = gl_GlobalInvocationID.x;
  if (k >= VPLKIT_PARITY_COUNT) return;
  vplkit_alias_table t = descs[queries[k].d];
  vplkit_discrete_sample a = vplkit_alias_table_sample(t, queries[k].u1);
  vplkit_discrete_sample b = vplkit_alias_table_sample(t, queries[k].u1, queries[k].u2);
  results[k] = R(a.index, a.pmf, b.index, b.pmf);
})";
  vplkit::parity::kernel_call call;
  call.source = kernel;
  call.inputs = {input(0, q), input(2, bins), input(3, offsets), input(4, descs)};
  call.output_binding = 1;
  const auto gpu = vplkit::parity::run_compute<cdf_result>(call, q.size());
  std::vector<u32> g1, c1, g2, c2, gp1, cp1, gp2, cp2;
  for (std::size_t k = 0; k < q.size(); ++k) {
    const auto& t = tables[q[k].d].table;
    const auto a = t.sample(q[k].u1);
    const auto b = t.sample(q[k].u1, q[k].u2);
    g1.push_back(gpu[k].guided);
    c1.push_back(u32(a.index));
    g2.push_back(gpu[k].binary);
    c2.push_back(u32(b.index));
    gp1.push_back(bits_of(gpu[k].guided_pmf));
    cp1.push_back(bits_of(a.pmf));
    gp2.push_back(bits_of(gpu[k].binary_pmf));
    cp2.push_back(bits_of(b.pmf));
  }
  auto describe = [&](std::size_t k) {
    return tables[q[k].d].name + ", u1 = " + show(q[k].u1) + ", u2 = " + show(q[k].u2);
  };
  std::cout << "parity: " << q.size() << " alias-table queries" << std::endl;
  VPLKIT_CHECK_PARITY(compare_exact(g1, c1, describe, "alias sample(u) index"));
  VPLKIT_CHECK_PARITY(compare_exact(gp1, cp1, describe, "alias sample(u) pmf bits"));
  VPLKIT_CHECK_PARITY(compare_exact(g2, c2, describe, "alias sample(u1, u2) index"));
  VPLKIT_CHECK_PARITY(compare_exact(gp2, cp2, describe, "alias sample(u1, u2) pmf bits"));
}

// =================================================================================================
// defensive_mixture.glsl
// =================================================================================================

namespace {

// std430 of vplkit_defensive_mixture / vplkit_face_roulette (all members 4-byte scalars).
struct gpu_mixture {
  gpu_desc learned, fallback;
  float effective_eps, fallback_scale, learned_scale;
};
static_assert(sizeof(gpu_mixture) == 44, "std430 vplkit_defensive_mixture");
struct gpu_roulette {
  gpu_desc front, back;
  float b_front, b_back, front_scale, back_scale;
};
static_assert(sizeof(gpu_roulette) == 48, "std430 vplkit_face_roulette");

gpu_desc desc_of(const packed_cdfs& p, u32 id) { return p.descs[id]; }

// Exact 1 / p as the C++ computes it (double, rounded once), for the host-supplied scales.
float host_reciprocal(float p) { return p > 0.0f ? float(1.0 / double(p)) : 0.0f; }

}  // namespace

TEST_CASE("defensive_mixture.glsl: index exact and pmf within 1 ulp for eps from 0 to 1 and empty parts") {
  // learned: random with holes (median-filled CDFs leave zeros); fallback: uniform over "valid"
  // texels (0/1 weights), as in docs/math.md section 3, defensive mixing.
  const u32 n = 50000;
  std::vector<float> learned_w = zero_run_weights(n, 2000, 51);
  std::vector<float> valid(n);
  test_rng g(52);
  for (float& v : valid) v = (g.next_u32() % 100u) < 78u ? 1.0f : 0.0f;
  const vplkit::discrete_cdf<float> learned(learned_w), fallback(valid), none;
  const vplkit::discrete_cdf<float> zeros(std::vector<float>(n, 0.0f));

  struct named_mixture {
    std::string name;
    vplkit::defensive_mixture<float> m;
  };
  std::vector<named_mixture> mixtures;
  for (float eps : {0.0f, 1e-7f, 0.05f, 0.5f, 1.0f}) {
    mixtures.push_back({"eps = " + show(eps), vplkit::defensive_mixture<float>(learned, fallback, eps)});
  }
  mixtures.push_back({"learned empty, eps = 0.1", vplkit::defensive_mixture<float>(zeros, fallback, 0.1f)});
  mixtures.push_back({"fallback default, eps = 0.1", vplkit::defensive_mixture<float>(learned, none, 0.1f)});
  mixtures.push_back({"both empty", vplkit::defensive_mixture<float>(zeros, none, 0.3f)});

  packed_cdfs packed;
  std::vector<gpu_mixture> gm;
  std::vector<float> eps_in;
  for (const auto& nm : mixtures) {
    const u32 l = packed.add(nm.m.learned());
    const u32 f = packed.add(nm.m.fallback());
    gm.push_back({desc_of(packed, l), desc_of(packed, f), nm.m.effective_eps(), nm.m.fallback_scale(),
                  nm.m.learned_scale()});
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
  const std::string kernel = std::string(R"(
#include "vplkit/distribution/defensive_mixture.glsl"
)") + cdf_accessors() + R"(
struct Q { float u; uint i; uint d; };
struct R { uint index; float pmf; float pmf_of_i; uint fields_equal; float fallback_scale3; float learned_scale3; };
layout(std430, binding = 0) readonly buffer In { Q queries[]; };
layout(std430, binding = 1) writeonly buffer Out { R results[]; };
layout(std430, binding = 6) readonly buffer Mixtures { vplkit_defensive_mixture mixtures[]; };
layout(std430, binding = 7) readonly buffer Eps { float eps[]; };
void main() {
  uint k = gl_GlobalInvocationID.x;
  if (k >= VPLKIT_PARITY_COUNT) return;
  uint d = queries[k].d;
  vplkit_defensive_mixture m = mixtures[d];
  vplkit_discrete_sample s = vplkit_defensive_mixture_sample(m, queries[k].u);
  // The constructor's logic on the GPU, with the host's reciprocals of eps and 1 - eps ...
  float e = eps[d];
  vplkit_defensive_mixture made = vplkit_make_defensive_mixture(m.learned, m.fallback, e,
      eps[8u + 2u * d], eps[9u + 2u * d]);
  uint same = uint(floatBitsToUint(made.effective_eps) == floatBitsToUint(m.effective_eps)) +
              2u * uint(floatBitsToUint(made.fallback_scale) == floatBitsToUint(m.fallback_scale)) +
              4u * uint(floatBitsToUint(made.learned_scale) == floatBitsToUint(m.learned_scale));
  // ... and with its own (GLSL division).
  vplkit_defensive_mixture made3 = vplkit_make_defensive_mixture(m.learned, m.fallback, e);
  results[k] = R(s.index, s.pmf, vplkit_defensive_mixture_pmf(m, queries[k].i), same,
                 made3.fallback_scale, made3.learned_scale);
})";
  // eps[0..7]: the requested eps; eps[8 + 2d], eps[9 + 2d]: host reciprocals of eps and 1 - eps.
  REQUIRE(mixtures.size() == 8);
  std::vector<float> eps_buf = eps_in;
  for (float e : eps_in) {
    eps_buf.push_back(host_reciprocal(e));
    eps_buf.push_back(host_reciprocal(1.0f - e));
  }
  vplkit::parity::kernel_call call;
  call.source = kernel;
  call.inputs = packed.inputs();
  call.inputs.push_back(input(0, q));
  call.inputs.push_back(input(6, gm));
  call.inputs.push_back(input(7, eps_buf));
  call.output_binding = 1;
  struct r6 {
    u32 index;
    float pmf, pmf_of_i;
    u32 same;
    float fallback_scale3, learned_scale3;
  };
  const auto gpu = vplkit::parity::run_compute<r6>(call, q.size());
  std::vector<u32> gi, ci, gs, cs;
  std::vector<float> gp, cp, gpi, cpi, g3, c3;
  for (std::size_t k = 0; k < q.size(); ++k) {
    const auto& m = mixtures[q[k].d].m;
    const auto s = m.sample(q[k].u);
    gi.push_back(gpu[k].index);
    ci.push_back(u32(s.index));
    gp.push_back(gpu[k].pmf);
    cp.push_back(s.pmf);
    gpi.push_back(gpu[k].pmf_of_i);
    cpi.push_back(m.pmf(q[k].i));
    gs.push_back(gpu[k].same);
    cs.push_back(7u);
    g3.insert(g3.end(), {gpu[k].fallback_scale3, gpu[k].learned_scale3});
    c3.insert(c3.end(), {m.fallback_scale(), m.learned_scale()});
    if (!m.empty()) CHECK(s.pmf > 0.0f);
  }
  auto describe = [&](std::size_t k) {
    return mixtures[q[k].d].name + ", u = " + show(q[k].u) + ", i = " + show(q[k].i);
  };
  std::cout << "parity: " << q.size() << " defensive-mixture queries" << std::endl;
  VPLKIT_CHECK_PARITY(compare_exact(gi, ci, describe, "mixture sample index"));
  // 1 ulp (the brief's bound): the pmf is (1 - e) * p_l + e * p_f, both products and the sum
  // `precise`; a conforming implementation gives the C++ bits (measured worst: printed).
  VPLKIT_CHECK_PARITY(compare_floats(gp, cp, within_ulps(1), describe, "mixture sample pmf"));
  VPLKIT_CHECK_PARITY(compare_floats(gpi, cpi, within_ulps(1), describe, "mixture pmf(i)"));
  VPLKIT_CHECK_PARITY(compare_exact(gs, cs, describe,
                                    "vplkit_make_defensive_mixture fields == C++ (bit mask 7)"));
  // The 3-argument constructor divides in GLSL (<= 2.5 ulp allowed; the C++ rounds a double
  // quotient once): 3 ulps.
  VPLKIT_CHECK_PARITY(compare_floats(
      g3, c3, within_ulps(3), [&](std::size_t k) { return describe(k / 2); },
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
  std::vector<gpu_roulette> gr;
  for (const auto& nr : rs) {
    const u32 f = packed.add(nr.r.front());
    const u32 b = packed.add(nr.r.back());
    gr.push_back({desc_of(packed, f), desc_of(packed, b), nr.r.front_probability(),
                  nr.r.back_probability(), nr.r.front_scale(), nr.r.back_scale()});
  }
  struct q4 {
    float u;
    int face;
    u32 i, d;
  };
  std::vector<q4> q;
  test_rng g(65);
  for (u32 d = 0; d < rs.size(); ++d) {
    const float b = rs[d].r.front_probability();
    for (int k = 0; k < 100000; ++k) {
      q.push_back({g.grid_float(), int(g.next_u32() % 3u), u32(g.next() % 41000), d});
    }
    for (int k = 0; k < 5000; ++k) q.push_back({g.any_unit_float(), 0, 0, d});
    for (float u : {b, std::nextafter(b, 0.0f), std::nextafter(b, 1.0f)}) q.push_back({u, 1, 5, d});
    for (float s : special_us()) q.push_back({s, -1, 0, d});
  }
  const std::string kernel = std::string(R"(
#include "vplkit/distribution/face_roulette.glsl"
)") + cdf_accessors() + R"(
struct Q { float u; int face; uint i; uint d; };
struct R { int face; uint index; float pmf; float pmf_of; float b_made; uint made_flags; };
layout(std430, binding = 0) readonly buffer In { Q queries[]; };
layout(std430, binding = 1) writeonly buffer Out { R results[]; };
layout(std430, binding = 6) readonly buffer Roulettes { vplkit_face_roulette roulettes[]; };
void main() {
  uint k = gl_GlobalInvocationID.x;
  if (k >= VPLKIT_PARITY_COUNT) return;
  vplkit_face_roulette r = roulettes[queries[k].d];
  vplkit_face_sample s = vplkit_face_roulette_sample(r, queries[k].u);
  vplkit_face_roulette made = vplkit_make_face_roulette(r.front, r.back);
  uint flags = uint(made.b_back == 0.0) + 2u * uint(made.back_scale == 0.0) +
               4u * uint(made.front_scale == 0.0);
  results[k] = R(s.face, s.index, s.pmf, vplkit_face_roulette_pmf(r, queries[k].face, queries[k].i),
                 made.b_front, flags);
})";
  vplkit::parity::kernel_call call;
  call.source = kernel;
  call.inputs = packed.inputs();
  call.inputs.push_back(input(0, q));
  call.inputs.push_back(input(6, gr));
  call.output_binding = 1;
  struct r6 {
    int face;
    u32 index;
    float pmf, pmf_of, b_made;
    u32 flags;
  };
  const auto gpu = vplkit::parity::run_compute<r6>(call, q.size());
  std::vector<u32> gf, cf, gi, ci, gflags, cflags;
  std::vector<float> gp, cp, gpo, cpo, gb, cb;
  for (std::size_t k = 0; k < q.size(); ++k) {
    const auto& r = rs[q[k].d].r;
    const auto s = r.sample(q[k].u);
    gf.push_back(u32(gpu[k].face));
    cf.push_back(u32(s.face));
    gi.push_back(gpu[k].index);
    ci.push_back(u32(s.index));
    gp.push_back(gpu[k].pmf);
    cp.push_back(s.pmf);
    gpo.push_back(gpu[k].pmf_of);
    cpo.push_back(r.pmf(q[k].face, q[k].i));
    if (!r.empty()) CHECK(s.pmf > 0.0f);
    gb.push_back(gpu[k].b_made);
    cb.push_back(r.front_probability());
    gflags.push_back(gpu[k].flags);
    cflags.push_back(u32(r.back_probability() == 0.0f) + 2u * u32(r.back_scale() == 0.0f) +
                     4u * u32(r.front_scale() == 0.0f));
  }
  auto describe = [&](std::size_t k) {
    return rs[q[k].d].name + ", u = " + show(q[k].u) + ", (face, i) = (" +
           std::to_string(q[k].face) + ", " + show(q[k].i) + ")";
  };
  std::cout << "parity: " << q.size() << " face-roulette queries" << std::endl;
  VPLKIT_CHECK_PARITY(compare_exact(gf, cf, describe, "roulette face"));
  VPLKIT_CHECK_PARITY(compare_exact(gi, ci, describe, "roulette index"));
  VPLKIT_CHECK_PARITY(compare_floats(gp, cp, within_ulps(1), describe, "roulette sample pmf"));
  VPLKIT_CHECK_PARITY(compare_floats(gpo, cpo, within_ulps(1), describe, "roulette pmf(face, i)"));
  // vplkit_make_face_roulette computes b_F in float (GLSL division, <= 2.5 ulp; the C++ divides
  // in double): 3 ulps. Which of b_B and the scales are zero must agree exactly.
  VPLKIT_CHECK_PARITY(compare_floats(gb, cb, within_ulps(3), describe,
                                     "vplkit_make_face_roulette b_front vs C++"));
  VPLKIT_CHECK_PARITY(compare_exact(gflags, cflags, describe, "vplkit_make_face_roulette zero flags"));
}
