#pragma once
#include <string>

namespace vplrender {

// The whole file as bytes. Throws input_error "path: reason" for a missing file, a directory, or
// an unreadable one (the reason comes from errno).
std::string read_file_bytes(const std::string& path);

// True if `path` names an existing regular file (following links).
bool is_regular_file(const std::string& path);

}  // namespace vplrender
