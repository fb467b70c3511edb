// SPDX-License-Identifier: MIT
#include <vplkit/core/error.hpp>
#include <vplkit/core/vector.hpp>
#include <catch2/catch.hpp>

TEST_CASE("invalid_input carries the vplkit prefix", "[core]") {
  const vplkit::invalid_input e("bad weight at index 3");
  REQUIRE(std::string(e.what()) == "vplkit: bad weight at index 3");
}

TEST_CASE("vec3 is GLM's vec3", "[core]") {
  const vplkit::vec3<float> v(1.0f, 2.0f, 2.0f);
  REQUIRE(glm::length(v) == Approx(3.0f));
}
