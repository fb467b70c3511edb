// SPDX-License-Identifier: MIT
#include "io/json_file.hpp"

#include "io/atomic_file.hpp"

namespace vplrender {

void write_json(const std::string& path, const nlohmann::json& j) {
  output_set set;
  write_json(set, path, j);
  set.publish();
}

void write_json(output_set& set, const std::string& path, const nlohmann::json& j) {
  // error_handler replace: a file name that is not valid UTF-8 must not make dump() throw.
  const std::string text = j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  set.write(path, [&](const std::string& temp) { write_file_bytes(temp, path, text.data(), text.size()); });
}

}  // namespace vplrender
