// SPDX-License-Identifier: MIT
// Unit tests of the hole-aware 3x3 median fill (include/vplkit/image/median_fill.hpp).
#include <vplkit/image/median_fill.hpp>
#include <vplkit/paraboloid/texel_grid.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cstring>
#include <random>
#include <vector>

namespace {

// Straightforward reference: gather, std::sort, lower median.
template <class T, class F>
std::vector<T> reference_fill(const std::vector<T>& in, int w, int h, F fillable) {
  std::vector<T> out(in.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const T c = in[std::size_t(y * w + x)];
      if (c != T(0)) {
        out[std::size_t(y * w + x)] = c;
        continue;
      }
      std::vector<T> v;
      for (int yy = y - 1; yy <= y + 1; ++yy)
        for (int xx = x - 1; xx <= x + 1; ++xx)
          if ((xx != x || yy != y) && xx >= 0 && yy >= 0 && xx < w && yy < h && in[std::size_t(yy * w + xx)] != T(0))
            v.push_back(in[std::size_t(yy * w + xx)]);
      std::sort(v.begin(), v.end());
      out[std::size_t(y * w + x)] = (fillable(x, y) && !v.empty()) ? v[(v.size() - 1) / 2] : T(0);
    }
  return out;
}

template <class T>
bool same_bits(T a, T b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

// The centre of a 3x3 image after the fill (every texel fillable).
template <class T>
T filled_centre(const std::array<T, 9>& in) {
  std::array<T, 9> out{};
  vplkit::median_fill(in.data(), out.data(), 3, 3, [](int, int) { return true; });
  return out[4];
}

template <class T>
void random_images_match_reference() {
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const int w = 1 + int(u(rng) * 17), h = 1 + int(u(rng) * 13);
    const double hole_fraction = u(rng);
    std::vector<T> in(std::size_t(w * h));
    for (T& v : in) v = u(rng) < hole_fraction ? T(0) : T(std::ldexp(u(rng) - 0.3, int(u(rng) * 20) - 10));
    // Few distinct values as well, so that ties (equal neighbours) occur.
    if (trial % 3 == 0)
      for (T& v : in) v = v == T(0) ? T(0) : T(int(u(rng) * 4) + 1);
    const auto fillable = [](int x, int y) { return (x * 7 + y * 3) % 5 != 0; };
    std::vector<T> out(in.size(), T(-1));
    vplkit::median_fill(in.data(), out.data(), w, h, fillable);
    const std::vector<T> ref = reference_fill(in, w, h, fillable);
    for (std::size_t i = 0; i < in.size(); ++i) {
      INFO("trial " << trial << " texel " << i);
      REQUIRE(same_bits(out[i], ref[i]));
    }
  }
}

}  // namespace

TEST_CASE("sort_small sorts every count up to 8, duplicates included", "[image]") {
  std::mt19937 rng(7);
  for (int count = 0; count <= 8; ++count) {
    for (int trial = 0; trial < 500; ++trial) {
      float v[8], r[8];
      for (int i = 0; i < count; ++i) v[i] = r[i] = float(int(rng() % 5)) - 2.0f;
      vplkit::sort_small(v, count);
      std::sort(r, r + count);
      for (int i = 0; i < count; ++i) REQUIRE(v[i] == r[i]);
    }
  }
}

TEST_CASE("median fill matches a std::sort reference on random images (float)", "[image]") {
  random_images_match_reference<float>();
}

TEST_CASE("median fill matches a std::sort reference on random images (double)", "[image]") {
  random_images_match_reference<double>();
}

TEST_CASE("median fill takes the lower median for an even neighbour count", "[image]") {
  const auto all = [](int, int) { return true; };
  // 3x1 image: hole in the middle, neighbours 5 and 3 -> lower median 3.
  {
    const float in[3] = {5.0f, 0.0f, 3.0f};
    float out[3];
    vplkit::median_fill(in, out, 3, 1, all);
    REQUIRE(out[1] == 3.0f);
  }
  // 3x3 image: hole in the centre, neighbours 1, 2, 3, 4 (the rest holes) -> 2.
  REQUIRE(filled_centre<double>({4, 0, 1, 0, 0, 0, 3, 0, 2}) == 2.0);
  // Odd count: neighbours 9, 1, 5 -> 5.
  REQUIRE(filled_centre<double>({9, 0, 0, 0, 0, 1, 0, 5, 0}) == 5.0);
  // Eight neighbours 1..8 -> element (8-1)/2 = 3 of the sorted list: 4.
  REQUIRE(filled_centre<float>({8, 1, 7, 2, 0, 6, 3, 5, 4}) == 4.0f);
}

TEST_CASE("median fill is one pass: filled values do not feed other fills", "[image]") {
  // 5x1: [7, 0, 0, 0, 9]. Texel 1 sees 7 (texel 2 is a hole), texel 3 sees 9, texel 2 sees only
  // holes and stays 0 even though its neighbours get filled.
  const float in[5] = {7, 0, 0, 0, 9};
  float out[5];
  vplkit::median_fill(in, out, 5, 1, [](int, int) { return true; });
  REQUIRE(out[0] == 7.0f);
  REQUIRE(out[1] == 7.0f);
  REQUIRE(out[2] == 0.0f);
  REQUIRE(out[3] == 9.0f);
  REQUIRE(out[4] == 9.0f);
}

TEST_CASE("median fill: non-holes copied bit for bit, non-fillable holes and -0 become +0", "[image]") {
  const float in[9] = {-0.0f, 2.5f, -1.0f, 0.0f, -0.0f, 1e-40f, 3.0f, 0.0f, 7.0f};
  float out[9];
  vplkit::median_fill(in, out, 3, 3, [](int x, int) { return x != 0; });
  REQUIRE(same_bits(out[0], 0.0f));   // -0 hole at x = 0: not fillable -> +0
  REQUIRE(same_bits(out[3], 0.0f));   // not fillable
  REQUIRE(same_bits(out[1], 2.5f));
  REQUIRE(same_bits(out[2], -1.0f));  // negative values are values, not holes
  REQUIRE(same_bits(out[5], 1e-40f)); // a denormal is not a hole
  // Centre (-0, fillable): neighbours 2.5, -1, 1e-40, 3, 7 -> sorted -1, 1e-40, 2.5, 3, 7 -> 2.5.
  REQUIRE(out[4] == 2.5f);
  // (1, 2): in-bounds neighbours (0,1) = 0 and (1,1) = -0 are holes; the non-holes 1e-40, 3, 7
  // give 3.
  REQUIRE(out[7] == 3.0f);
}

TEST_CASE("median fill rejects bad arguments", "[image]") {
  std::vector<float> img(16, 1.0f), out(16);
  const auto all = [](int, int) { return true; };
  REQUIRE_THROWS_AS(vplkit::median_fill(img.data(), img.data(), 4, 4, all), vplkit::invalid_input);
  // Partial overlap is aliasing too.
  REQUIRE_THROWS_AS(vplkit::median_fill(img.data(), img.data() + 3, 4, 3, all), vplkit::invalid_input);
  REQUIRE_THROWS_AS(vplkit::median_fill(img.data(), out.data(), 0, 4, all), vplkit::invalid_input);
  REQUIRE_THROWS_AS(vplkit::median_fill(img.data(), out.data(), 4, -1, all), vplkit::invalid_input);
  REQUIRE_THROWS_AS(vplkit::median_fill<float>(nullptr, out.data(), 4, 4, all), vplkit::invalid_input);
  REQUIRE_THROWS_AS(vplkit::median_fill<float>(img.data(), nullptr, 4, 4, all), vplkit::invalid_input);
  // Adjacent but not overlapping buffers are fine.
  REQUIRE_NOTHROW(vplkit::median_fill(img.data(), img.data() + 8, 4, 2, all));
  REQUIRE_THROWS_AS(vplkit::median_fill_dprsm(img.data(), img.data(), 2), vplkit::invalid_input);
  REQUIRE_THROWS_AS(vplkit::median_fill_dprsm(img.data(), out.data(), 0), vplkit::invalid_input);
}

TEST_CASE("DPRSM fill: only texels inside the disk are filled, faces never mix", "[image]") {
  const int R = 16;
  std::vector<double> in(std::size_t(2 * R * R), 0.0), out(in.size(), -1.0);
  // Face 0: everything 1 except holes; face 1: all holes except its first row (y = 0), which
  // touches the last row of face 0 in the flat array.
  for (int y = 0; y < R; ++y)
    for (int x = 0; x < R; ++x) {
      if (vplkit::texel_is_valid(x, y, R) && (x + y) % 3 != 0) in[std::size_t(y * R + x)] = 1.0;
      if (!vplkit::texel_is_valid(x, y, R)) in[std::size_t(y * R + x)] = 0.0;
    }
  for (int x = 0; x < R; ++x) in[std::size_t(R * R + x)] = 5.0;  // inside and outside the disk
  vplkit::median_fill_dprsm(in.data(), out.data(), R);
  for (int face = 0; face < 2; ++face)
    for (int y = 0; y < R; ++y)
      for (int x = 0; x < R; ++x) {
        const std::size_t i = std::size_t(vplkit::texel_index(face, x, y, R));
        INFO("face " << face << " x " << x << " y " << y);
        if (in[i] != 0.0) {
          REQUIRE(out[i] == in[i]);
        } else if (!vplkit::texel_is_valid(x, y, R)) {
          REQUIRE(out[i] == 0.0);
        } else if (face == 0) {
          REQUIRE(out[i] == 1.0);  // every valid face-0 hole has a non-hole neighbour here
        } else {
          // Face 1 holes next to its row 0 get 5; the rest stay 0; nothing comes from face 0.
          REQUIRE(out[i] == (y == 1 ? 5.0 : 0.0));
        }
      }
  // Face 0's last row is next to face 1's row 0 in memory: those holes must not see the 5s.
  for (int x = 0; x < R; ++x) REQUIRE(out[std::size_t((R - 1) * R + x)] != 5.0);
}
