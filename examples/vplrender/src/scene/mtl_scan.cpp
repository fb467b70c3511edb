// SPDX-License-Identifier: MIT
#include "scene/mtl_scan.hpp"

#include "io/errors.hpp"
#include "scene/obj_syntax.hpp"

#include <cstddef>
#include <map>
#include <string_view>
#include <utility>

namespace vplrender {

namespace {

using obj_syntax::tokenize;
using tokens = std::vector<std::string_view>;

// Standard MTL statements (and tinyobjloader's PBR extension) that a diffuse renderer has no use
// for: ignored without a warning.
bool is_unused_statement(std::string_view k) {
  static const char* const unused[] = {
      "Ka",     "Ks",     "Ns",     "Ni",       "d",        "Tr",       "Tf",     "Kt",    "illum",
      "sharpness", "map_Ka", "map_Ks", "map_Ns", "map_d",  "map_bump", "map_Bump", "bump", "disp",
      "map_disp", "map_Disp", "decal", "refl",  "map_refl", "map_Ke",  "Pr",     "Pm",    "Ps",
      "Pc",     "Pcr",    "aniso",  "anisor",   "map_Pr",   "map_Pm",   "map_Ps", "norm"};
  for (const char* u : unused)
    if (k == u) return true;
  return false;
}

struct mtl_scanner {
  const std::string& file;

  [[noreturn]] void fail(std::size_t line, const std::string& msg) const { throw file_error(file, line, msg); }

  // One number of statement `what`, as tinyobjloader parses it and finite as a float.
  std::string number(std::size_t line, std::string_view tok, const std::string& what) const {
    const std::string s(tok);
    if (!obj_syntax::is_number(tok)) fail(line, "malformed " + what + ": '" + s + "' is not a number");
    if (!obj_syntax::is_finite_float(tok)) fail(line, what + " value '" + s + "' is out of range (not a finite float)");
    return s;
  }

  // "Kd r g b" or "Kd r" (grey): always written back with three numbers.
  std::string colour(std::size_t line, const tokens& t) const {
    const std::string key(t[0]);
    if (t.size() > 1 && (t[1] == "spectral" || t[1] == "xyz"))
      fail(line, key + " " + std::string(t[1]) + " is not supported; give " + key + " r g b");
    const std::size_t count = t.size() - 1;
    if (count != 1 && count != 3)
      fail(line, "malformed " + key + ": expected 1 or 3 numbers, got " + std::to_string(count));
    std::string out = key;
    for (std::size_t i = 1; i < 4; ++i) out += " " + number(line, t[count == 1 ? 1 : i], key);
    return out;
  }

  // map_Kd [options] file. tinyobjloader's option parser always takes three tokens after -s, -o
  // and -t, so a shorter list ("-s 2 tex.png") would swallow the file name: we take 1 to 3
  // numbers, fill in the MTL defaults, and keep only -s and -o (the options the renderer uses).
  std::string texture_map(std::size_t line, const tokens& t, std::string_view whole) const {
    const std::string key(t[0]);
    std::string options;
    std::size_t i = 1;
    auto need = [&](std::size_t k, const std::string& opt) {
      if (i + k >= t.size())
        fail(line, "malformed " + key + ": " + opt + " needs " + std::to_string(k) + " value" + (k == 1 ? "" : "s") +
                       " and a file name after it");
    };
    while (i < t.size() && t[i].size() > 1 && t[i][0] == '-') {
      const std::string opt(t[i]);
      if (opt == "-s" || opt == "-o" || opt == "-t") {
        std::string values[3] = {opt == "-s" ? "1" : "0", opt == "-s" ? "1" : "0", opt == "-s" ? "1" : "0"};
        std::size_t k = 0;
        while (k < 3 && i + 1 + k < t.size() && obj_syntax::is_number(t[i + 1 + k])) {
          values[k] = number(line, t[i + 1 + k], key + " " + opt);
          ++k;
        }
        if (k == 0) fail(line, "malformed " + key + ": " + opt + " needs 1 to 3 numbers");
        i += 1 + k;
        if (opt != "-t") options += " " + opt + " " + values[0] + " " + values[1] + " " + values[2];
      } else if (opt == "-mm") {
        need(2, opt);
        number(line, t[i + 1], key + " " + opt);
        number(line, t[i + 2], key + " " + opt);
        i += 3;
      } else if (opt == "-bm" || opt == "-boost" || opt == "-texres") {
        need(1, opt);
        number(line, t[i + 1], key + " " + opt);
        i += 2;
      } else if (opt == "-blendu" || opt == "-blendv" || opt == "-clamp" || opt == "-imfchan" || opt == "-type" ||
                 opt == "-colorspace") {
        need(1, opt);
        i += 2;
      } else {
        break;  // not an option: the file name starts here (tinyobjloader reads it the same way)
      }
    }
    if (i >= t.size()) fail(line, key + " without a file name");
    // The name runs to the end of the last token (names may hold blanks).
    const std::string_view last = t.back();
    const std::size_t from = static_cast<std::size_t>(t[i].data() - whole.data());
    const std::size_t to = static_cast<std::size_t>(last.data() + last.size() - whole.data());
    return key + options + " " + std::string(whole.substr(from, to - from));
  }
};

}  // namespace

mtl_scan_result scan_mtl(const std::string& text, const std::string& filename) {
  mtl_scan_result r;
  const mtl_scanner sc{filename};
  bool in_material = false;
  std::map<std::string, std::pair<std::size_t, std::size_t>> ignored;  // keyword -> first line, count
  std::size_t orphan_line = 0, orphans = 0;
  r.cleaned.reserve(text.size());
  obj_syntax::for_each_line(text, [&](std::size_t line, std::string_view s) {
    if (s.find('\0') != std::string_view::npos) sc.fail(line, "NUL byte: this is not a text MTL file");
    const tokens t = tokenize(s);
    if (obj_syntax::has_continuation(s, t)) sc.fail(line, "line continuation with '\\' is not supported");
    std::string out;
    if (t.empty() || is_unused_statement(t[0])) {
      // blank
    } else if (t[0] == "newmtl") {
      if (t.size() < 2) sc.fail(line, "newmtl without a material name");
      in_material = true;
      const std::string_view last = t.back();
      out.assign(s.data(), static_cast<std::size_t>(last.data() + last.size() - s.data()));
    } else if (t[0] == "Kd" || t[0] == "Ke" || t[0] == "map_Kd") {
      out = t[0] == "map_Kd" ? sc.texture_map(line, t, s) : sc.colour(line, t);
      if (!in_material) {  // validated all the same, but it belongs to no material
        if (orphans++ == 0) orphan_line = line;
        out.clear();
      }
    } else {
      auto it = ignored.find(std::string(t[0]));
      if (it == ignored.end()) ignored.emplace(std::string(t[0]), std::make_pair(line, std::size_t{1}));
      else ++it->second.second;
    }
    r.cleaned += out;
    r.cleaned.push_back('\n');
  });
  if (orphans > 0)
    r.warnings.push_back(filename + ":" + std::to_string(orphan_line) + ": " + std::to_string(orphans) +
                         " Kd/Ke/map_Kd statement(s) before the first newmtl belong to no material; ignored");
  for (const auto& [kw, where] : ignored)
    r.warnings.push_back(filename + ":" + std::to_string(where.first) + ": unknown statement '" + kw + "' ignored (" +
                         std::to_string(where.second) + (where.second == 1 ? " line)" : " lines)"));
  return r;
}

}  // namespace vplrender
