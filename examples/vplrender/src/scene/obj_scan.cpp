// SPDX-License-Identifier: MIT
#include "scene/obj_scan.hpp"

#include "io/errors.hpp"
#include "scene/obj_syntax.hpp"

#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <map>
#include <string_view>

namespace vplrender {

namespace {

using obj_syntax::for_each_line;
using obj_syntax::tokenize;

bool is_integer(std::string_view t) {
  std::size_t i = 0;
  if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
  if (i == t.size()) return false;
  for (; i < t.size(); ++i)
    if (t[i] < '0' || t[i] > '9') return false;
  return true;
}

struct scanner {
  const std::string& file;
  std::size_t total_v = 0, total_vt = 0, total_vn = 0;
  std::size_t seen_v = 0, seen_vt = 0, seen_vn = 0;

  [[noreturn]] void fail(std::size_t line, const std::string& msg) const { throw file_error(file, line, msg); }

  void number(std::size_t line, std::string_view tok, const char* what) const {
    const std::string s(tok);
    if (!obj_syntax::is_number(tok)) fail(line, std::string("malformed ") + what + ": '" + s + "' is not a number");
    if (!obj_syntax::is_finite_float(tok))
      fail(line, std::string(what) + " value '" + s + "' is out of range (not a finite float)");
  }

  void numbers(std::size_t line, const std::vector<std::string_view>& t, std::size_t lo, std::size_t hi,
               const char* what) const {
    const std::size_t count = t.size() - 1;
    if (count < lo || count > hi) {
      const std::string want = lo == hi ? std::to_string(lo) : std::to_string(lo) + " to " + std::to_string(hi);
      fail(line, std::string("malformed ") + what + ": expected " + want + " numbers, got " + std::to_string(count));
    }
    for (std::size_t i = 1; i < t.size(); ++i) number(line, t[i], what);
  }

  // One index of a vertex reference; `kind` is "vertex", "texcoord" or "normal".
  void index(std::size_t line, std::string_view part, std::string_view ref, const char* kind, std::size_t total,
             std::size_t seen) const {
    if (!is_integer(part)) fail(line, "malformed vertex reference '" + std::string(ref) + "'");
    const std::string s(part);
    errno = 0;
    const long long v = std::strtoll(s.c_str(), nullptr, 10);
    const bool overflow = errno == ERANGE || v > std::numeric_limits<int>::max() || v < -std::numeric_limits<int>::max();
    if (v == 0) fail(line, std::string(kind) + " index 0 in '" + std::string(ref) + "' (OBJ indices start at 1)");
    if (v > 0 && (overflow || static_cast<unsigned long long>(v) > total))
      fail(line, std::string(kind) + " index " + s + " is out of range (the file has " + std::to_string(total) + " " +
                     (total == 1 ? std::string(kind) : std::string(kind) == "vertex" ? "vertices" : std::string(kind) + "s") + ")");
    if (v < 0 && (overflow || static_cast<unsigned long long>(-v) > seen))
      fail(line, "relative " + std::string(kind) + " index " + s + " refers before the first " + kind + " (" +
                     std::to_string(seen) + " defined so far)");
  }

  void reference(std::size_t line, std::string_view ref) const {
    std::string_view parts[3];
    std::size_t count = 0, start = 0;
    for (std::size_t i = 0; i <= ref.size(); ++i) {
      if (i == ref.size() || ref[i] == '/') {
        if (count == 3) fail(line, "malformed vertex reference '" + std::string(ref) + "'");
        parts[count++] = ref.substr(start, i - start);
        start = i + 1;
      }
    }
    index(line, parts[0], ref, "vertex", total_v, seen_v);
    if (count >= 2 && !(count == 3 && parts[1].empty())) index(line, parts[1], ref, "texcoord", total_vt, seen_vt);
    if (count == 3) index(line, parts[2], ref, "normal", total_vn, seen_vn);
  }
};

}  // namespace

obj_scan_result scan_obj(const std::string& text, const std::string& filename) {
  obj_scan_result r;
  scanner sc{filename};

  // Pass 1: totals, so absolute indices can be checked against the whole file (forward references
  // are legal OBJ), and the byte-level checks.
  for_each_line(text, [&](std::size_t line, std::string_view s) {
    if (s.find('\0') != std::string_view::npos) sc.fail(line, "NUL byte: this is not a text OBJ file");
    const std::vector<std::string_view> t = tokenize(s);
    if (t.empty()) return;
    if (t[0] == "v") ++sc.total_v;
    else if (t[0] == "vt") ++sc.total_vt;
    else if (t[0] == "vn") ++sc.total_vn;
  });

  std::map<std::string, std::pair<std::size_t, std::size_t>> ignored;  // keyword -> first line, count
  r.cleaned.reserve(text.size());
  for_each_line(text, [&](std::size_t line, std::string_view s) {
    const std::vector<std::string_view> t = tokenize(s);
    if (obj_syntax::has_continuation(s, t)) sc.fail(line, "line continuation with '\\' is not supported");
    bool keep = true;
    if (t.empty()) {
      keep = false;
    } else if (t[0] == "v") {
      sc.numbers(line, t, 3, 7, "vertex");
      ++sc.seen_v;
    } else if (t[0] == "vt") {
      sc.numbers(line, t, 1, 3, "texcoord");
      ++sc.seen_vt;
    } else if (t[0] == "vn") {
      sc.numbers(line, t, 3, 3, "normal");
      ++sc.seen_vn;
    } else if (t[0] == "f") {
      if (t.size() < 4)
        sc.fail(line, "face with " + std::to_string(t.size() - 1) + " vertices (a face needs at least 3)");
      for (std::size_t i = 1; i < t.size(); ++i) sc.reference(line, t[i]);
      r.face_lines.push_back(line);
    } else if (t[0] == "mtllib") {
      if (t.size() < 2) r.warnings.push_back(filename + ":" + std::to_string(line) + ": mtllib without a file name");
      for (std::size_t i = 1; i < t.size(); ++i) r.mtllibs.push_back({std::string(t[i]), line});
    } else if (t[0] == "usemtl" || t[0] == "g" || t[0] == "o" || t[0] == "s") {
      // Names and smoothing groups: nothing to validate.
    } else {
      keep = false;
      auto it = ignored.find(std::string(t[0]));
      if (it == ignored.end()) ignored.emplace(std::string(t[0]), std::make_pair(line, std::size_t{1}));
      else ++it->second.second;
    }
    if (keep && t[0] == "mtllib") {
      // tinyobjloader splits mtllib names on spaces only; our names (split on blanks) are what
      // the loader serves, so hand it exactly those, one space apart.
      r.cleaned += "mtllib";
      for (std::size_t i = 1; i < t.size(); ++i) (r.cleaned += ' ') += t[i];
    } else if (keep) {
      // Up to the comment (tokenize stopped there); names keep their inner '#'.
      const std::string_view last = t.back();
      r.cleaned.append(s.data(), static_cast<std::size_t>(last.data() + last.size() - s.data()));
    }
    r.cleaned.push_back('\n');
  });

  for (const auto& [kw, where] : ignored) {
    const bool known = kw == "l" || kw == "p" || kw == "vp" || kw == "cstype" || kw == "deg" || kw == "bmat" ||
                       kw == "step" || kw == "curv" || kw == "curv2" || kw == "surf" || kw == "parm" ||
                       kw == "trim" || kw == "hole" || kw == "scrv" || kw == "sp" || kw == "end" || kw == "con" ||
                       kw == "mg" || kw == "bevel" || kw == "c_interp" || kw == "d_interp" || kw == "lod" ||
                       kw == "maplib" || kw == "usemap" || kw == "shadow_obj" || kw == "trace_obj" ||
                       kw == "ctech" || kw == "stech" || kw == "call" || kw == "csh" || kw == "vw" || kw == "t";
    r.warnings.push_back(filename + ":" + std::to_string(where.first) + ": " +
                         (known ? "unsupported statement '" : "unknown statement '") + kw + "' ignored (" +
                         std::to_string(where.second) + (where.second == 1 ? " line)" : " lines)"));
  }
  r.vertices = sc.total_v;
  r.texcoords = sc.total_vt;
  r.normals = sc.total_vn;
  return r;
}

}  // namespace vplrender
