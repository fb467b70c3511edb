// SPDX-License-Identifier: MIT
#pragma once
// The lexical rules shared by our OBJ and MTL passes (obj_scan.cpp, mtl_scan.cpp): how lines end,
// how a line splits into tokens, and which tokens are numbers, all as tinyobjloader reads them.
#include <cfloat>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

namespace vplrender::obj_syntax {

// Calls f(line_number, line) for every line; "\n", "\r\n" and a lone "\r" end a line, as in
// tinyobjloader's safeGetline. A final line without terminator counts; an empty tail does not.
template <class F>
void for_each_line(const std::string& text, F&& f) {
  std::size_t line = 0, begin = 0;
  const std::size_t n = text.size();
  while (begin < n) {
    std::size_t end = begin;
    while (end < n && text[end] != '\n' && text[end] != '\r') ++end;
    ++line;
    f(line, std::string_view(text.data() + begin, end - begin));
    if (end < n && text[end] == '\r' && end + 1 < n && text[end + 1] == '\n') ++end;
    begin = end + 1;
  }
}

inline bool is_space(char c) { return c == ' ' || c == '\t'; }

// Tokens split on blanks, stopping at a token that starts with '#'.
inline std::vector<std::string_view> tokenize(std::string_view s) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && is_space(s[i])) ++i;
    if (i >= s.size() || s[i] == '#') break;
    std::size_t j = i;
    while (j < s.size() && !is_space(s[j])) ++j;
    out.push_back(s.substr(i, j - i));
    i = j;
  }
  return out;
}

// The decimal grammar tinyobjloader reads: [+-] (digits [. digits*] | . digits) [(e|E) [+-] digits].
// strtod would also take "nan", "inf" and hex floats, which tinyobjloader reads as 0.
inline bool is_number(std::string_view t) {
  std::size_t i = 0;
  auto digits = [&]() {
    const std::size_t s = i;
    while (i < t.size() && t[i] >= '0' && t[i] <= '9') ++i;
    return i - s;
  };
  if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
  if (i < t.size() && t[i] == '.') {
    ++i;
    if (digits() == 0) return false;
  } else {
    if (digits() == 0) return false;
    if (i < t.size() && t[i] == '.') {
      ++i;
      digits();
    }
  }
  if (i < t.size() && (t[i] == 'e' || t[i] == 'E')) {
    ++i;
    if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
    if (digits() == 0) return false;
  }
  return i == t.size();
}

// A number in that grammar whose value is a finite float ("1e39" is not).
inline bool is_finite_float(std::string_view t) {
  if (!is_number(t)) return false;
  const double v = std::strtod(std::string(t).c_str(), nullptr);
  return std::isfinite(v) && std::abs(v) <= static_cast<double>(FLT_MAX);
}

// True when the line ends in a '\' continuation (after trailing blanks), which neither file
// format we read supports.
inline bool has_continuation(std::string_view s, const std::vector<std::string_view>& tokens) {
  std::size_t e = s.size();
  while (e > 0 && is_space(s[e - 1])) --e;
  return !tokens.empty() && e > 0 && s[e - 1] == '\\' && tokens.back().back() == '\\';
}

}  // namespace vplrender::obj_syntax
