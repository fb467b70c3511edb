// SPDX-License-Identifier: MIT
#pragma once
// OPTIONAL helper, not included by <vplkit/vplkit.hpp> (nor the single header): include it when
// you feed vplkit's GLSL pack to plain OpenGL, whose drivers do not implement #include.
// vplkit::glsl::resolve_includes() inlines `#include "..."` / `#include <...>` recursively with the
// lookup rules of glslang's GL_GOOGLE_include_directive (so one source serves Vulkan and OpenGL),
// each file once (one included inside an #if group again at its next include), with `#line`
// directives and a table that map driver logs back to file names (resolved_source::map_log); it
// keeps #version first and hoists #extension lines after it. It
// does not evaluate #if, except that includes in the C++ branches of a two-language header (the
// kernels' *_params.h) are left out. Every rule, and the errors (include_error): docs/glsl.md,
// "Using the pack with OpenGL". Header-only, C++17, standard library only.
#include <cctype>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace vplkit::glsl {

class include_error : public std::runtime_error {
public:
  explicit include_error(const std::string& what)
      : std::runtime_error("vplkit include_resolver: " + what) {}
};

struct source_file {
  std::string name;  // as written by the includer (or the name given for the root source)
  std::string path;  // the file read (empty for a root given as a string)
};

struct resolved_source {
  std::string text;               // ready for glShaderSource
  std::vector<source_file> files; // index = GLSL source-string number used in #line; 0 = root

  // Name shown for source-string number k: the file's path, else its name.
  std::string file_label(std::size_t k) const {
    if (k >= files.size()) return std::to_string(k);
    return files[k].path.empty() ? files[k].name : files[k].path;
  }

  // Rewrites the source-string numbers at the start of each info-log line into file names:
  //   "0:12(3): error: ..."   -> "<file>:12(3): error: ..."     (Mesa)
  //   "ERROR: 1:12: '...' ..." -> "ERROR: <file>:12: '...' ..." (glslang, AMD)
  //   "1(12) : error C0000: ..." -> "<file>(12) : error C0000: ..." (NVIDIA)
  // Numbers outside the table are left alone.
  std::string map_log(const std::string& log) const {
    std::istringstream in(log);
    std::string line, out;
    bool first = true;
    while (std::getline(in, line)) {
      if (!first) out += '\n';
      first = false;
      std::size_t number_begin = 0, number_end = 0;
      if (find_location(line, number_begin, number_end)) {
        const std::size_t k = std::stoul(line.substr(number_begin, number_end - number_begin));
        if (k < files.size()) line.replace(number_begin, number_end - number_begin, file_label(k));
      }
      out += line;
    }
    if (!log.empty() && log.back() == '\n') out += '\n';
    return out;
  }

private:
  // Finds the source-string number of a log line that starts with
  //   [spaces][ERROR|WARNING|INFO|NOTE|error|warning :]<k>:<line>   or   ...<k>(<line>)
  // Hand-written rather than std::regex: GCC 12 reports false -Wmaybe-uninitialized inside
  // <regex> under -fsanitize, which -Werror users of this header would inherit.
  static bool find_location(const std::string& s, std::size_t& begin, std::size_t& end) {
    auto is_digit = [](char c) { return c >= '0' && c <= '9'; };
    std::size_t i = 0;
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
    for (const char* word : {"ERROR", "WARNING", "INFO", "NOTE", "error", "warning"}) {
      const std::string w(word);
      if (s.compare(i, w.size(), w) != 0) continue;
      std::size_t j = i + w.size();
      while (j < s.size() && s[j] == ' ') ++j;
      if (j < s.size() && s[j] == ':') {
        ++j;
        while (j < s.size() && s[j] == ' ') ++j;
        i = j;
      }
      break;
    }
    begin = i;
    while (i < s.size() && is_digit(s[i])) ++i;
    end = i;
    if (end == begin || end - begin > 9 || i + 1 >= s.size()) return false;
    if (s[i] == ':') return is_digit(s[i + 1]);
    if (s[i] != '(') return false;
    std::size_t j = i + 1;
    while (j < s.size() && is_digit(s[j])) ++j;
    return j > i + 1 && j < s.size() && s[j] == ')';
  }
};

namespace detail {

inline std::string read_text_file(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  if (!f) throw include_error("cannot read " + p.string());
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

inline std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::string line;
  std::istringstream in(text);
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();  // CRLF files
    lines.push_back(line);
  }
  return lines;
}

inline std::string trim_left(const std::string& s) {
  std::size_t i = 0;
  while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
  return s.substr(i);
}

// Classifies one line: its directive name ("include", "version", ...), "" for anything else.
// `in_comment` carries /* */ state across lines: a '#' inside a block comment is no directive.
// `code` is set when the line holds something besides blanks, comments and a directive.
inline std::string scan_line(const std::string& line, bool& in_comment, bool& code) {
  const bool starts_in_comment = in_comment;
  code = false;
  bool directive_line = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    const char next = i + 1 < line.size() ? line[i + 1] : '\0';
    if (in_comment) {
      if (c == '*' && next == '/') {
        in_comment = false;
        ++i;
      }
    } else if (c == '/' && next == '/') {
      break;
    } else if (c == '/' && next == '*') {
      in_comment = true;
      ++i;
    } else if (c == '#' && !code && !directive_line) {
      directive_line = true;
    } else if (c != ' ' && c != '\t' && !directive_line) {
      code = true;
    }
  }
  if (starts_in_comment || code) return "";
  const std::string t = trim_left(line);
  if (t.empty() || t[0] != '#') return "";
  std::size_t i = 1;
  while (i < t.size() && (t[i] == ' ' || t[i] == '\t')) ++i;
  std::size_t j = i;
  while (j < t.size() && (std::isalnum(static_cast<unsigned char>(t[j])) || t[j] == '_')) ++j;
  return t.substr(i, j - i);
}

// `#include "name"` or `#include <name>`, optionally followed by a comment.
inline bool parse_include(const std::string& line, bool& quoted, std::string& name) {
  std::string t = trim_left(line);
  if (t.empty() || t[0] != '#') return false;
  t = trim_left(t.substr(1));
  if (t.compare(0, 7, "include") != 0) return false;
  t = trim_left(t.substr(7));
  if (t.empty() || (t[0] != '"' && t[0] != '<')) return false;
  quoted = t[0] == '"';
  const std::size_t close = t.find(quoted ? '"' : '>', 1);
  if (close == std::string::npos || close == 1) return false;
  name = t.substr(1, close - 1);
  const std::string rest = trim_left(t.substr(close + 1));
  if (rest.empty() || rest.compare(0, 2, "//") == 0) return true;
  if (rest.compare(0, 2, "/*") == 0) {
    const std::size_t end = rest.find("*/", 2);
    return end != std::string::npos && trim_left(rest.substr(end + 2)).empty();
  }
  return false;
}

// For `#if...` lines: does the group test __cplusplus alone? +1: its first branch is C++ (#ifdef
// __cplusplus, #if defined(__cplusplus), #if defined __cplusplus); -1: its first branch is GLSL
// (#ifndef __cplusplus, #if !defined(...)); 0: anything else.
inline int cplusplus_condition(const std::string& line) {
  std::string t = trim_left(line);
  t = trim_left(t.substr(1));  // after '#'
  std::string compact;
  for (char c : t) {
    if (c == '/' && !compact.empty() && compact.back() == '/') {
      compact.pop_back();
      break;
    }
    if (c != ' ' && c != '\t' && c != '(' && c != ')') compact += c;
  }
  if (compact == "ifdef__cplusplus" || compact == "ifdefined__cplusplus") return 1;
  if (compact == "ifndef__cplusplus" || compact == "if!defined__cplusplus") return -1;
  return 0;
}

inline bool is_google_extension(const std::string& line) {
  return line.find("GL_GOOGLE_include_directive") != std::string::npos ||
         line.find("GL_GOOGLE_cpp_style_line_directive") != std::string::npos;
}

struct resolver {
  std::vector<std::filesystem::path> dirs;
  std::vector<source_file> files;
  std::vector<std::string> seen;          // canonical paths inlined so far
  std::vector<std::string> stack;         // canonical paths being inlined (cycle detection)
  std::vector<std::string> stack_labels;  // the same, as shown in messages
  std::vector<std::string> extensions;    // hoisted #extension lines, first-seen order
  std::string body;

  static std::string canonical(const std::filesystem::path& p) {
    std::error_code ec;
    const auto c = std::filesystem::weakly_canonical(p, ec);
    return (ec ? std::filesystem::absolute(p).lexically_normal() : c).string();
  }

  std::filesystem::path find(const std::string& name, bool quoted,
                             const std::filesystem::path& includer_dir, const std::string& from,
                             std::size_t line_no) const {
    std::vector<std::filesystem::path> tried;
    if (std::filesystem::path(name).is_absolute()) {
      if (std::filesystem::is_regular_file(name)) return name;
    } else {
      if (quoted && !includer_dir.empty()) tried.push_back(includer_dir);
      for (const auto& d : dirs) tried.push_back(d);
      for (const auto& d : tried) {
        const auto p = d / name;
        if (std::filesystem::is_regular_file(p)) return p;
      }
    }
    std::string searched;
    for (const auto& d : tried) searched += (searched.empty() ? "" : ", ") + d.string();
    throw include_error("cannot find \"" + name + "\" included from " + from + ":" +
                        std::to_string(line_no) + " (searched: " +
                        (searched.empty() ? std::string("no include directories") : searched) +
                        ")");
  }

  void hoist_extension(const std::string& line) {
    if (is_google_extension(line)) return;  // dropped: no OpenGL driver knows it
    const std::string t = trim_left(line);
    for (const auto& e : extensions) {
      if (e == t) return;
    }
    extensions.push_back(t);
  }

  // Appends lines [first, end) of source string `index` to body, expanding includes.
  // `conditional`: this text lies in an #if group of an includer (not its include guard), so the
  // preprocessor may drop it; its includes are then conditional too.
  void expand(const std::vector<std::string>& lines, std::size_t index,
              const std::filesystem::path& dir, std::size_t first, bool root,
              bool conditional = false) {
    const std::string label = stack_labels.back();
    body += "#line " + std::to_string(first + 1) + " " + std::to_string(index) + "\n";
    bool in_comment = false, code = false;
    // Open conditional groups: cplusplus_condition of the #if line, and the branch we are in
    // (0 before the first #elif / #else). A branch is C++ when it is the first of a +1 group or a
    // later one of a -1 group.
    // guard: the file's include guard, the #ifndef that is its first directive (an included file's).
    struct group {
      int condition;
      int branch;
      bool guard;
    };
    std::vector<group> groups;
    bool directive_seen = false;
    auto in_cplusplus = [&groups] {
      for (const group& g : groups)
        if ((g.condition == 1 && g.branch == 0) || (g.condition == -1 && g.branch > 0)) return true;
      return false;
    };
    for (std::size_t i = 0; i < first; ++i) scan_line(lines[i], in_comment, code);
    for (std::size_t i = first; i < lines.size(); ++i) {
      const std::string& line = lines[i];
      const std::string d = scan_line(line, in_comment, code);
      if (d == "if" || d == "ifdef" || d == "ifndef") {
        groups.push_back({cplusplus_condition(line), 0, d == "ifndef" && !directive_seen && !root});
      } else if ((d == "else" || d == "elif") && !groups.empty()) {
        ++groups.back().branch;
      } else if (d == "endif" && !groups.empty()) {
        groups.pop_back();
      }
      if (!d.empty()) directive_seen = true;
      if (d == "include" && in_cplusplus()) {
        body += "\n";  // C++ only: not GLSL, not looked up
        continue;
      }
      if (d == "extension") {
        hoist_extension(line);
        body += "\n";  // a blank line keeps the numbering
        continue;
      }
      if (d == "version" && !root) {
        throw include_error(label + ":" + std::to_string(i + 1) +
                            ": #version in an included file (the including shader chooses it)");
      }
      if (d != "include") {
        body += line;
        body += "\n";
        continue;
      }
      bool quoted = false;
      std::string name;
      if (!parse_include(line, quoted, name)) {
        throw include_error(label + ":" + std::to_string(i + 1) + ": malformed #include: " + line);
      }
      const auto path = find(name, quoted, dir, label, i + 1);
      const std::string key = canonical(path);
      for (std::size_t s = 0; s < stack.size(); ++s) {
        if (stack[s] == key) {
          std::string chain;
          for (std::size_t t = s; t < stack_labels.size(); ++t) chain += stack_labels[t] + " -> ";
          throw include_error("include cycle: " + chain + path.string() + " (#include at " +
                              label + ":" + std::to_string(i + 1) + ")");
        }
      }
      bool already = false;
      for (const auto& s : seen) already = already || s == key;
      if (already) {
        body += "\n";  // inlined once only; the blank line keeps the numbering
        continue;
      }
      // An include in an #if group (other than the include guard) is inlined there, but not
      // remembered: if the group is disabled the file's text is dropped, and the next include of
      // it must inline it again. Where both are enabled, the file's include guard keeps the second
      // copy out.
      bool in_group = conditional;
      for (const group& g : groups) in_group = in_group || !g.guard;
      if (!in_group) seen.push_back(key);
      const std::size_t child = files.size();
      files.push_back({name, path.string()});
      stack.push_back(key);
      stack_labels.push_back(path.string());
      expand(split_lines(read_text_file(path)), child, path.parent_path(), 0, false, in_group);
      stack.pop_back();
      stack_labels.pop_back();
      body += "#line " + std::to_string(i + 2) + " " + std::to_string(index) + "\n";
    }
  }
};

inline resolved_source resolve(const std::string& source, const std::string& name,
                               const std::string& root_path,
                               const std::vector<std::string>& include_dirs,
                               const std::string& preamble, const std::string& base_dir) {
  resolver r;
  for (const auto& d : include_dirs) r.dirs.emplace_back(d);
  r.files.push_back({name, root_path});
  const auto lines = split_lines(source);

  // The head: blank and comment lines, then #version, then #extension / blank / comment lines.
  // It is emitted first, unchanged (less the GL_GOOGLE extensions); without a #version line there
  // is no head.
  std::string head_text;
  std::size_t head = 0;
  bool in_comment = false, code = false, have_version = false;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string d = scan_line(lines[i], in_comment, code);
    if (d == "version" && !have_version) {
      have_version = true;
    } else if (!(d.empty() && !code) && !(d == "extension" && have_version)) {
      break;
    }
    if (!(d == "extension" && is_google_extension(lines[i]))) head_text += lines[i];
    head_text += "\n";
    head = i + 1;
  }
  if (!have_version) {
    head_text.clear();
    head = 0;
  }

  const std::string root_key =
      root_path.empty() ? "<string:" + name + ">" : resolver::canonical(root_path);
  r.seen.push_back(root_key);
  r.stack.push_back(root_key);
  r.stack_labels.push_back(root_path.empty() ? name : root_path);
  r.expand(lines, 0, base_dir.empty() ? std::filesystem::path() : std::filesystem::path(base_dir),
           head, true);

  resolved_source out;
  out.text = head_text;
  for (const auto& e : r.extensions) out.text += e + "\n";
  if (!preamble.empty()) {
    out.text += preamble;
    if (preamble.back() != '\n') out.text += "\n";
  }
  out.text += r.body;
  out.files = std::move(r.files);
  return out;
}

}  // namespace detail

// Expands the includes of `source` (a whole shader). `name` labels it in messages and is
// files[0].name; quoted includes of the root look in `base_dir` first (empty: only in
// `include_dirs`). `preamble` (e.g. "#define N 64\n") goes after #version and #extension.
inline resolved_source resolve_includes(const std::string& source, const std::string& name,
                                        const std::vector<std::string>& include_dirs,
                                        const std::string& preamble = {},
                                        const std::string& base_dir = {}) {
  return detail::resolve(source, name, {}, include_dirs, preamble, base_dir);
}

// Reads `path` and expands it; its quoted includes look in the file's own folder first.
inline resolved_source resolve_include_file(const std::string& path,
                                            const std::vector<std::string>& include_dirs,
                                            const std::string& preamble = {}) {
  const std::filesystem::path p(path);
  return detail::resolve(detail::read_text_file(p), path, path, include_dirs, preamble,
                         p.parent_path().string());
}

}  // namespace vplkit::glsl
