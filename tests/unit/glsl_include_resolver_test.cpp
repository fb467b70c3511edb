// SPDX-License-Identifier: MIT
// vplkit::glsl::resolve_includes on small files written to a fresh temporary folder.
#include <vplkit/glsl/include_resolver.hpp>

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace fs = std::filesystem;
using vplkit::glsl::include_error;
using vplkit::glsl::resolve_include_file;
using vplkit::glsl::resolve_includes;

namespace {

// What resolve_includes(source, name, dirs) throws; fails the test case when it throws nothing.
std::string include_error_of(const std::string& source, const std::string& name,
                             const std::vector<std::string>& dirs) {
  try {
    resolve_includes(source, name, dirs);
  } catch (const include_error& e) {
    return e.what();
  }
  FAIL("no exception");
  return {};
}

// A temporary tree, removed at the end of the test case.
struct temp_tree {
  fs::path root;
  temp_tree() {
    static int counter = 0;
    root = fs::temp_directory_path() /
           ("vplkit_include_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    fs::remove_all(root);
    fs::create_directories(root);
  }
  ~temp_tree() {
    std::error_code ec;
    fs::remove_all(root, ec);
  }
  std::string write(const std::string& rel, const std::string& text) const {
    const fs::path p = root / rel;
    fs::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }
  std::string dir(const std::string& rel = {}) const { return (root / rel).string(); }
};

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::string line;
  std::istringstream in(text);
  while (std::getline(in, line)) out.push_back(line);
  return out;
}

// Replays the #line directives of `text` and returns, for the first line equal to `needle`,
// "<source-string number>:<line>" — what a driver would report for an error on that line.
std::string location_of(const std::string& text, const std::string& needle) {
  int line = 1, file = 0;
  for (const auto& l : lines_of(text)) {
    if (l.rfind("#line ", 0) == 0) {
      std::istringstream d(l.substr(6));
      d >> line >> file;
      continue;  // GLSL 4.30+: the line after "#line n" is line n
    }
    if (l == needle) return std::to_string(file) + ":" + std::to_string(line);
    ++line;
  }
  return "not found";
}

std::size_t count_of(const std::string& text, const std::string& needle) {
  std::size_t n = 0;
  for (std::size_t p = text.find(needle); p != std::string::npos; p = text.find(needle, p + 1)) ++n;
  return n;
}

}  // namespace

TEST_CASE("include_resolver: nested includes expand once, with #line back to each file") {
  temp_tree t;
  t.write("pack/vplkit/core/a.glsl", "// a\nfloat vplkit_a() { return 1.0; }\n");
  t.write("pack/vplkit/core/b.glsl",
          "#include \"a.glsl\"\n"          // quoted: next to the includer
          "float vplkit_b() { return vplkit_a(); }\n");
  const std::string shader = "#version 430\n"
                             "#include \"vplkit/core/b.glsl\"\n"
                             "#include <vplkit/core/a.glsl>\n"
                             "void main() {}\n";
  const auto r = resolve_includes(shader, "main.comp", {t.dir("pack")});
  REQUIRE(r.files.size() == 3);
  CHECK(r.files[0].name == "main.comp");
  CHECK(r.files[1].name == "vplkit/core/b.glsl");
  CHECK(r.files[2].name == "a.glsl");
  CHECK(lines_of(r.text).front() == "#version 430");
  CHECK(count_of(r.text, "float vplkit_a()") == 1);
  CHECK(location_of(r.text, "float vplkit_a() { return 1.0; }") == "2:2");
  CHECK(location_of(r.text, "float vplkit_b() { return vplkit_a(); }") == "1:2");
  CHECK(location_of(r.text, "void main() {}") == "0:4");
}

TEST_CASE("include_resolver: a file first included in an #if group is inlined again at its next include") {
  // The group may be disabled: had the first copy been remembered, the file would vanish with it
  // (glslang's own #include evaluates the group; the resolver does not). Where both copies are
  // enabled, the guard keeps the second one out. An include inside a file's include guard is not
  // in a group, and a file included by a conditionally included one is conditional too.
  temp_tree t;
  t.write("pack/vplkit/a.glsl", "#ifndef VPLKIT_A_GLSL\n#define VPLKIT_A_GLSL\nfloat vplkit_a() { return 1.0; }\n#endif\n");
  t.write("pack/vplkit/b.glsl",
          "#ifndef VPLKIT_B_GLSL\n#define VPLKIT_B_GLSL\n#include \"a.glsl\"\nfloat vplkit_b() { return vplkit_a(); }\n#endif\n");
  const std::string shader = "#version 430\n"
                             "#ifdef USE_B\n"
                             "#include <vplkit/b.glsl>\n"
                             "#endif\n"
                             "#include <vplkit/a.glsl>\n"
                             "#include <vplkit/b.glsl>\n"
                             "#include <vplkit/a.glsl>\n"
                             "#include <vplkit/b.glsl>\n"
                             "void main() {}\n";
  const auto r = resolve_includes(shader, "main.comp", {t.dir("pack")});
  // a: in the group (through b), then once outside; b: in the group, then once outside.
  CHECK(count_of(r.text, "float vplkit_a()") == 2);
  CHECK(count_of(r.text, "float vplkit_b()") == 2);
  // Outside any group (the include guard is none), each file once, as before.
  const std::string plain = "#version 430\n#include <vplkit/b.glsl>\n#include <vplkit/a.glsl>\nvoid main() {}\n";
  const auto p = resolve_includes(plain, "plain.comp", {t.dir("pack")});
  CHECK(count_of(p.text, "float vplkit_a()") == 1);
  CHECK(count_of(p.text, "float vplkit_b()") == 1);
}

TEST_CASE("include_resolver: #version and #extension stay in front, the preamble after them") {
  temp_tree t;
  t.write("inc/x.glsl", "#extension GL_EXT_shader_explicit_arithmetic_types : enable\nint x;\n");
  const std::string shader = "// leading comment\n"
                             "#version 450\n"
                             "#extension GL_GOOGLE_include_directive : require\n"
                             "#extension GL_ARB_gpu_shader_int64 : enable\n"
                             "#include \"x.glsl\"\n"
                             "#extension GL_ARB_shader_ballot : enable\n"
                             "void main() {}\n";
  const auto r = resolve_includes(shader, "s.comp", {t.dir("inc")}, "#define N 4");
  const auto l = lines_of(r.text);
  REQUIRE(l.size() > 6);
  CHECK(l[0] == "// leading comment");
  CHECK(l[1] == "#version 450");
  CHECK(l[2].empty());  // the GL_GOOGLE extension is dropped, its line kept blank
  CHECK(l[3] == "#extension GL_ARB_gpu_shader_int64 : enable");
  CHECK(l[4] == "#extension GL_EXT_shader_explicit_arithmetic_types : enable");
  CHECK(l[5] == "#extension GL_ARB_shader_ballot : enable");
  CHECK(l[6] == "#define N 4");
  CHECK(count_of(r.text, "GL_GOOGLE_include_directive") == 0);
  CHECK(count_of(r.text, "#extension") == 3);
  CHECK(location_of(r.text, "int x;") == "1:2");
  CHECK(location_of(r.text, "void main() {}") == "0:7");
}

TEST_CASE("include_resolver: a shader without #version gets the preamble first") {
  temp_tree t;
  const auto r = resolve_includes("void main() {}\n", "s", {}, "#define A 1\n");
  const auto l = lines_of(r.text);
  REQUIRE(l.size() == 3);
  CHECK(l[0] == "#define A 1");
  CHECK(l[1] == "#line 1 0");
  CHECK(l[2] == "void main() {}");
}

TEST_CASE("include_resolver: missing file names the includer and line") {
  temp_tree t;
  t.write("inc/vplkit/a.glsl", "int a;\n\n#include \"vplkit/missing.glsl\"\n");
  {
    const std::string what =
        include_error_of("#version 430\n#include \"vplkit/a.glsl\"\n", "s.comp", {t.dir("inc")});
    INFO(what);
    CHECK(what.find("\"vplkit/missing.glsl\"") != std::string::npos);
    CHECK(what.find("a.glsl:3") != std::string::npos);
    CHECK(what.find(t.dir("inc")) != std::string::npos);  // where it looked
  }
  // Angle includes do not look next to the includer.
  t.write("inc/vplkit/near.glsl", "int near;\n");
  t.write("inc/vplkit/b.glsl", "#include <near.glsl>\n");
  CHECK_THROWS_AS(resolve_includes("#include \"vplkit/b.glsl\"\n", "s", {t.dir("inc")}),
                  include_error);
}

TEST_CASE("include_resolver: include cycles are errors") {
  temp_tree t;
  t.write("inc/a.glsl", "#include \"b.glsl\"\n");
  t.write("inc/b.glsl", "int b;\n#include \"a.glsl\"\n");
  {
    const std::string what = include_error_of("#include \"a.glsl\"\n", "s.comp", {t.dir("inc")});
    INFO(what);
    CHECK(what.find("include cycle") != std::string::npos);
    CHECK(what.find("b.glsl:2") != std::string::npos);
  }
  // A file that includes itself, and a root file included from below.
  t.write("inc/self.glsl", "#include \"self.glsl\"\n");
  CHECK_THROWS_AS(resolve_includes("#include \"self.glsl\"\n", "s", {t.dir("inc")}), include_error);
  const std::string root = t.write("inc/root.comp", "#version 430\n#include \"c.glsl\"\n");
  t.write("inc/c.glsl", "#include \"root.comp\"\n");
  CHECK_THROWS_AS(resolve_include_file(root, {}), include_error);
}

TEST_CASE("include_resolver: comments, CRLF, malformed lines and #version in includes") {
  temp_tree t;
  t.write("inc/a.glsl", "int a;\r\n");
  const auto r = resolve_includes(
      "#version 430\r\n/* #include \"nope.glsl\"\n#include \"nope.glsl\" */\n"
      "// #include \"nope.glsl\"\n#include \"a.glsl\" // trailing comment\nvoid main() {}\n",
      "s", {t.dir("inc")});
  CHECK(count_of(r.text, "int a;") == 1);
  CHECK(count_of(r.text, "\r") == 0);
  CHECK(location_of(r.text, "void main() {}") == "0:6");
  CHECK_THROWS_AS(resolve_includes("#include a.glsl\n", "s", {t.dir("inc")}), include_error);
  t.write("inc/v.glsl", "#version 450\n");
  CHECK_THROWS_AS(resolve_includes("#include \"v.glsl\"\n", "s", {t.dir("inc")}), include_error);
}

TEST_CASE("include_resolver: resolve_include_file looks next to the file first") {
  temp_tree t;
  t.write("kernels/common.glsl", "int common_value;\n");
  const std::string path = t.write("kernels/k.comp", "#version 430\n#include \"common.glsl\"\n");
  const auto r = resolve_include_file(path, {});
  REQUIRE(r.files.size() == 2);
  CHECK(r.files[0].path == path);
  CHECK(r.file_label(1) == (fs::path(t.dir("kernels")) / "common.glsl").string());
  CHECK(count_of(r.text, "int common_value;") == 1);
}

TEST_CASE("include_resolver: map_log names files in Mesa, glslang and NVIDIA logs") {
  vplkit::glsl::resolved_source r;
  r.files = {{"main.comp", ""}, {"vplkit/a.glsl", "/pack/vplkit/a.glsl"}};
  CHECK(r.map_log("0:12(3): error: `x' undeclared\n1:4(1): warning: y") ==
        "main.comp:12(3): error: `x' undeclared\n/pack/vplkit/a.glsl:4(1): warning: y");
  CHECK(r.map_log("ERROR: 1:7: 'foo' : undeclared identifier\n") ==
        "ERROR: /pack/vplkit/a.glsl:7: 'foo' : undeclared identifier\n");
  CHECK(r.map_log("1(12) : error C1008: undefined variable \"z\"") ==
        "/pack/vplkit/a.glsl(12) : error C1008: undefined variable \"z\"");
  // Numbers beyond the table and numbers inside messages stay as they are.
  CHECK(r.map_log("5:1(1): error: 0:3 is not a file") == "5:1(1): error: 0:3 is not a file");
}

TEST_CASE("include_resolver: includes in C++ branches of two-language headers are left out") {
  temp_tree t;
  // A *_params.h-style header: C++ includes under __cplusplus that do not exist for GLSL, GLSL
  // includes in the other branches, and an ordinary #ifdef whose include must still exist.
  t.write("pack/vplkit/core/g.glsl", "float vplkit_g() { return 2.0; }\n");
  t.write("pack/vplkit/core/h.glsl", "float vplkit_h() { return 3.0; }\n");
  t.write("pack/vplkit/core/params.h",
          "#ifdef __cplusplus\n"
          "#include <glm/vec4.hpp>\n"                      // 2: C++ only
          "#if SOMETHING\n"
          "#include \"cxx_only.hpp\"\n"                    // 4: nested in the C++ branch
          "#endif\n"
          "#else\n"
          "#include \"g.glsl\"\n"                          // 7: GLSL
          "#endif\n"
          "#if defined( __cplusplus )  // comment\n"
          "#include <cstdint>\n"                           // 10: C++ only
          "#endif\n"
          "#ifndef __cplusplus\n"
          "#include \"h.glsl\"\n"                          // 13: GLSL
          "#elif OTHER\n"
          "#include <other_cxx.hpp>\n"                     // 15: C++ only (needs __cplusplus)
          "#else\n"
          "#include <more_cxx.hpp>\n"                      // 17: C++ only
          "#endif\n"
          "struct vplkit_p { vec4 a; };\n");
  const auto r = resolve_includes("#version 430\n#include \"vplkit/core/params.h\"\nvoid main() {}\n", "root",
                                  {t.dir("pack")});
  CHECK(count_of(r.text, "vplkit_g()") == 1);
  CHECK(count_of(r.text, "vplkit_h()") == 1);
  CHECK(count_of(r.text, "glm/vec4.hpp") == 0);
  CHECK(count_of(r.text, "#include") == 0);
  CHECK(location_of(r.text, "struct vplkit_p { vec4 a; };") == "1:19");  // numbering kept
  CHECK(r.files.size() == 4);  // root, params.h, g.glsl, h.glsl

  // An include in an ordinary conditional branch is still looked up.
  t.write("pack/vplkit/core/q.h", "#ifdef VPLKIT_OPTION\n#include \"missing.glsl\"\n#endif\n");
  CHECK_THROWS_AS(resolve_includes("#include \"vplkit/core/q.h\"\n", "root", {t.dir("pack")}), include_error);
}
