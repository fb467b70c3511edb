// SPDX-License-Identifier: MIT
#pragma once
// One exception type for bad input, so a host renderer can catch vplkit's complaints apart from
// its own. Messages name what was wrong and where (an index, a texel, a size).
#include <vplkit/core/version.hpp>  // the C++17 check, for every header that reports errors

#include <stdexcept>
#include <string>

namespace vplkit {

class invalid_input : public std::invalid_argument {
public:
  explicit invalid_input(const std::string& what) : std::invalid_argument("vplkit: " + what) {}
};

}  // namespace vplkit
