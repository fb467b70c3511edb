// SPDX-License-Identifier: MIT
// The share tree on the GPU against vplkit::share_tree<float>:
// - share_tree_build.comp writes the C++ sums and shares bit for bit (every sum is one `precise`
//   float add of normal floats or zeros, every share an integer function of two sums' bits), on
//   weight sets with zeros, denormals, rejected weights (counted as 0, as sanitized() does), sizes
//   around powers of two, n = 0 and 1, 1e-38 beside 1e37, and a float overflow (+Inf root).
// - share_tree.glsl samples the C++ tree with the same counter_rng streams: the same index, the
//   same pmf bits, the same count of numbers consumed, and pmf(i) bit for bit for every leaf.
#include <parity_harness.hpp>

#include <fp_mode.hpp>
#include <weight_generators.hpp>

#include <vplkit/distribution/share_tree.hpp>
#include <vplkit/distribution/share_tree_build_params.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

using namespace vplkit::parity;
using u32 = std::uint32_t;

namespace {

struct tree_arrays {
  std::vector<float> sums;
  std::vector<u32> shares;
};

tree_arrays gpu_build(const std::vector<float>& w) {
  context();
  const u32 n = u32(w.size());
  const u32 leaves = u32(vplkit::share_tree_leaf_count(n));
  const unsigned depth = vplkit::share_tree_depth(leaves);
  const std::vector<float> upload = w.empty() ? std::vector<float>{0.0f} : w;
  vplkit::gl::buffer weights = vplkit::gl::buffer::from_vector(upload);
  vplkit::gl::buffer sums = vplkit::gl::buffer::filled(std::size_t(2) * leaves * 4, 0xFF);
  vplkit::gl::buffer shares = vplkit::gl::buffer::filled(std::size_t(leaves) * 4, 0xFF);
  vplkit::gl::buffer params = vplkit::gl::buffer::filled(sizeof(vplkit::gpu::share_tree_build_params), 0);
  vplkit_test::bind({vplkit_test::storage_at(VPLKIT_SHARE_TREE_BUILD_BINDING_WEIGHTS, weights),
                     vplkit_test::storage_at(VPLKIT_SHARE_TREE_BUILD_BINDING_SUMS, sums),
                     vplkit_test::storage_at(VPLKIT_SHARE_TREE_BUILD_BINDING_SHARES, shares),
                     vplkit_test::uniform_at(VPLKIT_SHARE_TREE_BUILD_BINDING_PARAMS, params)});
  const auto& program = pack_kernel("vplkit/distribution/share_tree_build.comp");
  for (int level = int(depth); level >= 0; --level) {
    vplkit::gpu::share_tree_build_params p{};
    p.n = n;
    p.leaves = leaves;
    p.level = u32(level);
    params.write_bytes(&p, 0, sizeof p);
    vplkit::gl::dispatch(program, vplkit::gpu::share_tree_build_groups(u32(level)));
  }
  glFinish();
  return {sums.read<float>(), shares.read<u32>()};
}

std::vector<u32> bits(const std::vector<float>& v) {
  std::vector<u32> b(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) b[i] = bits_of(v[i]);
  return b;
}

void check_build(const std::string& name, const std::vector<float>& w) {
  const tree_arrays g = gpu_build(w);
  vplkit_test::reference_scope ref;
  const auto cpu = vplkit::share_tree<float>::sanitized(w);
  const vplkit::share_tree<float>& c = cpu.distribution;
  auto describe = [&](std::size_t k) { return name + ", node " + std::to_string(k); };
  VPLKIT_CHECK_PARITY(compare_exact(bits(g.sums), bits(c.sums()), describe, name + ": sums (bits)"));
  VPLKIT_CHECK_PARITY(compare_exact(g.shares, c.shares(), describe, name + ": shares"));
}

}  // namespace

TEST_CASE("share_tree_build.comp writes the C++ share tree bit for bit") {
  using namespace vplkit_test::portable;
  for (u32 n : {0u, 1u, 2u, 3u, 255u, 256u, 257u, 4097u}) {
    check_build("random, n = " + std::to_string(n), random_weights(n, 10 + n));
  }
  check_build("log-uniform 1e-30 .. 1e30, n = 2^19 + 5", log_uniform_weights((1u << 19) + 5u, -30, 30, 4));
  check_build("all zero", std::vector<float>(3000, 0.0f));
  std::vector<float> w = random_weights(3000, 30);
  w[0] = std::numeric_limits<float>::quiet_NaN();
  w[5] = -1.0f;
  w[6] = std::numeric_limits<float>::infinity();
  w[7] = -std::numeric_limits<float>::infinity();
  w[8] = -0.0f;
  w[1500] = std::numeric_limits<float>::denorm_min();
  w[1501] = 1e-40f;
  w[1502] = -1e-40f;
  w[2047] = 1e37f;
  w[2048] = 1e-38f;
  w[2049] = 1.5e-38f;
  check_build("NaN, -1, +-Inf, -0, denormals, 1e37 beside 1e-38", w);
  // A float total past FLT_MAX: the C++ build refuses it, the kernel leaves +Inf at the root.
  const tree_arrays over = gpu_build(std::vector<float>{3e38f, 3e38f, 1.0f});
  CHECK(std::isinf(over.sums[1]));
}

TEST_CASE("share_tree.glsl draws the C++ indices and pmfs from the same streams") {
  using namespace vplkit_test::portable;
  std::vector<std::vector<float>> sets = {random_weights(1000, 1), log_uniform_weights(4097, -30, 30, 2),
                                          std::vector<float>{0.0f, 1e-30f, 3.0f, 0.5f, 0.0f, 2e-7f, 1.0f},
                                          std::vector<float>{2.0f}, std::vector<float>(5, 0.0f)};
  sets[0][17] = 0.0f;
  sets[0][500] = 1.2e-38f;
  for (std::size_t set = 0; set < sets.size(); ++set) {
    const vplkit::share_tree<float> t(sets[set]);
    const std::size_t count = 20000;
    std::ostringstream defs;
    defs << "#define N " << t.size() << "u\n#define LEAVES " << t.leaf_count() << "u\n#define TOTAL_BITS "
         << bits_of(t.total()) << "u\n#define SEED " << (7u + set) << "u\n";
    kernel_call k = per_item(R"(
#include "vplkit/distribution/share_tree.glsl"
#include "vplkit/sampling/rng.glsl"
vplkit_counter_rng stream;  // the invocation's stream, read through the hook
uint vplkit_share_tree_next_bits(uint tree) { return vplkit_rng_next_u32(stream) >> 8u; }
struct R { uint index; float pmf; float pmf_of_i; uint counter; };
uint vplkit_load_share_tree_share(uint tree, uint node) { return shares[node]; }
)",
                             {input(0, t.shares(), "uint shares")}, "R results", R"(
  vplkit_share_tree t = vplkit_share_tree(0u, N, LEAVES, uintBitsToFloat(TOTAL_BITS));
  stream = vplkit_make_counter_rng(SEED, i);
  vplkit_discrete_sample s = vplkit_share_tree_sample(t);
  results[i] = R(s.index, s.pmf, vplkit_share_tree_pmf(t, i % LEAVES), stream.counter);)");
    k.defines = defs.str();
    // The buffer is declared before the source's accessor: move the declaration into the source.
    k.inputs[0].glsl.clear();
    k.source = "layout(std430, binding = 0) readonly buffer Shares { uint shares[]; };\n" + k.source;
    k.name = "share_tree_sample.comp";
    struct R {
      u32 index;
      float pmf;
      float pmf_of_i;
      u32 counter;
    };
    const auto gpu = run_compute<R>(k, count);
    vplkit_test::reference_scope ref;
    std::vector<u32> gi, ci, gp, cp, gpi, cpi, gc, cc;
    for (std::size_t i = 0; i < count; ++i) {
      vplkit::counter_rng r = vplkit::make_counter_rng(u32(7 + set), u32(i));
      const auto s = t.sample([&] { return vplkit::rng_next_u32(r) >> 8u; });
      if (!t.empty()) REQUIRE(sets[set][s.index] >= std::numeric_limits<float>::min());
      gi.push_back(gpu[i].index);
      ci.push_back(u32(s.index));
      gp.push_back(bits_of(gpu[i].pmf));
      cp.push_back(bits_of(s.pmf));
      gpi.push_back(bits_of(gpu[i].pmf_of_i));
      cpi.push_back(bits_of(t.pmf(i % t.leaf_count())));
      gc.push_back(gpu[i].counter);
      cc.push_back(r.counter);
    }
    const std::string what = "set " + std::to_string(set) + " (n = " + std::to_string(t.size()) + ")";
    auto describe = [&](std::size_t i) { return what + ", stream " + std::to_string(i); };
    VPLKIT_CHECK_PARITY(compare_exact(gi, ci, describe, what + ": index"));
    VPLKIT_CHECK_PARITY(compare_exact(gp, cp, describe, what + ": pmf bits"));
    VPLKIT_CHECK_PARITY(compare_exact(gpi, cpi, describe, what + ": pmf(i) bits"));
    VPLKIT_CHECK_PARITY(compare_exact(gc, cc, describe, what + ": numbers consumed"));
  }
}

TEST_CASE("share_tree.glsl turns exactly where the C++ does: numbers at q - 1 and q on every path") {
  // Random numbers hit a share exactly with probability ~depth 2^-24 per draw: the comparison
  // b < q is checked here with the path numbers of every leaf at the edges, q - 1 (left) and q
  // (right) at each level, and 0 / 2^24 - 1 as the other turn.
  using namespace vplkit_test::portable;
  std::vector<float> w = random_weights(300, 5);
  w[3] = 0.0f;
  w[100] = 1.2e-38f;
  const vplkit::share_tree<float> t(w);
  const u32 depth = t.depth();
  std::vector<u32> numbers;  // item j: leaf j / 2, variant j % 2 (0: edges, 1: far values)
  const std::size_t count = 2 * t.leaf_count();
  for (std::size_t j = 0; j < count; ++j) {
    const std::size_t leaf = j / 2;
    std::vector<u32> path;
    for (std::size_t m = t.leaf_count() + leaf; m > 1; m /= 2) {
      const u32 q = t.shares()[m / 2];
      const bool right = m % 2 == 1;
      if (j % 2 == 0) path.push_back(right ? q : (q > 0 ? q - 1 : 0));
      else path.push_back(right ? vplkit::share_tree_one - 1 : 0);
    }
    numbers.insert(numbers.end(), path.rbegin(), path.rend());
  }
  std::ostringstream defs;
  defs << "#define N " << t.size() << "u\n#define LEAVES " << t.leaf_count() << "u\n#define TOTAL_BITS "
       << bits_of(t.total()) << "u\n#define DEPTH " << depth << "u\n";
  kernel_call k;
  k.source = R"(
#include "vplkit/distribution/share_tree.glsl"
layout(std430, binding = 0) readonly buffer Shares { uint shares[]; };
layout(std430, binding = 2) readonly buffer Numbers { uint numbers[]; };
uint next_number;  // the invocation's position in `numbers`
uint vplkit_load_share_tree_share(uint tree, uint node) { return shares[node]; }
uint vplkit_share_tree_next_bits(uint tree) { return numbers[next_number++]; }
struct R { uint index; float pmf; };
)";
  k.inputs = {input(0, t.shares()), input(2, numbers)};
  k.output_glsl = "R results";
  k.body = R"(
  next_number = i * DEPTH;
  vplkit_share_tree t = vplkit_share_tree(0u, N, LEAVES, uintBitsToFloat(TOTAL_BITS));
  vplkit_discrete_sample s = vplkit_share_tree_sample(t);
  results[i] = R(s.index, s.pmf);)";
  k.defines = defs.str();
  k.name = "share_tree_edges.comp";
  struct R {
    u32 index;
    float pmf;
  };
  const auto gpu = run_compute<R>(k, count);
  vplkit_test::reference_scope ref;
  std::vector<u32> gi, ci, gp, cp;
  for (std::size_t j = 0; j < count; ++j) {
    std::size_t level = 0;
    const auto s = t.sample([&] { return numbers[j * depth + level++]; });
    gi.push_back(gpu[j].index);
    ci.push_back(u32(s.index));
    gp.push_back(bits_of(gpu[j].pmf));
    cp.push_back(bits_of(s.pmf));
  }
  auto describe = [&](std::size_t j) { return "leaf " + std::to_string(j / 2) + (j % 2 ? ", far" : ", edges"); };
  VPLKIT_CHECK_PARITY(compare_exact(gi, ci, describe, "edge paths: index"));
  VPLKIT_CHECK_PARITY(compare_exact(gp, cp, describe, "edge paths: pmf bits"));
  // And the C++ lands on the leaf of every positive weight through its edge path.
  for (std::size_t leaf = 0; leaf < w.size(); ++leaf) {
    if (t.pmf(leaf) > 0.0f) CHECK(ci[2 * leaf] == leaf);
  }
}
