// SPDX-License-Identifier: MIT
#pragma once
// A JSON document written to a file the way every output is: to a temporary file, then renamed.
#include "io/output_set.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace vplrender {

// Pretty-printed, atomically (temporary file + rename). Throws output_error.
void write_json(const std::string& path, const nlohmann::json& j);
// The same into `set`: on disk under `path` once the set is published.
void write_json(output_set& set, const std::string& path, const nlohmann::json& j);

}  // namespace vplrender
