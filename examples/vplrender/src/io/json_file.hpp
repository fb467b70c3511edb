#pragma once
// A JSON document written to a file the way every output is: to a temporary file, then renamed.
#include <nlohmann/json.hpp>

#include <string>

namespace vplrender {

// Pretty-printed, atomically (temporary file + rename). Throws output_error.
void write_json(const std::string& path, const nlohmann::json& j);

}  // namespace vplrender
