// SPDX-License-Identifier: MIT
// Known answers of the counter-based RNG. The GLSL mirror must reproduce these exact bits; the
// values were computed by an independent Python implementation of the algorithm in rng.hpp, and
// pcg_hash(0), (1), (2), (4096), (0xDEADBEEF) agree with golden values published elsewhere for
// Jarzynski & Olano's pcg_hash.
#include <vplkit/sampling/rng.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <vector>

using namespace vplkit;

namespace {

void check_sequence(std::uint32_t key, std::uint32_t counter, const std::uint32_t (&expected)[8]) {
  counter_rng r{key, counter};
  for (int i = 0; i < 8; ++i) {
    INFO("key " << key << " counter " << counter << " draw " << i);
    CHECK(rng_next_u32(r) == expected[i]);
  }
  CHECK(r.counter == counter + 8u);  // wraps like GLSL uint
}

}  // namespace

TEST_CASE("pcg_hash known answers") {
  CHECK(pcg_hash(0u) == 0x07BB2FE2u);
  CHECK(pcg_hash(1u) == 0xA8BEEA3Cu);
  CHECK(pcg_hash(2u) == 0x7A7ECC88u);
  CHECK(pcg_hash(4096u) == 0x9410F6B5u);  // 2484139701
  CHECK(pcg_hash(0xDEADBEEFu) == 0x67299972u);
  CHECK(pcg_hash(0x80000000u) == 0x21C72646u);
  CHECK(pcg_hash(0xFFFFFFFFu) == 0xE62A4902u);
  CHECK(pcg_hash(12345u) == 0xF45EAD0Eu);
}

TEST_CASE("rng_key known answers") {
  CHECK(rng_key(0u, 0u) == 0x7EF300CCu);
  CHECK(rng_key(1u, 0u) == 0x6F434657u);
  CHECK(rng_key(0u, 1u) == 0x49046676u);
  CHECK(rng_key(42u, 7u) == 0x09EE1509u);
  CHECK(rng_key(7u, 42u) == 0x736F85B2u);  // seed and stream are not interchangeable
  const counter_rng r = make_counter_rng(42u, 7u);
  CHECK(r.key == 0x09EE1509u);
  CHECK(r.counter == 0u);
}

TEST_CASE("rng_next_u32 known answers: first 8 outputs") {
  check_sequence(0u, 0u, {0x30BE035Eu, 0xE92A518Au, 0x7A0F8CF3u, 0xD3016361u, 0xD8D452F1u,
                          0x9BD91B45u, 0x48BA8FD4u, 0x80A6E29Du});
  check_sequence(1u, 0u, {0x5E6301B0u, 0xB1921CDEu, 0x7DEDA5D8u, 0xA5CD984Bu, 0x4F238228u,
                          0x89E4422Bu, 0x2F3D6980u, 0xA77AF8DFu});
  check_sequence(0xDEADBEEFu, 0u, {0x2FB44A75u, 0x40C3CF8Du, 0xF0F5A1DEu, 0xAE4399B9u,
                                   0x7D7DC222u, 0x6541F14Du, 0x7B89508Cu, 0xEB38D594u});
  // make_counter_rng(42, 7)
  check_sequence(0x09EE1509u, 0u, {0xE5A02CCEu, 0xF2D83641u, 0xAD35F443u, 0x83CD33D5u,
                                   0xBA7038EBu, 0x81FDF929u, 0xA7A8167Au, 0x0996A4A5u});
  // counter wrap-around: 0xFFFFFFFC .. 0x00000003
  check_sequence(123u, 0xFFFFFFFCu, {0x704B878Eu, 0xB34797EAu, 0xC9B105E6u, 0xEBFA7C2Au,
                                     0xAF6BB3EAu, 0x8FA3A6D0u, 0x822FCEC2u, 0x91601201u});
}

TEST_CASE("rng_next_float known answers are exact 24-bit values") {
  counter_rng r{0u, 0u};
  // 0x30BE035E >> 8 = 0x30BE03 -> 3194371 / 2^24, etc.; compared exactly (==).
  const float expected[8] = {0.19039934873580933f, 0.9108019471168518f, 0.47679972648620605f,
                             0.8242399096488953f,  0.8469897508621216f, 0.6087815165519714f,
                             0.2840966582298279f,  0.5025464296340942f};
  for (int i = 0; i < 8; ++i) CHECK(rng_next_float(r) == expected[i]);
  counter_rng a{0u, 0u};
  CHECK(rng_next_float(a) == float(0x30BE03u) / 16777216.0f);
}

TEST_CASE("uint_to_unit_float range and exactness") {
  CHECK(uint_to_unit_float(0u) == 0.0f);
  CHECK(uint_to_unit_float(0xFFu) == 0.0f);  // low 8 bits are dropped
  CHECK(uint_to_unit_float(0x100u) == std::ldexp(1.0f, -24));
  CHECK(uint_to_unit_float(0xFFFFFFFFu) == 1.0f - std::ldexp(1.0f, -24));
  CHECK(uint_to_unit_float(0xFFFFFFFFu) < 1.0f);
  CHECK(uint_to_unit_float(0x80000000u) == 0.5f);
  // Every 24-bit value maps to a distinct float and back.
  for (std::uint32_t v = 0; v < (1u << 24); v += 4099u) {
    const float f = uint_to_unit_float(v << 8);
    CHECK(std::uint32_t(double(f) * 16777216.0) == v);
  }
}

TEST_CASE("rng_next_double and rng_next_unit consume the same numbers as the float path") {
  counter_rng a = make_counter_rng(9u, 1234u), b = a, c = a, d = a;
  for (int i = 0; i < 1000; ++i) {
    const float f = rng_next_float(a);
    const double g = rng_next_double(b);
    CHECK(g == double(f));
    CHECK(rng_next_unit<double>(c) == double(f));
    CHECK(rng_next_unit<float>(d) == f);
    CHECK(f >= 0.0f);
    CHECK(f < 1.0f);
  }
  CHECK(a.counter == 1000u);
  CHECK(b.counter == 1000u);
  static_assert(std::is_trivially_copyable<counter_rng>::value, "plain value type");
}

TEST_CASE("a stream is a bijection of the counter: no repeats in a window") {
  // pcg_hash is a permutation of the 32-bit integers, so key + pcg_hash(c) and its hash are too:
  // one stream never repeats a value within 2^32 draws.
  counter_rng r{rng_key(5u, 77u), 0u};
  std::vector<std::uint32_t> v(1u << 20);
  for (auto& x : v) x = rng_next_u32(r);
  std::sort(v.begin(), v.end());
  CHECK(std::adjacent_find(v.begin(), v.end()) == v.end());
}
