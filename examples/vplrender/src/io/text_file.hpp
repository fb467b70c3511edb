// SPDX-License-Identifier: MIT
#pragma once
#include <string>

namespace vplrender {

// The whole file as bytes. Throws input_error "path: reason" for a missing file, a directory,
// anything that is not a regular file (a FIFO would block, /dev/zero never ends), or an
// unreadable one (the reason comes from errno). Never blocks on the open.
std::string read_file_bytes(const std::string& path);

// True if `path` names an existing regular file (following links).
bool is_regular_file(const std::string& path);

// What keeps `path` from being read as a file: "" for a regular file, else a phrase that follows
// the path in a message ("does not exist", "is a directory, not a file", "is not a regular file
// (a named pipe)", "cannot be examined (Permission denied)").
std::string file_problem(const std::string& path);

}  // namespace vplrender
