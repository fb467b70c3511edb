// SPDX-License-Identifier: MIT
// docs/math.md section 10, "MIS: both pdfs 0, one infinite, denormal", and more (denormal counts
// and pdfs count as 0: "GPU arithmetic model"). Every case in
// float and double; nothing may be NaN or infinite; the weights of the two strategies add up to 1
// (within 2 ulps) whenever at least one strategy has n > 0 and p > 0, and are both 0 otherwise.
#include <vplkit/mis/heuristics.hpp>
#include <vplkit/mis/pdf_conversion.hpp>

#include <special_values.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <vector>

using namespace vplkit;

namespace {

template <class T> bool ok(T v) { return std::isfinite(v); }

// Checks both heuristics and balance_combined at (n1,p1,n2,p2); returns the balance weight.
template <class T> T check_all(T n1, T p1, T n2, T p2, T f = T(1)) {
  INFO("n1 " << n1 << " p1 " << p1 << " n2 " << n2 << " p2 " << p2);
  const T b1 = balance_heuristic(n1, p1, n2, p2), b2 = balance_heuristic(n2, p2, n1, p1);
  const T w1 = power_heuristic(n1, p1, n2, p2), w2 = power_heuristic(n2, p2, n1, p1);
  const T c = balance_combined(f, n1, p1, n2, p2);
  REQUIRE(ok(b1));
  REQUIRE(ok(b2));
  REQUIRE(ok(w1));
  REQUIRE(ok(w2));
  REQUIRE(ok(c));
  CHECK(b1 >= T(0));
  CHECK(b1 <= T(1));
  CHECK(w1 >= T(0));
  CHECK(w1 <= T(1));
  // Counts and pdfs below the smallest normal T count as 0.
  const T lo = std::numeric_limits<T>::min();
  const bool live1 = n1 >= lo && std::isfinite(n1) && p1 >= lo;
  const bool live2 = n2 >= lo && std::isfinite(n2) && p2 >= lo;
  const T tol = T(2) * std::numeric_limits<T>::epsilon();
  if (live1 || live2) {
    CHECK(std::abs(b1 + b2 - T(1)) <= tol);
    CHECK(std::abs(w1 + w2 - T(1)) <= tol);
  } else {
    CHECK(b1 == T(0));
    CHECK(b2 == T(0));
    CHECK(w1 == T(0));
    CHECK(w2 == T(0));
    CHECK(c == T(0));
  }
  return b1;
}

template <class T> void both_zero() {
  CHECK(check_all(T(1), T(0), T(1), T(0)) == T(0));
  CHECK(check_all(T(4), T(0), T(9), T(-0.0)) == T(0));
  CHECK(balance_combined(T(5), T(1), T(0), T(1), T(0)) == T(0));
}

template <class T> void one_infinite() {
  const T inf = std::numeric_limits<T>::infinity();
  CHECK(check_all(T(1), inf, T(1), T(0.5)) == T(1));
  CHECK(check_all(T(1), T(0.5), T(1), inf) == T(0));
  CHECK(check_all(T(3), inf, T(2), T(0)) == T(1));
  CHECK(check_all(T(3), inf, T(2), std::numeric_limits<T>::max()) == T(1));
  CHECK(power_heuristic(T(1), inf, T(1), T(1e30)) == T(1));
  // the denominator is infinite: a continuous sample's share vanishes
  CHECK(balance_combined(T(7), T(1), inf, T(1), T(0.5)) == T(0));
  CHECK(balance_combined(inf, T(1), inf, T(1), T(0.5)) == T(0));
}

template <class T> void both_infinite() {
  const T inf = std::numeric_limits<T>::infinity();
  CHECK(check_all(T(1), inf, T(1), inf) == T(0.5));
  CHECK(check_all(T(1), inf, T(3), inf) == T(0.25));  // by counts: n1 / (n1 + n2)
  CHECK(power_heuristic(T(1), inf, T(3), inf) == Approx(T(0.1)));  // n1^2 / (n1^2 + n2^2)
  CHECK(balance_combined(T(1), T(1), inf, T(1), inf) == T(0));
}

template <class T> void denormal() {
  // The normal-range contract (heuristics.hpp, docs/math.md, "GPU arithmetic model"): a denormal count or pdf
  // counts as 0, as on a GPU that flushes it; tiny normal pdfs are rescaled, not squared.
  const T d = std::numeric_limits<T>::denorm_min();
  const T m = std::numeric_limits<T>::min();  // smallest normal
  CHECK(check_all(T(1), d, T(1), d) == T(0));
  CHECK(check_all(T(1), T(3) * d, T(1), d) == T(0));
  CHECK(check_all(T(1), d, T(1), T(1)) == T(0));
  CHECK(check_all(T(1), T(1), T(1), d) == T(1));
  CHECK(check_all(d, T(1), T(1), T(1)) == T(0));
  CHECK(check_all(T(1), m, T(1), m) == T(0.5));
  CHECK(check_all(T(1), T(3) * m, T(1), m) == T(0.75));
  // squares of 3m and m underflow in a naive power heuristic; rescaled: 9 / 10
  CHECK(power_heuristic(T(1), T(3) * m, T(1), m) == Approx(T(0.9)));
  CHECK(power_heuristic(T(1), m, T(2), m) == Approx(T(0.2)));
  CHECK(check_all(T(1), m, T(1), T(1)) <= T(4) * std::numeric_limits<T>::epsilon());
  // f / (n p) with a tiny denominator overflows: guarded to 0, never inf
  CHECK(balance_combined(T(4), T(1), m, T(1), T(0)) == T(0));
  CHECK(balance_combined(T(1), T(1), d, T(1), T(0)) == T(0));
  CHECK(balance_combined(T(1), T(1), m, T(1), T(0)) == T(1) / m);  // 2^126: finite
  CHECK(balance_combined(d, T(1), m, T(1), m) == T(0));  // a denormal f
  CHECK(balance_combined(m, T(1), m, T(1), m) == T(0.5));
  CHECK(balance_combined(m, T(1), m, T(1), T(0)) == T(1));
}

template <class T> void huge() {
  const T h = T(1e38), big = std::numeric_limits<T>::max();
  CHECK(check_all(T(4), h, T(4), h) == T(0.5));  // n p overflows float without rescaling
  CHECK(check_all(T(1), big, T(1), big) == T(0.5));
  CHECK(check_all(T(1), big, T(3), big) == T(0.25));
  CHECK(power_heuristic(T(1), h, T(1), h) == T(0.5));  // squares overflow without rescaling
  CHECK(power_heuristic(T(1), T(3) * T(1e37), T(1), T(1e37)) == Approx(T(0.9)));
  CHECK(balance_combined(h, T(4), h, T(4), h) == Approx(T(0.125)));
  CHECK(balance_combined(T(1), T(16), big, T(16), big) >= T(0));
  CHECK(check_all(big, big, big, big) == T(0.5));  // even n1 p1 + n2 p2 of the scaled terms
}

template <class T> void count_zero() {
  const T inf = std::numeric_limits<T>::infinity();
  CHECK(check_all(T(0), T(1), T(3), T(0.5)) == T(0));
  CHECK(check_all(T(3), T(0.5), T(0), T(1)) == T(1));
  CHECK(check_all(T(0), inf, T(2), T(1)) == T(0));  // no 0 * inf
  CHECK(check_all(T(2), T(1), T(0), inf) == T(1));
  CHECK(check_all(T(0), T(1), T(0), T(1)) == T(0));
  CHECK(balance_combined(T(2), T(0), T(1), T(4), T(0.25)) == T(2));
  CHECK(balance_combined(T(2), T(0), inf, T(4), T(0.25)) == T(2));
}

// The special values and the large ones a count or pdf can take.
template <class T> std::vector<T> specials() {
  return vplkit_test::special_values_and<T>({T(1e-20), T(3), T(1e20), std::numeric_limits<T>::max()});
}

template <class T> void sweep() {
  const std::vector<T> s = specials<T>();
  for (T n1 : s)
    for (T p1 : s)
      for (T n2 : {T(0), T(1), T(5), std::numeric_limits<T>::quiet_NaN()})
        for (T p2 : s)
          for (T f : {T(0), T(1), T(-2), std::numeric_limits<T>::max()}) check_all(n1, p1, n2, p2, f);
}

template <class T> void pdf_conversion_specials() {
  const std::vector<T> s = specials<T>();
  for (T a : s)
    for (T b : s)
      for (T c : s)
        for (T d : {T(-1), T(0), T(1e-30), T(0.3), T(1), std::numeric_limits<T>::infinity(),
                    std::numeric_limits<T>::quiet_NaN()}) {
          const T p = vpl_pdf_solid_angle(a, b, c, d);
          REQUIRE(!std::isnan(p));
          CHECK(p >= T(0));
          const mis_weight_pair<T> w = mis_weights_as_published(d, b, a);
          REQUIRE(ok(w.gathering));
          REQUIRE(ok(w.vpl));
          REQUIRE(!std::isnan(cosine_pdf_as_published(a, b)));
          REQUIRE(!std::isnan(cosine_pdf_solid_angle(a)));
        }
}

}  // namespace

TEST_CASE("MIS hard case: both pdfs 0") {
  both_zero<float>();
  both_zero<double>();
}

TEST_CASE("MIS hard case: one pdf infinite") {
  one_infinite<float>();
  one_infinite<double>();
}

TEST_CASE("MIS hard case: both pdfs infinite") {
  both_infinite<float>();
  both_infinite<double>();
}

TEST_CASE("MIS hard case: denormal pdfs") {
  denormal<float>();
  denormal<double>();
}

TEST_CASE("MIS hard case: huge pdfs (1e38, max)") {
  huge<float>();
  huge<double>();
}

TEST_CASE("MIS hard case: n1 or n2 zero") {
  count_zero<float>();
  count_zero<double>();
}

TEST_CASE("MIS hard case: every combination of special values is finite and a partition of unity") {
  sweep<float>();
  sweep<double>();
}

TEST_CASE("MIS hard case: pdf conversions and as-published weights never NaN") {
  pdf_conversion_specials<float>();
  pdf_conversion_specials<double>();
}

TEST_CASE("MIS hard case: VPL patch facing away, grazing, zero area, zero distance") {
  const double inf = std::numeric_limits<double>::infinity();
  CHECK(vpl_pdf_solid_angle(0.1, 4.0, 0.01, -0.3) == 0.0);   // x behind the patch
  CHECK(vpl_pdf_solid_angle(0.1, 4.0, 0.01, 0.0) == 0.0);    // exactly edge-on: no contribution
  CHECK(vpl_pdf_solid_angle(0.1, 4.0, 0.01, 1e-300) == Approx(4e301));  // grazing: huge density
  CHECK(vpl_pdf_solid_angle(0.1f, 4.0f, 0.01f, 2e-38f) == std::numeric_limits<float>::infinity());
  // A cosine below the smallest normal float counts as 0 (a GPU may flush it): no contribution.
  CHECK(vpl_pdf_solid_angle(0.1f, 4.0f, 0.01f, 1e-38f) == 0.0f);
  // Exactly where the density leaves the float range: +inf above FLT_MAX, 0 below FLT_MIN, with
  // operands (1e38 areas and distances) whose naive quotients a GPU evaluates through a denormal
  // reciprocal.
  CHECK(vpl_pdf_solid_angle(1.0f, 3e38f, 1e38f, 1.0f) == Approx(3.0f));
  CHECK(vpl_pdf_solid_angle(1e-30f, 3e38f, 1e-31f, 1.0f) == std::numeric_limits<float>::infinity());
  CHECK(vpl_pdf_solid_angle(1e-30f, 1e-30f, 1e30f, 1.0f) == 0.0f);
  CHECK(vpl_pdf_solid_angle(0.5f, 3e38f, 1e38f, 0.5f) == Approx(3.0f));
  CHECK(vpl_pdf_solid_angle(0.1, 4.0, 0.0, 0.5) == inf);     // zero area: all mass in no solid angle
  CHECK(vpl_pdf_solid_angle(0.1, 0.0, 0.01, 0.5) == 0.0);    // x on the VPL: gathering takes over
  CHECK(vpl_pdf_solid_angle(0.0, 4.0, 0.01, 0.5) == 0.0);    // never drawn
  CHECK(vpl_pdf_solid_angle(0.1, 4.0, inf, 0.5) == 0.0);
  CHECK(vpl_pdf_solid_angle(0.1, inf, 0.01, 0.5) == inf);
  CHECK(vpl_pdf_solid_angle(0.1f, 1e-30f, 1e30f, 0.5f) == 0.0f);  // underflow, not NaN
  // an infinite p2 from a zero-area patch in the heuristics: the VPL strategy takes the sample
  const double p2 = vpl_pdf_solid_angle(0.1, 4.0, 0.0, 0.5);
  CHECK(balance_heuristic(8.0, cosine_pdf_solid_angle(0.7), 8.0, p2) == 0.0);
  CHECK(balance_combined(1.0, 8.0, cosine_pdf_solid_angle(0.7), 8.0, p2) == 0.0);
}
