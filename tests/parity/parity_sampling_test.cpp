// SPDX-License-Identifier: MIT
// Parity of glsl/vplkit/sampling/{rng,orthonormal_basis,cosine_hemisphere}.glsl with the C++
// templates of include/vplkit/sampling/ (T = float, and T = double where it says how far each side
// is from the exact value).
//
// - RNG: integers and float bits compared exactly (docs/math.md section 9: identical bits on both
//   sides).
// - Orthonormal basis and cosine hemisphere: floats within the bounds stated at each check, chosen
//   from measurement with margin (docs/glsl/sampling.md lists the measured worst differences).
//
// Denormals: llvmpipe keeps them, most GPUs flush them to zero. The test asks the device first
// (device_flushes_denormals, parity_sampling_mis_support.hpp); on a flushing device the C++
// reference is computed with the x86 FTZ/DAZ bits set, so that the CPU flushes exactly the inputs
// and intermediates the GPU does.
#include <parity_harness.hpp>
#include <parity_sampling_mis_support.hpp>

#include <vplkit/sampling/cosine_hemisphere.hpp>
#include <vplkit/sampling/orthonormal_basis.hpp>
#include <vplkit/sampling/rng.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

using namespace vplkit::parity;
using namespace vplkit::parity::sampmis;

namespace {

using u32 = std::uint32_t;
const float eps = vplkit_test::flt_eps;  // 2^-23
const float flt_min = vplkit_test::flt_min;
const float denorm_min = vplkit_test::flt_denorm_min;
const float flt_max = vplkit_test::flt_max;
const float inf = vplkit_test::flt_inf;
const float qnan = vplkit_test::flt_nan;

// Uniform direction on the sphere, computed in double and rounded.
vplkit::vec3<double> sphere_direction(input_rng& g) {
  const double z = 2.0 * g.uniform() - 1.0;
  const double phi = 2.0 * 3.14159265358979323846 * g.uniform();
  const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {s * std::cos(phi), s * std::sin(phi), z};
}

}  // namespace

// =================================================================================================
// RNG
// =================================================================================================

TEST_CASE("rng.glsl: pcg_hash bit for bit over 1.2 million inputs") {
  std::vector<u32> in;
  for (u32 v = 0; v < 65536u; ++v) in.push_back(v);                  // 0 and small values
  for (u32 v = 0; v < 65536u; ++v) in.push_back(0xFFFF0000u + v);    // up to 0xFFFFFFFF
  for (int k = 0; k < 32; ++k) {                                     // powers of two, neighbours
    const u32 p = 1u << k;
    for (u32 v : {p, p - 1u, p + 1u, ~p, p | 0x80000000u, p * 3u}) in.push_back(v);
  }
  for (u32 v : {0x7FFFFFFFu, 0x80000000u, 0xFFFFFFFFu, 0xDEADBEEFu, 0x9E3779B9u, 12345u}) {
    in.push_back(v);
  }
  input_rng g(1);
  while (in.size() < 1200000u) in.push_back(g.next_u32());
  const auto gpu = run_compute<u32>(
      per_item(R"(#include "vplkit/sampling/rng.glsl")", {input(0, in, "uint v")}, "uint h", "h[i] = vplkit_pcg_hash(v[i]);"),
      in.size());
  std::vector<u32> cpu(in.size());
  for (std::size_t i = 0; i < in.size(); ++i) cpu[i] = vplkit::pcg_hash(in[i]);
  VPLKIT_CHECK_PARITY(compare_exact(
      gpu, cpu, [&](std::size_t i) { return "v = " + show(in[i]); }, "vplkit_pcg_hash"));
}

TEST_CASE("rng.glsl: rng_key bit for bit over seed x stream grids") {
  std::vector<u32> seeds, streams;
  for (u32 s = 0; s < 64u; ++s) seeds.push_back(s);
  for (u32 s : {0x7FFFFFFFu, 0x80000000u, 0xFFFFFFFFu, 0x9E3779B9u, 0x61C88646u, 0xDEADBEEFu}) {
    seeds.push_back(s);
  }
  for (u32 s = 0; s < 2048u; ++s) streams.push_back(s);
  for (u32 s : {0x7FFFFFFFu, 0x80000000u, 0xFFFFFFFFu, 0x9E3779B9u, 1u << 20, 1920u * 1080u}) {
    streams.push_back(s);
  }
  std::vector<u32> pairs;  // (seed, stream) as uvec2
  for (u32 seed : seeds)
    for (u32 stream : streams) {
      pairs.push_back(seed);
      pairs.push_back(stream);
    }
  input_rng g(2);
  for (int i = 0; i < 100000; ++i) {  // random pairs
    pairs.push_back(g.next_u32());
    pairs.push_back(g.next_u32());
  }
  const std::size_t n = pairs.size() / 2;
  struct u2 {
    u32 x, y;
  };
  const auto gpu2 = run_compute<u2>(per_item(R"(#include "vplkit/sampling/rng.glsl")",
                                             {input(0, pairs, "uvec2 seed_stream")}, "uvec2 key_counter", R"(
  uint key = vplkit_rng_key(seed_stream[i].x, seed_stream[i].y);
  vplkit_counter_rng r = vplkit_make_counter_rng(seed_stream[i].x, seed_stream[i].y);
  key_counter[i] = (r.key == key) ? uvec2(key, r.counter) : uvec2(0xDEADu, 0xDEADu);)"),
                                    n);
  std::vector<u32> gpu;
  for (const u2& v : gpu2) gpu.insert(gpu.end(), {v.x, v.y});
  std::vector<u32> cpu(2 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const vplkit::counter_rng r = vplkit::make_counter_rng(pairs[2 * i], pairs[2 * i + 1]);
    REQUIRE(r.key == vplkit::rng_key(pairs[2 * i], pairs[2 * i + 1]));
    cpu[2 * i] = r.key;
    cpu[2 * i + 1] = r.counter;
  }
  VPLKIT_CHECK_PARITY(compare_exact(
      gpu, cpu,
      [&](std::size_t i) {
        const std::size_t k = i / 2;
        return "seed = " + show(pairs[2 * k]) + ", stream = " + show(pairs[2 * k + 1]) +
               (i % 2 ? " (counter)" : " (key)");
      },
      "vplkit_rng_key / vplkit_make_counter_rng"));
}

namespace {

// GPU: for each starting state, D draws of rng_next_u32 on one copy and D draws of rng_next_float
// (even draws) / rng_next_unit (odd draws) on another, then both final states. Per state the
// output holds D hashes, D float bit patterns, key and counter after the u32 draws, counter after
// the float draws: 2 D + 3 uints.
constexpr u32 draws = 48;

std::vector<u32> gpu_sequences(const std::vector<u32>& states, bool from_seed_stream) {
  kernel_call call = per_item(R"(#include "vplkit/sampling/rng.glsl")", {input(0, states, "uvec2 start")},
                              "uint result", R"(
#if FROM_SEED_STREAM
  vplkit_counter_rng a = vplkit_make_counter_rng(start[i].x, start[i].y);
#else
  vplkit_counter_rng a = vplkit_counter_rng(start[i].x, start[i].y);
#endif
  vplkit_counter_rng b = a;  // a copy forks the stream
  uint base = i * (2u * DRAWS + 3u);
  for (uint d = 0u; d < DRAWS; ++d) result[base + d] = vplkit_rng_next_u32(a);
  for (uint d = 0u; d < DRAWS; ++d) {
    float x = (d % 2u == 0u) ? vplkit_rng_next_float(b) : vplkit_rng_next_unit(b);
    result[base + DRAWS + d] = floatBitsToUint(x);
  }
  result[base + 2u * DRAWS] = a.key;
  result[base + 2u * DRAWS + 1u] = a.counter;
  result[base + 2u * DRAWS + 2u] = b.counter;)");
  call.name = "rng_sequences.comp";
  call.defines = "#define DRAWS " + std::to_string(draws) + "u\n#define FROM_SEED_STREAM " +
                 (from_seed_stream ? "1" : "0") + "\n";
  const std::size_t n = states.size() / 2;
  const std::size_t per = 2 * draws + 3;
  // count = number of invocations; the output holds `per` uints for each.
  return run_kernel(call, n, per * sizeof(u32)).get<u32>(1);
}

std::vector<u32> cpu_sequences(const std::vector<u32>& states, bool from_seed_stream) {
  const std::size_t n = states.size() / 2;
  std::vector<u32> out;
  out.reserve(n * (2 * draws + 3));
  for (std::size_t i = 0; i < n; ++i) {
    vplkit::counter_rng a = from_seed_stream
                                ? vplkit::make_counter_rng(states[2 * i], states[2 * i + 1])
                                : vplkit::counter_rng{states[2 * i], states[2 * i + 1]};
    vplkit::counter_rng b = a;
    for (u32 d = 0; d < draws; ++d) out.push_back(vplkit::rng_next_u32(a));
    for (u32 d = 0; d < draws; ++d) {
      const float x = d % 2 == 0 ? vplkit::rng_next_float(b) : vplkit::rng_next_unit<float>(b);
      out.push_back(bits_of(x));
    }
    out.push_back(a.key);
    out.push_back(a.counter);
    out.push_back(b.counter);
  }
  return out;
}

std::string describe_sequence(const std::vector<u32>& states, std::size_t i, const char* start) {
  const std::size_t per = 2 * draws + 3, k = i / per, j = i % per;
  std::string what = j < draws                ? "rng_next_u32 draw " + std::to_string(j)
                     : j < 2 * draws          ? "rng_next_float/unit bits, draw " +
                                                    std::to_string(j - draws)
                     : j == 2 * draws         ? "key after the draws"
                     : j == 2 * draws + 1     ? "counter after the u32 draws"
                                              : "counter after the float draws";
  return std::string(start) + " (" + show(states[2 * k]) + ", " + show(states[2 * k + 1]) +
         "): " + what;
}

}  // namespace

TEST_CASE("rng.glsl: rng_next_u32 / rng_next_float sequences, counters wrapping at 2^32") {
  std::vector<u32> states;  // (key, counter)
  input_rng g(3);
  const std::vector<u32> keys = {0u, 1u, 0xDEADBEEFu, 0x09EE1509u, 123u, 0xFFFFFFFFu, 0x80000000u};
  for (u32 key : keys) {
    // every start from 2^32 - 64 to 2^32 - 1: the 48 draws cross the wrap at each position
    for (u32 c = 0xFFFFFFC0u; c != 0u; ++c) {
      states.push_back(key);
      states.push_back(c);
    }
    for (u32 c : {0u, 1u, 0x7FFFFFFFu, 0x80000000u}) {
      states.push_back(key);
      states.push_back(c);
    }
  }
  while (states.size() < 2 * 6000u) {
    states.push_back(g.next_u32());
    const u32 c = g.next_u32();
    states.push_back((c & 3u) == 0u ? 0xFFFFFFFFu - (c >> 26) : c);  // a quarter near the wrap
  }
  const auto gpu = gpu_sequences(states, false);
  const auto cpu = cpu_sequences(states, false);
  VPLKIT_CHECK_PARITY(compare_exact(
      gpu, cpu, [&](std::size_t i) { return describe_sequence(states, i, "key, counter"); },
      "vplkit_rng_next_u32 / _float / _unit from (key, counter)"));
  // The wrap itself: the counter after 48 draws from 2^32 - 10 is 38.
  const std::size_t per = 2 * draws + 3;
  const std::size_t k = 0xFFFFFFF6u - 0xFFFFFFC0u;  // first key, counter 2^32 - 10
  REQUIRE(states[2 * k + 1] == 0xFFFFFFF6u);
  CHECK(gpu[k * per + 2 * draws + 1] == 38u);
  CHECK(gpu[k * per + 2 * draws + 2] == 38u);
}

TEST_CASE("rng.glsl: make_counter_rng streams over seed x stream grids") {
  std::vector<u32> states;  // (seed, stream)
  for (u32 seed : {0u, 1u, 2u, 42u, 0xFFFFFFFFu})
    for (u32 stream = 0; stream < 1024u; ++stream) {
      states.push_back(seed);
      states.push_back(stream);
    }
  input_rng g(4);
  while (states.size() < 2 * 8000u) states.push_back(g.next_u32());
  const auto gpu = gpu_sequences(states, true);
  const auto cpu = cpu_sequences(states, true);
  VPLKIT_CHECK_PARITY(compare_exact(
      gpu, cpu, [&](std::size_t i) { return describe_sequence(states, i, "seed, stream"); },
      "vplkit_make_counter_rng + draws"));
}

TEST_CASE("rng.glsl: the known-answer vectors of docs/api/sampling.md") {
  const std::vector<u32> hash_in = {0u, 1u, 2u, 4096u, 0xDEADBEEFu, 0x80000000u, 0xFFFFFFFFu, 12345u};
  const std::vector<u32> hash_out = {0x07BB2FE2u, 0xA8BEEA3Cu, 0x7A7ECC88u, 0x9410F6B5u,
                                     0x67299972u, 0x21C72646u, 0xE62A4902u, 0xF45EAD0Eu};
  const std::vector<u32> key_in = {0, 0, 1, 0, 0, 1, 42, 7, 7, 42};  // (seed, stream)
  const std::vector<u32> key_out = {0x7EF300CCu, 0x6F434657u, 0x49046676u, 0x09EE1509u,
                                    0x736F85B2u};
  const std::vector<u32> seq_in = {0u, 0u, 1u, 0u, 0xDEADBEEFu, 0u, 0x09EE1509u, 0u, 123u, 0xFFFFFFFCu};
  const std::vector<u32> seq_out = {
      0x30BE035E, 0xE92A518A, 0x7A0F8CF3, 0xD3016361, 0xD8D452F1, 0x9BD91B45, 0x48BA8FD4, 0x80A6E29D,
      0x5E6301B0, 0xB1921CDE, 0x7DEDA5D8, 0xA5CD984B, 0x4F238228, 0x89E4422B, 0x2F3D6980, 0xA77AF8DF,
      0x2FB44A75, 0x40C3CF8D, 0xF0F5A1DE, 0xAE4399B9, 0x7D7DC222, 0x6541F14D, 0x7B89508C, 0xEB38D594,
      0xE5A02CCE, 0xF2D83641, 0xAD35F443, 0x83CD33D5, 0xBA7038EB, 0x81FDF929, 0xA7A8167A, 0x0996A4A5,
      0x704B878E, 0xB34797EA, 0xC9B105E6, 0xEBFA7C2A, 0xAF6BB3EA, 0x8FA3A6D0, 0x822FCEC2, 0x91601201};
  const std::vector<double> floats = {0.19039934873580933, 0.9108019471168518, 0.47679972648620605,
                                      0.8242399096488953,  0.8469897508621216, 0.6087815165519714,
                                      0.2840966582298279,  0.5025464296340942};
  std::vector<u32> in = hash_in;
  in.insert(in.end(), key_in.begin(), key_in.end());
  in.insert(in.end(), seq_in.begin(), seq_in.end());
  // one invocation does everything: 8 hashes, 5 keys, 5 x 8 draws, 8 floats, make_counter_rng(42,7)
  kernel_call call = per_item(R"(#include "vplkit/sampling/rng.glsl")", {input(0, in, "uint v")}, "uint o", R"(
  if (i != 0u) return;
  uint k = 0u;
  for (uint j = 0u; j < 8u; ++j) o[k++] = vplkit_pcg_hash(v[j]);
  for (uint j = 0u; j < 5u; ++j) o[k++] = vplkit_rng_key(v[8u + 2u * j], v[9u + 2u * j]);
  for (uint s = 0u; s < 5u; ++s) {
    vplkit_counter_rng r = vplkit_counter_rng(v[18u + 2u * s], v[19u + 2u * s]);
    for (uint d = 0u; d < 8u; ++d) o[k++] = vplkit_rng_next_u32(r);
  }
  vplkit_counter_rng r0 = vplkit_counter_rng(0u, 0u);
  for (uint d = 0u; d < 8u; ++d) o[k++] = floatBitsToUint(vplkit_rng_next_float(r0));
  vplkit_counter_rng m = vplkit_make_counter_rng(42u, 7u);
  o[k++] = m.key;
  o[k++] = m.counter;)");
  call.local_size = {1, 1, 1};
  const std::size_t count = 8 + 5 + 40 + 8 + 2;
  const auto gpu = run_compute<u32>(call, count);
  std::vector<u32> want = hash_out;
  want.insert(want.end(), key_out.begin(), key_out.end());
  want.insert(want.end(), seq_out.begin(), seq_out.end());
  for (double f : floats) want.push_back(bits_of(static_cast<float>(f)));
  want.push_back(0x09EE1509u);
  want.push_back(0u);
  // The published decimals are exact float values.
  for (double f : floats) REQUIRE(static_cast<double>(static_cast<float>(f)) == f);
  VPLKIT_CHECK_PARITY(compare_exact(
      gpu, want,
      [](std::size_t i) {
        return i < 8 ? "pcg_hash table row " + std::to_string(i)
               : i < 13 ? "rng_key table row " + std::to_string(i - 8)
               : i < 53 ? "sequence table row " + std::to_string((i - 13) / 8) + ", draw " +
                              std::to_string((i - 13) % 8)
               : i < 61 ? "rng_next_float(key 0) draw " + std::to_string(i - 53)
                        : std::string("make_counter_rng(42, 7)");
      },
      "known answers of docs/api/sampling.md (GPU)"));
}

TEST_CASE("rng.glsl: uint_to_unit_float bit for bit, never 1") {
  std::vector<u32> in = {0u, 1u, 0xFFu, 0x100u, 0x1FFu, 0x80000000u, 0xFFFFFF00u, 0xFFFFFFFFu,
                         0x7FFFFFFFu, 0x00FFFFFFu, 0x01000000u};
  for (int k = 0; k < 32; ++k) in.push_back(1u << k);
  input_rng g(5);
  while (in.size() < 1000000u) in.push_back(g.next_u32());
  const auto gpu = run_compute<u32>(per_item(R"(#include "vplkit/sampling/rng.glsl")", {input(0, in, "uint h")},
                                             "uint bits", "bits[i] = floatBitsToUint(vplkit_uint_to_unit_float(h[i]));"),
                                    in.size());
  std::vector<u32> cpu(in.size());
  for (std::size_t i = 0; i < in.size(); ++i) cpu[i] = bits_of(vplkit::uint_to_unit_float(in[i]));
  VPLKIT_CHECK_PARITY(compare_exact(
      gpu, cpu, [&](std::size_t i) { return "h = " + show(in[i]); }, "vplkit_uint_to_unit_float (bits)"));
  CHECK(gpu[7] == bits_of(1.0f - 1.0f / 16777216.0f));  // h = 0xFFFFFFFF: the largest value
  CHECK(*std::max_element(gpu.begin(), gpu.end()) < bits_of(1.0f));
}

// =================================================================================================
// Orthonormal basis
// =================================================================================================

namespace {

struct onb_out {
  float4 t, b, n, world, local;
};

struct onb_case {
  float x, y, z;
  std::string label;
};

// The hard cases of docs/math.md section 10 / docs/api/sampling.md for the basis.
std::vector<onb_case> onb_hard_cases() {
  std::vector<onb_case> c;
  c.push_back({0.0f, 0.0f, -1.0f, "(0,0,-1)"});
  c.push_back({0.0f, 0.0f, 1.0f, "(0,0,1)"});
  for (float tiny : {1.0f / 16777216.0f, 1.0f / 8388608.0f, 1e-7f, 1e-6f, 1e-5f, 1e-4f, 1e-3f}) {
    c.push_back({0.0f, 0.0f, -1.0f + tiny, "z = -1 + tiny"});
    c.push_back({tiny, -tiny, -1.0f + tiny, "z = -1 + tiny, x,y = +-tiny"});
  }
  const float one_minus_ulp = 1.0f - 1.0f / 16777216.0f;
  for (float z : {-1.0f, -one_minus_ulp, 1.0f, one_minus_ulp})
    for (float x : {0.0f, denorm_min, -denorm_min, eps, -eps})
      for (float y : {0.0f, denorm_min, -denorm_min, eps, -eps}) {
        c.push_back({x, y, z, "near a pole, +-1 ulp"});
      }
  for (float nz : {0.0f, -0.0f}) {  // s switches at n.z = -0.0 / +0.0
    c.push_back({1.0f, 0.0f, nz, "n.z = +-0"});
    c.push_back({0.0f, 1.0f, nz, "n.z = +-0"});
    c.push_back({0.6f, -0.8f, nz, "n.z = +-0"});
    c.push_back({-denorm_min, denorm_min, nz, "denormal x,y, n.z = +-0"});
  }
  // denormal components (on a flushing device the all-denormal ones read as zero)
  c.push_back({denorm_min, 0.0f, 0.0f, "denormal"});
  c.push_back({0.0f, 0.0f, -denorm_min, "denormal"});
  c.push_back({1e-40f, 2e-40f, -3e-40f, "denormal"});
  c.push_back({1.0f, denorm_min, -denorm_min, "denormal components next to 1"});
  c.push_back({flt_min, -flt_min, flt_min, "smallest normals"});
  // unnormalised, including divisors >= 2^126 (1e38, 3e38, max) and tiny normal ones
  for (float k : {1e30f, 1e38f, 3e38f, flt_max, 1e-30f, 2e-38f}) {
    c.push_back({k, 0.0f, 0.0f, "unnormalised"});
    c.push_back({0.0f, 0.0f, -k, "unnormalised"});
    c.push_back({k, k, k, "unnormalised"});
    c.push_back({k, -k, k * 0.5f, "unnormalised"});
    c.push_back({k * 1e-3f, k * 0.5f, -k, "unnormalised"});
  }
  c.push_back({3e38f, 1.0f, -1e-30f, "unnormalised, spread"});
  c.push_back({3.0f, 4.0f, 12.0f, "unnormalised"});
  // no direction: canonical frame
  c.push_back({0.0f, 0.0f, 0.0f, "zero"});
  c.push_back({-0.0f, -0.0f, -0.0f, "zero"});
  c.push_back({qnan, 0.0f, 1.0f, "NaN"});
  c.push_back({0.0f, qnan, 1.0f, "NaN"});
  c.push_back({0.0f, 0.0f, qnan, "NaN"});
  c.push_back({qnan, qnan, qnan, "NaN"});
  c.push_back({inf, 0.0f, 0.0f, "inf"});
  c.push_back({0.0f, -inf, 0.0f, "inf"});
  c.push_back({0.0f, 0.0f, -inf, "inf"});
  c.push_back({inf, inf, inf, "inf"});
  c.push_back({inf, qnan, 1.0f, "inf and NaN"});
  return c;
}

}  // namespace

TEST_CASE("orthonormal_basis.glsl: random normals and the hard cases") {
  const bool ftz = device_flushes_denormals();
  std::vector<onb_case> cases;
  input_rng g(6);
  for (int i = 0; i < 100000; ++i) {
    const int kind = i % 8;
    vplkit::vec3<double> d = sphere_direction(g);
    if (kind == 1 || kind == 2) {  // crowded around (0,0,-1): n.z = -1 + 10^[-8, -1]
      const double t = std::pow(10.0, -8.0 + 7.0 * g.uniform());
      const double phi = 2.0 * 3.14159265358979323846 * g.uniform();
      const double r = std::sqrt(t * (2.0 - t));
      d = {r * std::cos(phi), r * std::sin(phi), -1.0 + t};
    } else if (kind == 3) {  // around (0,0,+1)
      const double t = std::pow(10.0, -8.0 + 7.0 * g.uniform());
      const double phi = 2.0 * 3.14159265358979323846 * g.uniform();
      const double r = std::sqrt(t * (2.0 - t));
      d = {r * std::cos(phi), r * std::sin(phi), 1.0 - t};
    } else if (kind == 4) {  // unnormalised: length 10^[-30, 30]
      d *= std::pow(10.0, -30.0 + 60.0 * g.uniform());
    } else if (kind == 5) {  // slightly off unit length
      d *= 1.0 + (g.uniform() - 0.5) * 1e-3;
    }
    cases.push_back({static_cast<float>(d.x), static_cast<float>(d.y), static_cast<float>(d.z),
                     "random"});
  }
  const std::size_t first_hard = cases.size();
  const auto hard = onb_hard_cases();
  cases.insert(cases.end(), hard.begin(), hard.end());
  const std::size_t n = cases.size();

  std::vector<float4> normals(n), locals(n);
  for (std::size_t i = 0; i < n; ++i) {
    normals[i] = {cases[i].x, cases[i].y, cases[i].z, 0.0f};
    const auto l = sphere_direction(g) * (0.25 + g.uniform());
    locals[i] = {static_cast<float>(l.x), static_cast<float>(l.y), static_cast<float>(l.z), 0.0f};
  }
  const auto gpu = run_compute<onb_out>(per_item(R"(
#include "vplkit/sampling/orthonormal_basis.glsl"
struct R { vec4 t; vec4 b; vec4 n; vec4 world; vec4 local; };
)",
                                                 {input(0, normals, "vec4 normal"), input(2, locals, "vec4 local_dir")},
                                                 "R result", R"(
  vplkit_orthonormal_basis f = vplkit_make_orthonormal_basis(normal[i].xyz);
  result[i].t = vec4(f.t, 0.0);
  result[i].b = vec4(f.b, 0.0);
  result[i].n = vec4(f.n, 0.0);
  result[i].world = vec4(vplkit_to_world(f, local_dir[i].xyz), 0.0);
  // the same random vector read as a world direction
  result[i].local = vec4(vplkit_to_local(f, local_dir[i].xyz), 0.0);)"),
                                        n);

  std::vector<vplkit::orthonormal_basis<float>> cpu(n);
  std::vector<vplkit::vec3<float>> cpu_world(n), cpu_local(n);
  {
    // The plain reference: the normal-range contract (docs/math.md, "GPU arithmetic model") makes it the
    // answer of a flushing device too (the [ftz-daz] run checks it under flushing).
    for (std::size_t i = 0; i < n; ++i) {
      const vplkit::vec3<float> l(locals[i].x, locals[i].y, locals[i].z);
      cpu[i] = vplkit::make_orthonormal_basis(vplkit::vec3<float>(cases[i].x, cases[i].y, cases[i].z));
      cpu_world[i] = vplkit::to_world(cpu[i], l);
      cpu_local[i] = vplkit::to_local(cpu[i], l);
    }
  }
  std::vector<vplkit::orthonormal_basis<double>> exact(n);
  for (std::size_t i = 0; i < n; ++i) {
    exact[i] = vplkit::make_orthonormal_basis(vplkit::vec3<double>(cases[i].x, cases[i].y, cases[i].z));
  }

  // Per vector: 3 components each of t, b, n (frame), world, local.
  auto flatten = [&](auto get) {
    std::vector<float> v;
    v.reserve(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
      const auto x = get(i);
      v.push_back(x[0]);
      v.push_back(x[1]);
      v.push_back(x[2]);
    }
    return v;
  };
  auto describe = [&](std::size_t i) {
    const auto& c = cases[i / 9 < n ? i / 9 : 0];
    return "n = " + show3(c.x, c.y, c.z) + " [" + c.label + "], component " + std::to_string(i % 9);
  };
  std::vector<float> gpu_frame, cpu_frame;
  std::vector<double> exact_frame;
  for (std::size_t i = 0; i < n; ++i) {
    const float4* g4[3] = {&gpu[i].t, &gpu[i].b, &gpu[i].n};
    const vplkit::vec3<float>* c3[3] = {&cpu[i].t, &cpu[i].b, &cpu[i].n};
    const vplkit::vec3<double>* e3[3] = {&exact[i].t, &exact[i].b, &exact[i].n};
    for (int k = 0; k < 3; ++k) {
      gpu_frame.insert(gpu_frame.end(), {g4[k]->x, g4[k]->y, g4[k]->z});
      cpu_frame.insert(cpu_frame.end(), {(*c3[k])[0], (*c3[k])[1], (*c3[k])[2]});
      exact_frame.insert(exact_frame.end(), {(*e3[k])[0], (*e3[k])[1], (*e3[k])[2]});
    }
  }
  // Components of unit vectors: an absolute bound in units of eps = 2^-23 (relative bounds mean
  // nothing for t.x = 1 + s n.x^2 a, which cancels to ~0 when |n.x| ~ 1). Both sides round the
  // same dozen operations; llvmpipe may contract a*b+c into an FMA, GPUs also divide and take
  // square roots to ~1-3 ulps. Measured on llvmpipe: see docs/glsl/sampling.md.
  const auto frame_bound = within_abs(4.0 * eps);
  VPLKIT_CHECK_PARITY(compare_floats(gpu_frame, cpu_frame, frame_bound, describe,
                                     "vplkit_make_orthonormal_basis (t, b, n) vs C++ float"));
  if (!ftz) {
    // Against the double template: how far the GPU frame is from the exact one. Skipped where
    // float and double take different branches s = +-1 (both right): n.z underflows to -0 in
    // float, e.g. (3e38, 1, -1e-30), or normalises below FLT_MIN and counts as 0, and keeps its
    // sign in double.
    std::vector<float> g;
    std::vector<double> e;
    std::vector<std::size_t> at;
    std::size_t branch_skips = 0, denormal_skips = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if ((cpu[i].n.z >= 0.0f) != (exact[i].n.z >= 0.0)) {
        ++branch_skips;
        continue;
      }
      // A float component below FLT_MIN counts as 0 (the normal-range contract, docs/math.md
      // "GPU arithmetic model"), where double keeps the same (to double, normal) component.
      const vplkit::vec3<float> nf(cases[i].x, cases[i].y, cases[i].z);
      const vplkit::vec3<float> ff = vplkit::flush_denormal(nf);
      if (ff.x != nf.x || ff.y != nf.y || ff.z != nf.z) {
        ++denormal_skips;
        continue;
      }
      for (std::size_t k = 0; k < 9; ++k) {
        g.push_back(gpu_frame[9 * i + k]);
        e.push_back(exact_frame[9 * i + k]);
        at.push_back(9 * i + k);
      }
    }
    std::cout << "  vs double: " << branch_skips << " cases with another branch, " << denormal_skips
              << " with a denormal float component left out\n";
    CHECK(branch_skips <= 8);  // a few: n.z underflows, or is below FLT_MIN and counts as 0, in float
    VPLKIT_CHECK_PARITY(compare_floats(g, e, frame_bound,
                                       [&](std::size_t j) { return describe(at[j]); },
                                       "vplkit_make_orthonormal_basis (t, b, n) vs C++ double"));
  }
  // to_world / to_local of vectors of length <= 1.25: a few roundings of terms <= 1.25.
  auto describe3 = [&](std::size_t i) {
    const auto& c = cases[i / 3];
    return "n = " + show3(c.x, c.y, c.z) + " [" + c.label + "], local = " +
           show3(locals[i / 3].x, locals[i / 3].y, locals[i / 3].z);
  };
  const auto gpu_world = flatten([&](std::size_t i) { return std::vector<float>{gpu[i].world.x, gpu[i].world.y, gpu[i].world.z}; });
  const auto cpu_world_f = flatten([&](std::size_t i) { return std::vector<float>{cpu_world[i][0], cpu_world[i][1], cpu_world[i][2]}; });
  const auto gpu_local = flatten([&](std::size_t i) { return std::vector<float>{gpu[i].local.x, gpu[i].local.y, gpu[i].local.z}; });
  const auto cpu_local_f = flatten([&](std::size_t i) { return std::vector<float>{cpu_local[i][0], cpu_local[i][1], cpu_local[i][2]}; });
  VPLKIT_CHECK_PARITY(compare_floats(gpu_world, cpu_world_f, within_abs(8.0 * eps), describe3, "vplkit_to_world"));
  VPLKIT_CHECK_PARITY(compare_floats(gpu_local, cpu_local_f, within_abs(8.0 * eps), describe3, "vplkit_to_local"));

  // The GPU frames themselves, evaluated in double on the host: orthonormal, right-handed, no NaN
  // (the C++ promise: 8 eps), and n along the input.
  double worst = 0;
  std::size_t worst_i = 0, bad = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const vplkit::vec3<double> t(gpu[i].t.x, gpu[i].t.y, gpu[i].t.z);
    const vplkit::vec3<double> b(gpu[i].b.x, gpu[i].b.y, gpu[i].b.z);
    const vplkit::vec3<double> nn(gpu[i].n.x, gpu[i].n.y, gpu[i].n.z);
    const vplkit::vec3<double> c = glm::cross(t, b) - nn;
    const double e = std::max({std::abs(glm::dot(t, b)), std::abs(glm::dot(t, nn)),
                               std::abs(glm::dot(b, nn)), std::abs(glm::dot(t, t) - 1.0),
                               std::abs(glm::dot(b, b) - 1.0), std::abs(glm::dot(nn, nn) - 1.0),
                               std::abs(c.x), std::abs(c.y), std::abs(c.z)});
    if (!(e <= worst)) {  // NaN lands here too
      worst = std::isnan(e) ? std::numeric_limits<double>::infinity() : e;
      worst_i = i;
    }
    if (!(e <= 8.0 * eps)) ++bad;
  }
  std::cout << "  GPU frames: worst orthonormality error " << worst / eps << " eps at n = "
            << show3(cases[worst_i].x, cases[worst_i].y, cases[worst_i].z) << "\n";
  CHECK(bad == 0);

  // Zero, NaN, inf and (on a flushing device) all-denormal inputs: exactly the canonical frame.
  for (std::size_t i = first_hard; i < n; ++i) {
    const auto& c = cases[i];
    const bool no_direction = c.label == "zero" || c.label == "NaN" || c.label == "inf" ||
                              c.label == "inf and NaN";
    if (!no_direction) continue;
    INFO("n = " << show3(c.x, c.y, c.z));
    const float4* got[3] = {&gpu[i].t, &gpu[i].b, &gpu[i].n};
    for (int k = 0; k < 3; ++k) {  // (1,0,0), (0,1,0), (0,0,1); zeros may carry a sign
      CHECK(got[k]->x == (k == 0 ? 1.0f : 0.0f));
      CHECK(got[k]->y == (k == 1 ? 1.0f : 0.0f));
      CHECK(got[k]->z == (k == 2 ? 1.0f : 0.0f));
    }
  }
}

// =================================================================================================
// Cosine-weighted hemisphere
// =================================================================================================

namespace {

struct hemi_out {
  float4 dir;    // direction, w = vplkit_cosine_hemisphere_pdf(direction.z)
  float4 polar;  // disk.xy, polar r, polar phi
};

}  // namespace

TEST_CASE("cosine_hemisphere.glsl: random u and the hard cases") {
  const bool ftz = device_flushes_denormals();
  std::vector<float> u;  // pairs
  std::vector<std::string> label;
  input_rng g(7);
  for (int i = 0; i < 100000; ++i) {
    u.push_back(g.uniform_float());
    u.push_back(g.uniform_float());
    label.push_back("random");
  }
  const float one_minus_ulp = 1.0f - 1.0f / 16777216.0f;  // 0x3F7FFFFF
  const float half_minus_ulp = 0.5f - 1.0f / 33554432.0f;
  const float half_plus_ulp = 0.5f + 1.0f / 16777216.0f;
  const std::vector<float> edge = {0.0f, denorm_min, 1e-30f, half_minus_ulp, 0.5f,
                                   half_plus_ulp, one_minus_ulp, 1.0f};
  for (float a : edge)
    for (float b : edge) {
      u.push_back(a);
      u.push_back(b);
      label.push_back("edge values");
    }
  for (float a : {-1e-7f, -0.5f, 1.0000001f, 2.0f}) {  // slightly / far outside [0,1]: clamped
    for (float b : {0.3f, 0.5f, -1e-7f, 1.0000001f}) {
      u.push_back(a);
      u.push_back(b);
      label.push_back("outside [0,1]");
    }
  }
  const std::size_t n = label.size();
  const auto gpu = run_compute<hemi_out>(per_item(R"(
#include "vplkit/sampling/cosine_hemisphere.glsl"
struct R { vec4 dir; vec4 polar; };
)",
                                                  {input(0, u, "vec2 u")}, "R result", R"(
  vec3 d = vplkit_sample_cosine_hemisphere(u[i]);
  vplkit_concentric_polar p = vplkit_concentric_disk_polar(u[i]);
  result[i].dir = vec4(d, vplkit_cosine_hemisphere_pdf(d.z));
  result[i].polar = vec4(vplkit_concentric_disk(u[i]), p.r, p.phi);)"),
                                         n);
  std::vector<float> g_r, c_r, g_phi, c_phi, g_xy, c_xy, g_z, c_z, g_pdf, c_pdf;
  std::vector<double> e_xy, e_z;
  {
    cpu_denormals_like_device mode(ftz);
    for (std::size_t i = 0; i < n; ++i) {
      const vplkit::vec2<float> ui(u[2 * i], u[2 * i + 1]);
      const auto p = vplkit::concentric_disk_polar(ui);
      const auto d = vplkit::sample_cosine_hemisphere(ui);
      const auto disk = vplkit::concentric_disk(ui);
      const auto de = vplkit::sample_cosine_hemisphere(vplkit::vec2<double>(ui.x, ui.y));
      g_r.push_back(gpu[i].polar.z);
      c_r.push_back(p.r);
      g_phi.push_back(gpu[i].polar.w);
      c_phi.push_back(p.phi);
      g_xy.insert(g_xy.end(), {gpu[i].dir.x, gpu[i].dir.y, gpu[i].polar.x, gpu[i].polar.y});
      c_xy.insert(c_xy.end(), {d.x, d.y, disk.x, disk.y});
      e_xy.insert(e_xy.end(), {de.x, de.y, de.x, de.y});
      g_z.push_back(gpu[i].dir.z);
      c_z.push_back(d.z);
      e_z.push_back(de.z);
      g_pdf.push_back(gpu[i].dir.w);
      c_pdf.push_back(vplkit::cosine_hemisphere_pdf(gpu[i].dir.z));  // pdf of the GPU's own z
    }
  }
  auto describe = [&](std::size_t per) {
    return [&, per](std::size_t i) {
      const std::size_t k = i / per;
      return "u = (" + show(u[2 * k]) + ", " + show(u[2 * k + 1]) + ") [" + label[k] + "]";
    };
  };
  // r is 2u - 1 clamped: exact on both sides (2u is exact; fma(2, u, -1) rounds the same value).
  VPLKIT_CHECK_PARITY(compare_floats(g_r, c_r, within_ulps(0), describe(1), "concentric polar r (exact)"));
  // phi: one division and one multiply (plus a subtraction) on both sides; IEEE division gives the
  // same bits, GLSL allows 2.5 ulp for the division.
  VPLKIT_CHECK_PARITY(compare_floats(g_phi, c_phi, within_ulps(4) | within_abs(eps), describe(1),
                                     "concentric polar phi"));
  // x, y = r cos(phi), r sin(phi): the GPU's cos/sin are approximations (GLSL bounds them only
  // loosely). Absolute bound 1e-6 (~8 eps): llvmpipe measures well below it (see the report and
  // docs/glsl/sampling.md); NVIDIA's documented sin/cos.approx error, 2^-20.9 ~ 5e-7, fits too.
  VPLKIT_CHECK_PARITY(compare_floats(g_xy, c_xy, within_abs(1e-6), describe(4),
                                     "direction x,y and disk x,y vs C++ float"));
  if (!ftz) {
    VPLKIT_CHECK_PARITY(compare_floats(g_xy, e_xy, within_abs(1e-6), describe(4),
                                       "direction x,y and disk x,y vs C++ double"));
  }
  // z = sqrt of the same float (1 - |r|)(1 + |r|) on both sides: only sqrt may differ (GLSL: it
  // is inversesqrt-based on many GPUs, ~2 ulp).
  VPLKIT_CHECK_PARITY(compare_floats(g_z, c_z, within_ulps(2), describe(1), "direction z vs C++ float"));
  // The pdf is one multiply of the same float by 1/pi: exact (a denormal product may flush).
  VPLKIT_CHECK_PARITY(compare_floats(g_pdf, c_pdf, within_ulps(0) | within_abs(flt_min), describe(1),
                                     "vplkit_cosine_hemisphere_pdf(z)"));
  // The GPU's directions: unit to within 1e-6 (double on the host), z >= 0, finite.
  std::size_t bad = 0;
  double worst = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = gpu[i].dir.x, y = gpu[i].dir.y, z = gpu[i].dir.z;
    const double e = std::abs(std::sqrt(x * x + y * y + z * z) - 1.0);
    if (!(e <= 2e-6) || !(z >= 0.0) || !std::isfinite(gpu[i].dir.w)) ++bad;
    if (e > worst) worst = e;
  }
  std::cout << "  GPU directions: worst | |d| - 1 | = " << worst / eps << " eps\n";
  CHECK(bad == 0);
  // The corners and the centre land where they must (rim z = 0, pole z = 1) on the GPU too.
  for (std::size_t i = 100000; i < n; ++i) {
    const float a = u[2 * i], b = u[2 * i + 1];
    if ((a == 0.0f || a == 1.0f) && (b == 0.0f || b == 1.0f)) CHECK(gpu[i].dir.z == 0.0f);
    if (a == 0.5f && b == 0.5f) {
      CHECK(gpu[i].dir.z == 1.0f);
      CHECK(gpu[i].dir.x == 0.0f);
    }
  }
}

TEST_CASE("cosine_hemisphere.glsl: cosine_hemisphere_pdf over random and special cosines") {
  device_flushes_denormals();  // prints whether it does: the reference is the same either way
  std::vector<float> c = {0.0f, -0.0f, denorm_min, 1e-40f, flt_min, 1e-30f, 0.5f, 1.0f,
                          1.0f - 1.0f / 16777216.0f, -1.0f, 2.0f, flt_max, inf, -inf, qnan};
  input_rng g(8);
  while (c.size() < 100000u) c.push_back(static_cast<float>(2.4 * g.uniform() - 1.2));
  const auto gpu = run_compute<float>(per_item(R"(#include "vplkit/sampling/cosine_hemisphere.glsl")",
                                               {input(0, c, "float c")}, "float pdf",
                                               "pdf[i] = vplkit_cosine_hemisphere_pdf(c[i]);"),
                                      c.size());
  std::vector<float> cpu(c.size());
  {
    // The plain reference: the normal-range contract (docs/math.md, "GPU arithmetic model") makes it the
    // answer of a flushing device too (the [ftz-daz] run checks it under flushing).
    for (std::size_t i = 0; i < c.size(); ++i) cpu[i] = vplkit::cosine_hemisphere_pdf(c[i]);
  }
  // One multiply by the same constant: bit-exact (NaN -> 0 on both sides).
  VPLKIT_CHECK_PARITY(compare_floats(gpu, cpu, within_ulps(0),
                                     [&](std::size_t i) { return "cos = " + show(c[i]); },
                                     "vplkit_cosine_hemisphere_pdf"));
  for (float v : gpu) CHECK_FALSE(std::isnan(v));
}
