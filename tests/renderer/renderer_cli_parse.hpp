// SPDX-License-Identifier: MIT
// vplrender's command-line parser as the option tests call it: the flags without the program name,
// the parsed options, or the one-line message of the usage_error it throws.
#pragma once

#include <catch2/catch.hpp>

#include "cli/options.hpp"
#include "io/errors.hpp"

#include <string>
#include <utility>
#include <vector>

namespace vplrender_test {

inline vplrender::parse_result parse_all(std::vector<std::string> args) {
  args.insert(args.begin(), "vplrender");
  return vplrender::parse_command_line(args);
}

// The options of a command line that must parse to a run (not --help).
inline vplrender::options parse(std::vector<std::string> args) {
  const vplrender::parse_result r = parse_all(std::move(args));
  REQUIRE(r.what == vplrender::parse_result::action::run);
  return r.opts;
}

// The message of the usage_error that parsing throws (checked to be one line), or "" if it does
// not throw.
inline std::string error_of(std::vector<std::string> args) {
  try {
    parse_all(std::move(args));
  } catch (const vplrender::usage_error& e) {
    const std::string m = e.what();
    CHECK(m.find('\n') == std::string::npos);
    return m;
  }
  return "";
}

inline bool starts_with(const std::string& s, const std::string& p) { return s.rfind(p, 0) == 0; }

}  // namespace vplrender_test
