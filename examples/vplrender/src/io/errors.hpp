// SPDX-License-Identifier: MIT
#pragma once
// The renderer's error vocabulary. Every complaint is one line that names where the problem is
// (a file and line, a flag, a pixel), so the command line can print it as is and exit non-zero.
#include <stdexcept>
#include <string>

namespace vplrender {

// Bad input data: a scene file, a texture, a light inside geometry. Exit code 1.
class input_error : public std::runtime_error {
public:
  explicit input_error(const std::string& what) : std::runtime_error(what) {}
};

// "file:line: message" (line 0 means the file as a whole).
inline input_error file_error(const std::string& file, std::size_t line, const std::string& message) {
  return input_error(line > 0 ? file + ":" + std::to_string(line) + ": " + message
                              : file + ": " + message);
}

// A bad command line: unknown flag, a value out of range. Exit code 2.
class usage_error : public std::runtime_error {
public:
  explicit usage_error(const std::string& what) : std::runtime_error(what) {}
};

// Writing an output failed, or an image holds values we refuse to write (NaN/Inf). Exit code 1.
class output_error : public std::runtime_error {
public:
  explicit output_error(const std::string& what) : std::runtime_error(what) {}
};

// A method/backend combination this build cannot run yet. Exit code 3.
class not_implemented_error : public std::runtime_error {
public:
  explicit not_implemented_error(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace vplrender
