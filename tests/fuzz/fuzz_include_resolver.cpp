// SPDX-License-Identifier: MIT
// libFuzzer harness: vplkit::glsl::resolve_includes / resolve_include_file (include_resolver.hpp).
// The input is up to four files separated by NUL bytes: the root shader, then a.glsl, b.glsl and
// sub/c.glsl, written to a private folder that is the include directory. Contract: the resolver
// returns or throws include_error (one line), nothing else; every `#line N K` names a source
// string in the table, and each output line after it is line N, N + 1, ... of file K as written,
// or blank (a hoisted #extension, an include inlined before); each file is inlined once; map_log
// never throws and rewrites "K:line" prefixes to the file's label.
#include "fuzz_check.hpp"

#include <vplkit/glsl/include_resolver.hpp>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

const fs::path& work_dir() {
  static const fs::path dir = [] {
    const fs::path d = vplkit_fuzz::make_temp_dir("vplkit_fuzz_include");
    fs::create_directories(d / "sub");
    return d;
  }();
  return dir;
}

using vplkit_fuzz::write_file;

// A source file's lines as the resolver reads them (one trailing '\r' dropped: CRLF files).
std::vector<std::string> lines_of(const std::string& text) {
  return vplkit::glsl::detail::split_lines(text);
}

// The output's lines exactly: split on '\n' only (the resolver writes each line and a '\n').
std::vector<std::string> output_lines(const std::string& text) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t nl = text.find('\n', start);
    out.push_back(text.substr(start, nl == std::string::npos ? std::string::npos : nl - start));
    if (nl == std::string::npos) break;
    start = nl + 1;
  }
  return out;
}

// Reads a `#line N K` directive as the resolver writes it.
bool parse_line_directive(const std::string& s, std::size_t& n, std::size_t& k) {
  if (s.rfind("#line ", 0) != 0) return false;
  std::size_t pos = 6, end = 0;
  try {
    n = std::stoul(s.substr(pos), &end);
    pos += end + 1;
    k = std::stoul(s.substr(pos), &end);
  } catch (const std::exception&) {
    return false;
  }
  return true;
}

void check_result(const vplkit::glsl::resolved_source& r, const std::string& root_text) {
  VPLKIT_FUZZ_CHECK(!r.files.empty());
  std::vector<std::vector<std::string>> sources;
  std::set<std::string> paths;
  for (std::size_t k = 0; k < r.files.size(); ++k) {
    if (k == 0 && r.files[0].path.empty()) {
      sources.push_back(lines_of(root_text));
      continue;
    }
    VPLKIT_FUZZ_CHECK(!r.files[k].path.empty());
    VPLKIT_FUZZ_CHECK(paths.insert(fs::weakly_canonical(r.files[k].path).string()).second);  // once each
    std::ifstream f(r.files[k].path, std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    sources.push_back(lines_of(text));
  }
  // Output lines after a #line directive map to their source lines.
  bool mapped = false;
  std::size_t line = 0, file = 0;
  for (const std::string& out : output_lines(r.text)) {
    std::size_t n = 0, k = 0;
    if (parse_line_directive(out, n, k)) {
      VPLKIT_FUZZ_CHECK(k < r.files.size() && n >= 1);
      mapped = true;
      line = n;
      file = k;
      continue;
    }
    if (!mapped) continue;  // the head: #version, hoisted #extension lines, the preamble
    const std::vector<std::string>& src = sources[file];
    VPLKIT_FUZZ_CHECK(out.empty() || (line <= src.size() && out == src[line - 1]));
    ++line;
  }
  // map_log: never throws; "K:12(3): x" becomes "<label>:12(3): x" for a K in the table.
  const std::string log = "0:12(3): error: x\nERROR: 0:7: 'y'\n" + root_text.substr(0, 200);
  const std::string mapped_log = r.map_log(log);
  VPLKIT_FUZZ_CHECK(mapped_log.rfind(r.file_label(0) + ":12(3): error: x\n", 0) == 0);
  (void)r.map_log(root_text);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  // Absolute includes could reach /proc (/proc/kcore is a huge "regular file") or a device: the
  // harness keeps to its own folder.
  // A `#line` of the input's own would read as one of the resolver's in the check below.
  for (const char* outside : {"/proc", "/sys", "/dev", "/run", "#line"})
    if (input.find(outside) != std::string::npos) return 0;
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (parts.size() < 4) {
    const std::size_t nul = input.find('\0', start);
    parts.push_back(input.substr(start, nul == std::string::npos ? std::string::npos : nul - start));
    if (nul == std::string::npos) break;
    start = nul + 1;
  }
  parts.resize(4);
  const fs::path& dir = work_dir();
  write_file(dir / "a.glsl", parts[1]);
  write_file(dir / "b.glsl", parts[2]);
  write_file(dir / "sub" / "c.glsl", parts[3]);
  write_file(dir / "root.glsl", parts[0]);
  const std::vector<std::string> dirs = {dir.string()};
  for (int mode = 0; mode < 2; ++mode) {
    try {
      const vplkit::glsl::resolved_source r =
          mode == 0 ? vplkit::glsl::resolve_includes(parts[0], "root", dirs, "#define VPLKIT_FUZZ 1\n", dir.string())
                    : vplkit::glsl::resolve_include_file((dir / "root.glsl").string(), dirs);
      check_result(r, parts[0]);
    } catch (const vplkit::glsl::include_error& e) {
      VPLKIT_FUZZ_CHECK(std::string(e.what()).find('\n') == std::string::npos);
    }
  }
  return 0;
}
