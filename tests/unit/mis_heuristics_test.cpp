// SPDX-License-Identifier: MIT
#include <vplkit/mis/heuristics.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

using namespace vplkit;

TEST_CASE("balance heuristic: textbook values") {
  CHECK(balance_heuristic(1.0, 1.0, 1.0, 1.0) == 0.5);
  CHECK(balance_heuristic(1.0, 3.0, 1.0, 1.0) == Approx(0.75));
  CHECK(balance_heuristic(2.0, 1.0, 1.0, 2.0) == Approx(0.5));
  CHECK(balance_heuristic(4.0, 0.25, 1.0, 3.0) == Approx(1.0 / 4.0));
  CHECK(balance_heuristic(1.0f, 2.0f, 3.0f, 0.5f) == Approx(2.0f / 3.5f));
}

TEST_CASE("power heuristic: textbook values") {
  CHECK(power_heuristic(1.0, 1.0, 1.0, 1.0) == 0.5);
  CHECK(power_heuristic(1.0, 3.0, 1.0, 1.0) == Approx(0.9));
  CHECK(power_heuristic(2.0, 1.0, 1.0, 1.0) == Approx(0.8));
  CHECK(power_heuristic(1.0f, 2.0f, 3.0f, 0.5f) == Approx(4.0f / (4.0f + 2.25f)));
}

TEST_CASE("heuristics are a partition of unity and symmetric") {
  for (double n1 : {1.0, 3.0, 64.0})
    for (double n2 : {1.0, 7.0})
      for (double p1 : {1e-3, 0.2, 5.0, 1e4})
        for (double p2 : {1e-5, 0.7, 30.0}) {
          const double b = balance_heuristic(n1, p1, n2, p2) + balance_heuristic(n2, p2, n1, p1);
          const double p = power_heuristic(n1, p1, n2, p2) + power_heuristic(n2, p2, n1, p1);
          CHECK(std::abs(b - 1.0) <= 4e-16);
          CHECK(std::abs(p - 1.0) <= 4e-16);
          CHECK(balance_heuristic(n1, p1, n2, p2) ==
                Approx(n1 * p1 / (n1 * p1 + n2 * p2)).epsilon(1e-15));
        }
}

TEST_CASE("balance_combined equals the balance weight times f / (n p) of either strategy") {
  const double f = 2.5, n1 = 3, p1 = 0.4, n2 = 5, p2 = 1.7;
  const double v = balance_combined(f, n1, p1, n2, p2);
  CHECK(v == Approx(f / (n1 * p1 + n2 * p2)).epsilon(1e-15));
  CHECK(v == Approx(balance_heuristic(n1, p1, n2, p2) * f / (n1 * p1)).epsilon(1e-15));
  CHECK(v == Approx(balance_heuristic(n2, p2, n1, p1) * f / (n2 * p2)).epsilon(1e-15));
  CHECK(balance_combined(-f, n1, p1, n2, p2) == -v);
  CHECK(balance_combined(1.0f, 1.0f, 0.5f, 1.0f, 0.25f) == Approx(1.0f / 0.75f));
}

TEST_CASE("invalid counts and pdfs count as zero") {
  const double nan = std::nan("");
  CHECK(balance_heuristic(-1.0, 1.0, 1.0, 1.0) == 0.0);
  CHECK(balance_heuristic(1.0, -1.0, 1.0, 1.0) == 0.0);
  CHECK(balance_heuristic(1.0, nan, 1.0, 1.0) == 0.0);
  CHECK(balance_heuristic(1.0, 1.0, nan, 1.0) == 1.0);
  CHECK(balance_heuristic(nan, 1.0, 1.0, 1.0) == 0.0);
  CHECK(power_heuristic(1.0, 1.0, 1.0, nan) == 1.0);
  CHECK(balance_combined(nan, 1.0, 1.0, 1.0, 1.0) == 0.0);
  CHECK(balance_combined(1.0, 1.0, nan, 1.0, 1.0) == 1.0);
  CHECK(mis_clean_count(std::numeric_limits<double>::infinity()) == 0.0);
}
