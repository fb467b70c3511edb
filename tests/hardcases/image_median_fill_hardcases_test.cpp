// SPDX-License-Identifier: MIT
// docs/math.md section 10, median fill: borders, all-hole neighbourhoods; nothing NaN or infinite.
// One TEST_CASE per hard case.
#include <vplkit/image/median_fill.hpp>
#include <vplkit/paraboloid/texel_grid.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace {

const auto all_fillable = [](int, int) { return true; };

template <class T>
void require_all_finite(const std::vector<T>& v) {
  for (std::size_t i = 0; i < v.size(); ++i) {
    INFO("texel " << i);
    REQUIRE(std::isfinite(v[i]));
  }
}

}  // namespace

TEST_CASE("median fill hard case: borders and corners use only in-bounds neighbours", "[image][hardcase]") {
  // 4x3 image, holes at the four corners and the middle of each border, values elsewhere.
  //   y=0:  0  1  0  2
  //   y=1:  3  4  5  0
  //   y=2:  0  6  0  7
  const std::vector<float> in = {0, 1, 0, 2, 3, 4, 5, 0, 0, 6, 0, 7};
  std::vector<float> out(in.size(), -1.0f);
  vplkit::median_fill(in.data(), out.data(), 4, 3, all_fillable);
  // (0,0): neighbours (1,0)=1, (0,1)=3, (1,1)=4 -> 3.
  REQUIRE(out[0] == 3.0f);
  // (2,0): (1,0)=1, (3,0)=2, (1,1)=4, (2,1)=5, (3,1)=hole -> 1,2,4,5 -> lower median 2.
  REQUIRE(out[2] == 2.0f);
  // (3,1), right border: (2,0)=hole, (3,0)=2, (2,1)=5, (2,2)=hole, (3,2)=7 -> 2,5,7 -> 5.
  REQUIRE(out[7] == 5.0f);
  // (0,2), corner: (0,1)=3, (1,1)=4, (1,2)=6 -> 4.
  REQUIRE(out[8] == 4.0f);
  // (2,2), bottom border: (1,1)=4, (2,1)=5, (3,1)=hole, (1,2)=6, (3,2)=7 -> 4,5,6,7 -> 5.
  REQUIRE(out[10] == 5.0f);
  require_all_finite(out);

  // 1 x N and N x 1 images: the window degenerates to a line.
  const std::vector<double> row = {0, 2, 0, 0, 8};
  std::vector<double> row_out(row.size());
  vplkit::median_fill(row.data(), row_out.data(), 5, 1, all_fillable);
  REQUIRE(row_out == std::vector<double>{2, 2, 2, 8, 8});
  vplkit::median_fill(row.data(), row_out.data(), 1, 5, all_fillable);
  REQUIRE(row_out == std::vector<double>{2, 2, 2, 8, 8});

  // 1x1: a lone hole has no neighbours and stays 0; a lone value is copied.
  const float hole = 0.0f, value = 0.25f;
  float one = -1.0f;
  vplkit::median_fill(&hole, &one, 1, 1, all_fillable);
  REQUIRE(one == 0.0f);
  vplkit::median_fill(&value, &one, 1, 1, all_fillable);
  REQUIRE(one == 0.25f);
}

TEST_CASE("median fill hard case: all-hole neighbourhoods stay 0", "[image][hardcase]") {
  // An all-zero image stays all zero.
  std::vector<float> zeros(7 * 5, 0.0f), out(zeros.size(), 1.0f);
  vplkit::median_fill(zeros.data(), out.data(), 7, 5, all_fillable);
  for (float v : out) REQUIRE(v == 0.0f);

  // A single value at the centre of a 7x7 image fills exactly its 8 neighbours; texels two steps
  // away see only holes and stay 0.
  std::vector<double> in(49, 0.0), o(49, -1.0);
  in[3 * 7 + 3] = 0.5;
  vplkit::median_fill(in.data(), o.data(), 7, 7, all_fillable);
  for (int y = 0; y < 7; ++y)
    for (int x = 0; x < 7; ++x) {
      const bool near = std::abs(x - 3) <= 1 && std::abs(y - 3) <= 1;
      REQUIRE(o[std::size_t(y * 7 + x)] == (near ? 0.5 : 0.0));
    }

  // A single value in a corner fills its 3 in-bounds neighbours only.
  std::vector<double> c(9, 0.0), co(9, -1.0);
  c[8] = 3.0;
  vplkit::median_fill(c.data(), co.data(), 3, 3, all_fillable);
  REQUIRE(co == std::vector<double>{0, 0, 0, 0, 3, 3, 0, 3, 3});

  // DPRSM whose weights are all zero: stays all zero (no NaN, no garbage).
  std::vector<float> d(2 * 8 * 8, 0.0f), dout(d.size(), 1.0f);
  vplkit::median_fill_dprsm(d.data(), dout.data(), 8);
  for (float v : dout) REQUIRE(v == 0.0f);
}

TEST_CASE("median fill hard case: NaN or infinite input is rejected, naming the texel", "[image][hardcase]") {
  std::vector<float> in(12, 1.0f), out(12);
  in[2 * 4 + 1] = std::numeric_limits<float>::quiet_NaN();  // (x=1, y=2)
  try {
    vplkit::median_fill(in.data(), out.data(), 4, 3, all_fillable);
    FAIL("no exception");
  } catch (const vplkit::invalid_input& e) {
    const std::string what = e.what();
    REQUIRE(what.find("x=1, y=2") != std::string::npos);
    REQUIRE(what.find("NaN") != std::string::npos);
  }
  in[2 * 4 + 1] = 1.0f;
  in[3] = -std::numeric_limits<float>::infinity();  // (x=3, y=0)
  REQUIRE_THROWS_WITH(vplkit::median_fill(in.data(), out.data(), 4, 3, all_fillable),
                      Catch::Contains("x=3, y=0") && Catch::Contains("infinite"));

  // The DPRSM variant names the face as well.
  const int R = 4;
  std::vector<double> d(2 * R * R, 0.0), dout(d.size());
  d[std::size_t(vplkit::texel_index(1, 2, 3, R))] = std::numeric_limits<double>::quiet_NaN();
  REQUIRE_THROWS_WITH(vplkit::median_fill_dprsm(d.data(), dout.data(), R),
                      Catch::Contains("face 1") && Catch::Contains("x=2, y=3"));
}

TEST_CASE("median fill hard case: extreme magnitudes produce no NaN or Inf", "[image][hardcase]") {
  // The fill value is always one of the neighbours' own values (no arithmetic), so the largest
  // finite float, denormals and mixed signs come through unchanged.
  const float big = std::numeric_limits<float>::max(), den = std::numeric_limits<float>::denorm_min();
  const std::vector<float> in = {big, 0, big, den, 0, -big, big, 0, den};
  std::vector<float> out(in.size());
  vplkit::median_fill(in.data(), out.data(), 3, 3, all_fillable);
  require_all_finite(out);
  // Centre: big, big, den, -big, big, den -> sorted -big, den, den, big, big, big -> lower median den.
  REQUIRE(out[4] == den);
  // (1,0): big, big, den, -big (and centre hole) -> -big, den, big, big -> den.
  REQUIRE(out[1] == den);
  // (1,2): den, -big, big, den -> -big, den, den, big -> den.
  REQUIRE(out[7] == den);
}

TEST_CASE("median fill hard case: texels outside the paraboloid disk stay 0", "[image][hardcase]") {
  // A DPRSM face that is all holes except a full ring of values just inside the rim: the corner
  // texels outside the disk have non-hole neighbours but must stay 0.
  for (int R : {1, 2, 3, 7, 16, 33}) {
    std::vector<float> in(std::size_t(2 * R * R), 0.0f), out(in.size(), -1.0f);
    for (int f = 0; f < 2; ++f)
      for (int y = 0; y < R; ++y)
        for (int x = 0; x < R; ++x)
          if (vplkit::texel_is_valid(x, y, R) && (x + y) % 2 == 0)
            in[std::size_t(vplkit::texel_index(f, x, y, R))] = 2.0f;
    vplkit::median_fill_dprsm(in.data(), out.data(), R);
    for (int f = 0; f < 2; ++f)
      for (int y = 0; y < R; ++y)
        for (int x = 0; x < R; ++x) {
          const float v = out[std::size_t(vplkit::texel_index(f, x, y, R))];
          INFO("R " << R << " face " << f << " x " << x << " y " << y);
          REQUIRE(std::isfinite(v));
          if (!vplkit::texel_is_valid(x, y, R)) REQUIRE(v == 0.0f);
          else REQUIRE(v == 2.0f);  // a valid hole's inward neighbour is valid and holds 2
        }
  }
}
