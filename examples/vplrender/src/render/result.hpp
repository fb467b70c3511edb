// SPDX-License-Identifier: MIT
#pragma once
// What an estimator run returns, whichever backend ran it.
#include "io/image.hpp"

#include <nlohmann/json.hpp>

namespace vplrender {

struct render_result {
  image_rgb image;          // row 0 = top
  nlohmann::json details;   // builder and estimator facts for the report (pipeline.estimator)
};

}  // namespace vplrender
