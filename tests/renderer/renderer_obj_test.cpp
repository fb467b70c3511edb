// SPDX-License-Identifier: MIT
// OBJ/MTL loading: what real files do (quads, n-gons, no normals, CRLF, missing MTL or textures,
// textures, relative indices) and what broken files do (each gets a one-line error naming file and
// line, never a crash). Every fixture is written by the test into its own temporary directory.
#include <catch2/catch.hpp>

#include "io/errors.hpp"
#include "renderer_test_util.hpp"
#include "scene/obj_loader.hpp"
#include "scene/obj_scan.hpp"
#include "scene/texture.hpp"

#include <stb_image_write.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

using namespace vplrender;
using vplrender_test::temp_dir;

namespace {

const char* kQuad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

double total_area(const scene& s) {
  double a = 0.0;
  for (const triangle& t : s.triangles) a += 0.5 * triangle_double_area(t);
  return a;
}

bool has_warning(const scene& s, const std::string& part) {
  return std::any_of(s.warnings.begin(), s.warnings.end(),
                     [&](const std::string& w) { return w.find(part) != std::string::npos; });
}

// The one-line error message loading `text` produces ("" if it loads).
std::string load_error(const std::string& text, const std::string& name = "bad.obj") {
  temp_dir d;
  const std::string path = d.write(name, text);
  try {
    load_obj_scene(path);
  } catch (const input_error& e) {
    std::string m = e.what();
    CHECK(m.find('\n') == std::string::npos);
    const std::string prefix = path + ":";
    CHECK(m.rfind(prefix, 0) == 0);  // names the file
    return m.substr(path.size());   // ":line: message" or ": message"
  }
  return "";
}

// The one-line error loading an OBJ whose MTL library holds `mtl` produces, without the MTL
// path that must start it ("" if it loads).
std::string mtl_error(const std::string& mtl) {
  temp_dir d;
  const std::string lib = d.write("m.mtl", mtl);
  const std::string obj = d.write("m.obj", "mtllib m.mtl\n" + std::string(kQuad) + "usemtl a\nf 1 2 3 4\n");
  try {
    load_obj_scene(obj);
  } catch (const input_error& e) {
    std::string m = e.what();
    CHECK(m.find('\n') == std::string::npos);
    CHECK(m.rfind(lib + ":", 0) == 0);  // names the MTL file
    return m.substr(std::min(lib.size(), m.size()));
  }
  return "";
}

// A FIFO at `path`, and a watchdog for it: should the code under test still wait on the FIFO
// after 5 s, the watchdog opens it for writing once, which releases a blocked open (and the read
// after it sees end of file). A regression then fails its checks instead of hanging the suite.
class fifo_with_watchdog {
public:
  explicit fifo_with_watchdog(std::string path) : path_(std::move(path)) {
    REQUIRE(::mkfifo(path_.c_str(), 0600) == 0);
    thread_ = std::thread([this] {
      std::unique_lock<std::mutex> lock(mutex_);
      if (cv_.wait_for(lock, std::chrono::seconds(5), [this] { return done_; })) return;
      released_ = true;
      const int fd = ::open(path_.c_str(), O_WRONLY | O_NONBLOCK);
      if (fd >= 0) ::close(fd);
    });
  }
  ~fifo_with_watchdog() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      done_ = true;
    }
    cv_.notify_all();
    thread_.join();
  }
  fifo_with_watchdog(const fifo_with_watchdog&) = delete;
  fifo_with_watchdog& operator=(const fifo_with_watchdog&) = delete;
  // True when the code under test waited on the FIFO (the watchdog had to release it).
  bool released() const { return released_; }

private:
  std::string path_;
  std::mutex mutex_;
  std::condition_variable cv_;
  bool done_ = false;
  std::atomic<bool> released_{false};
  std::thread thread_;
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

TEST_CASE("a quad becomes two triangles with the flat normal of its winding") {
  temp_dir d;
  const scene s = load_obj_scene(d.write("quad.obj", std::string(kQuad) + "f 1 2 3 4\n"));
  REQUIRE(s.triangles.size() == 2);
  CHECK(total_area(s) == Approx(1.0));
  for (const triangle& t : s.triangles)
    for (const vec3& n : t.n) CHECK(n.z == Approx(1.0f));  // counter-clockwise seen from +z
  const scene flipped = load_obj_scene(d.write("flip.obj", std::string(kQuad) + "f 4 3 2 1\n"));
  for (const triangle& t : flipped.triangles)
    for (const vec3& n : t.n) CHECK(n.z == Approx(-1.0f));
  // No usemtl: the default material.
  REQUIRE(s.materials.size() == 1);
  CHECK(s.materials[0].name == "default");
  CHECK(s.materials[0].kd == vec3(0.8f));
  CHECK(s.warnings.empty());
}

TEST_CASE("n-gons, convex and concave, keep their area") {
  temp_dir d;
  // A regular octagon and an L-shaped hexagon (concave) side by side.
  std::string obj;
  for (int i = 0; i < 8; ++i) {
    const double a = 2.0 * 3.141592653589793 * i / 8.0;
    obj += "v " + std::to_string(std::cos(a)) + " 0 " + std::to_string(-std::sin(a)) + "\n";
  }
  obj += "v 3 0 0\nv 5 0 0\nv 5 0 -1\nv 4 0 -1\nv 4 0 -2\nv 3 0 -2\n";
  obj += "f 1 2 3 4 5 6 7 8\nf 9 10 11 12 13 14\n";
  const scene s = load_obj_scene(d.write("ngon.obj", obj));
  CHECK(s.triangles.size() == 6 + 4);
  const double octagon = 8 * 0.5 * std::sin(2.0 * 3.141592653589793 / 8.0);
  CHECK(total_area(s) == Approx(octagon + 3.0).epsilon(1e-5));
  for (const triangle& t : s.triangles)
    for (const vec3& n : t.n) CHECK(n.y == Approx(1.0f));
}

TEST_CASE("given normals are normalised and kept as authored -- zero ones fall back to the face") {
  temp_dir d;
  const std::string obj = std::string(kQuad) + "vn 0 0 5\nvn 0 0 -1\nvn 0 0 0\nf 1//1 2//2 3//3\n";
  const scene s = load_obj_scene(d.write("n.obj", obj));
  REQUIRE(s.triangles.size() == 1);
  CHECK(s.triangles[0].n[0] == vec3(0, 0, 1));
  CHECK(s.triangles[0].n[1] == vec3(0, 0, -1));
  CHECK(s.triangles[0].n[2] == vec3(0, 0, 1));  // zero normal -> flat face normal
}

TEST_CASE("CRLF, lone CR, tabs, comments and negative (relative) indices") {
  temp_dir d;
  const std::string crlf = "# comment\r\nv\t0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nv 0 1 0\r\ng  quad \r\nf -4 -3 -2 -1 # trailing\r\n";
  const scene a = load_obj_scene(d.write("crlf.obj", crlf));
  CHECK(a.triangles.size() == 2);
  CHECK(total_area(a) == Approx(1.0));
  std::string cr = crlf;
  cr.erase(std::remove(cr.begin(), cr.end(), '\n'), cr.end());
  const scene b = load_obj_scene(d.write("cr.obj", cr));
  CHECK(b.triangles.size() == 2);
  // Line numbers count CRLF and CR endings alike.
  CHECK(load_error("v 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nf 1 2 4\r\n") ==
        ":4: vertex index 4 is out of range (the file has 3 vertices)");
  CHECK(load_error("v 0 0 0\rv 1 0 0\rv 1 1 0\rf 1 2 4\r") ==
        ":4: vertex index 4 is out of range (the file has 3 vertices)");
}

TEST_CASE("a face may refer to vertices defined after it") {
  temp_dir d;
  const scene s = load_obj_scene(d.write("fwd.obj", "f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"));
  CHECK(s.triangles.size() == 1);
}

TEST_CASE("a missing MTL library is a warning -- faces use the default material") {
  temp_dir d;
  const std::string obj = "mtllib nowhere.mtl\n" + std::string(kQuad) + "usemtl red\nf 1 2 3 4\n";
  const scene s = load_obj_scene(d.write("nomtl.obj", obj));
  CHECK(s.triangles.size() == 2);
  CHECK(has_warning(s, ":1: material library 'nowhere.mtl' not found"));
  REQUIRE(s.materials.size() == 1);
  CHECK(s.materials[0].kd == vec3(0.8f));
}

TEST_CASE("per-material Kd, clamped when above 1, unknown usemtl gets the default") {
  temp_dir d;
  d.write("m.mtl", "newmtl red\nKd 0.7 0.1 0.05\nnewmtl hot\nKd 2 0.5 0.5\nKe 1 1 1\n");
  const std::string obj = "mtllib m.mtl\n" + std::string(kQuad) +
                          "usemtl red\nf 1 2 3\nusemtl hot\nf 1 3 4\nusemtl unknown\nf 1 2 4\n";
  const scene s = load_obj_scene(d.write("m.obj", obj));
  REQUIRE(s.triangles.size() == 3);
  CHECK(s.materials[s.triangles[0].material].name == "red");
  CHECK(s.materials[s.triangles[0].material].kd == vec3(0.7f, 0.1f, 0.05f));
  CHECK(s.materials[s.triangles[1].material].kd == vec3(1.0f, 0.5f, 0.5f));
  CHECK(s.materials[s.triangles[1].material].ke == vec3(1.0f));
  CHECK(has_warning(s, "'hot' has Kd"));
  CHECK(s.materials[s.triangles[2].material].name == "default");
  CHECK(has_warning(s, "unknown"));
}

TEST_CASE("map_Kd textures are loaded bottom row first -- missing ones fall back to Kd") {
  temp_dir d;
  // 2x2 PNG: file row 0 (top) red, green; row 1 (bottom) blue, white.
  const unsigned char px[] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255};
  REQUIRE(stbi_write_png(d.file("tex.png").c_str(), 2, 2, 3, px, 6));
  d.write("t.mtl",
          "newmtl tex\nKd 0.5 0.5 0.5\nmap_Kd tex.png\n"
          "newmtl gone\nKd 0.2 0.3 0.4\nmap_Kd missing.png\n"
          "newmtl broken\nKd 0.1 0.1 0.1\nmap_Kd broken.png\n"
          "newmtl scaled\nmap_Kd -s 2 3 1 -o 0.5 0.25 0 tex.png\n");
  d.write("broken.png", "this is not a png");
  const std::string obj = "mtllib t.mtl\n" + std::string(kQuad) +
                          "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                          "usemtl tex\nf 1/1 2/2 3/3\nusemtl gone\nf 1/1 3/3 4/4\nusemtl broken\nf 1/1 2/2 4/4\n"
                          "usemtl tex\nf 1 3 4\nusemtl scaled\nf 1/1 2/2 3/3\n";
  const scene s = load_obj_scene(d.write("t.obj", obj));
  REQUIRE(s.triangles.size() == 5);
  REQUIRE(s.textures.size() == 1);  // shared by "tex" and "scaled"
  // map_Kd -s / -o are applied to the texcoords: uv * (2, 3) + (0.5, 0.25).
  CHECK(s.materials[s.triangles[4].material].texture == 0);
  CHECK(s.triangles[4].uv[0] == vec2(0.5f, 0.25f));
  CHECK(s.triangles[4].uv[2] == vec2(2.5f, 3.25f));
  const texture_rgb8& t = s.textures[0];
  CHECK(t.width == 2);
  CHECK(t.height == 2);
  // Row 0 is v = 0, the bottom of the picture: blue, white.
  CHECK(int(t.texels[0]) == 0);
  CHECK(int(t.texels[2]) == 255);
  CHECK(int(t.texels[6]) == 255);  // top-left red is now row 1
  const material& tex = s.materials[s.triangles[0].material];
  CHECK(tex.texture == 0);
  CHECK(s.triangles[0].uv[2] == vec2(1.0f, 1.0f));
  // Texel centres decode from sRGB: (0.25, 0.75) is the top-left texel, red.
  const vec3 red = albedo(s, tex, vec2(0.25f, 0.75f));
  CHECK(red.x == Approx(1.0f));
  CHECK(red.y == Approx(0.0f).margin(1e-6));
  CHECK(sample_texture(t, vec2(0.75f, 0.25f)) == vec3(1.0f));  // white, bottom right
  CHECK(sample_texture(t, vec2(1.75f, -0.75f)) == vec3(1.0f)); // repeat wrapping
  // Missing and unreadable textures: warnings, Kd.
  CHECK(s.materials[s.triangles[1].material].texture == -1);
  CHECK(s.materials[s.triangles[1].material].kd == vec3(0.2f, 0.3f, 0.4f));
  CHECK(has_warning(s, "texture 'missing.png' of material 'gone' not found; using Kd"));
  CHECK(s.materials[s.triangles[2].material].texture == -1);
  CHECK(has_warning(s, "broken.png: cannot load texture"));
  // A textured material on a face without texcoords: an untextured copy.
  const material& bare = s.materials[s.triangles[3].material];
  CHECK(bare.texture == -1);
  CHECK(bare.kd == vec3(0.5f));
  CHECK(has_warning(s, "have no texcoords"));
}

TEST_CASE("unknown and unsupported statements are ignored with one warning each") {
  temp_dir d;
  const std::string obj = std::string(kQuad) + "f 1 2 3 4\nl 1 2\nl 2 3\nfoo bar\ncstype bezier\n";
  const scene s = load_obj_scene(d.write("w.obj", obj));
  CHECK(s.triangles.size() == 2);
  CHECK(has_warning(s, ":6: unsupported statement 'l' ignored (2 lines)"));
  CHECK(has_warning(s, ":8: unknown statement 'foo' ignored (1 line)"));
  CHECK(has_warning(s, "unsupported statement 'cstype'"));
}

TEST_CASE("malformed lines are errors naming file and line") {
  CHECK(load_error("v 0 0 0\nv 1 abc 0\n") == ":2: malformed vertex: 'abc' is not a number");
  CHECK(load_error("v 0 0\n") == ":1: malformed vertex: expected 3 to 7 numbers, got 2");
  CHECK(load_error("v 0 0 0 1 2 3 4 5\n") == ":1: malformed vertex: expected 3 to 7 numbers, got 8");
  CHECK(load_error("vn 0 1\n") == ":1: malformed normal: expected 3 numbers, got 2");
  CHECK(load_error("vt\n") == ":1: malformed texcoord: expected 1 to 3 numbers, got 0");
  CHECK(load_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n") == ":4: face with 2 vertices (a face needs at least 3)");
  CHECK(load_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 x 3\n") == ":4: malformed vertex reference 'x'");
  CHECK(load_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/ 2 3\n") == ":4: malformed vertex reference '1/'");
  CHECK(load_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1/1/1 2 3\n") == ":4: malformed vertex reference '1/1/1/1'");
  CHECK(load_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1.5 2 3\n") == ":4: malformed vertex reference '1.5'");
  CHECK(load_error("v 0 0 0\nv 1 0 0\nv 0 1 0 \\\nf 1 2 3\n") == ":3: line continuation with '\\' is not supported");
  CHECK(load_error(std::string("v 0 0 0\nv 1 0\0 0\n", 17)) == ":2: NUL byte: this is not a text OBJ file");
}

TEST_CASE("indices out of range, zero, or relative before the first vertex") {
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  CHECK(load_error(tri + "f 1 2 4\n") == ":4: vertex index 4 is out of range (the file has 3 vertices)");
  CHECK(load_error(tri + "f 0 1 2\n") == ":4: vertex index 0 in '0' (OBJ indices start at 1)");
  CHECK(load_error(tri + "f -1 -2 -4\n") == ":4: relative vertex index -4 refers before the first vertex (3 defined so far)");
  CHECK(load_error(tri + "f 1/1 2/1 3/1\n") == ":4: texcoord index 1 is out of range (the file has 0 texcoords)");
  CHECK(load_error(tri + "vn 0 0 1\nf 1//1 2//2 3//1\n") == ":5: normal index 2 is out of range (the file has 1 normal)");
  CHECK(load_error(tri + "f 1 2 99999999999999999999\n") ==
        ":4: vertex index 99999999999999999999 is out of range (the file has 3 vertices)");
  // Relative indices count only what precedes the face.
  CHECK(load_error("v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 0 1 0\n") ==
        ":3: relative vertex index -3 refers before the first vertex (2 defined so far)");
}

TEST_CASE("NaN, Inf and out-of-float-range vertices are errors") {
  CHECK(load_error("v 0 nan 0\n") == ":1: malformed vertex: 'nan' is not a number");
  CHECK(load_error("v 0 0 inf\n") == ":1: malformed vertex: 'inf' is not a number");
  CHECK(load_error("v 0 0 -Infinity\n") == ":1: malformed vertex: '-Infinity' is not a number");
  CHECK(load_error("v 0 0 1e39\n") == ":1: vertex value '1e39' is out of range (not a finite float)");
  CHECK(load_error("v 0 0 1e999999\n") == ":1: vertex value '1e999999' is out of range (not a finite float)");
  CHECK(load_error("v 0 0 0\nvn 0 0 nan\n") == ":2: malformed normal: 'nan' is not a number");
  CHECK(load_error("v 0 0 0\nvt 0x10 0\n") == ":2: malformed texcoord: '0x10' is not a number");
  // What tinyobjloader reads as 0 must not slip through: numbers are accepted as it parses them.
  temp_dir d;
  const scene s = load_obj_scene(d.write("num.obj", "v -.5 +1. 2e-1\nv 1E+1 0 0\nv 0 1 0\nf 1 2 3\n"));
  CHECK(s.triangles[0].p[0] == vec3(-0.5f, 1.0f, 0.2f));
  CHECK(s.triangles[0].p[1].x == 10.0f);
}

TEST_CASE("empty and degenerate scenes are errors") {
  CHECK(load_error("") == ": empty scene (no faces)");
  CHECK(load_error("# only a comment\n\n") == ": empty scene (no faces)");
  CHECK(load_error("v 0 0 0\nv 1 0 0\n") == ": empty scene (no faces, 2 vertices)");
  CHECK(load_error("v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\nf 1 1 1\n") ==
        ": degenerate scene: all 2 faces have zero area");
  CHECK(load_error("v 5 5 5\nv 5 5 5\nv 5 5 5\nv 5 5 5\nf 1 2 3 4\n") ==
        ": degenerate scene: all 1 faces have zero area");
  // Distinct vertices near 1e-38 (denormal extent): not "every vertex is at (0, 0, 0)".
  const std::string tiny = load_error("v 1e-38 0 0\nv 0 1e-38 0\nv 0 0 1e-38\nf 1 2 3\n");
  CHECK_THAT(tiny, Catch::StartsWith(": the scene's extent (1e-38, 1e-38, 1e-38) is too small to render"));
  CHECK_THAT(tiny, Catch::Contains("denormal") && Catch::Contains("scale the model up"));
  // Some degenerate faces among good ones: dropped with a warning naming the first.
  temp_dir d;
  const scene s = load_obj_scene(d.write("some.obj", std::string(kQuad) + "f 1 2 3\nf 1 1 2\nf 1 3 4\n"));
  CHECK(s.triangles.size() == 2);
  CHECK(has_warning(s, ":6: dropped 1 zero-area"));
}

TEST_CASE("missing and unreadable files are errors naming the file") {
  temp_dir d;
  const std::string missing = d.file("missing.obj");
  CHECK_THROWS_WITH(load_obj_scene(missing), missing + ": cannot open (No such file or directory)");
  CHECK_THROWS_WITH(load_obj_scene(d.path()), d.path() + ": is a directory, not a file");
  CHECK_THROWS_AS(load_texture(d.file("none.png")), input_error);
}

TEST_CASE("huge coordinates that overflow the bounds are refused") {
  CHECK(load_error("v -3e38 0 0\nv 3e38 0 0\nv 0 3e38 0\nf 1 2 3\n").find("not finite") != std::string::npos);
}

TEST_CASE("the scan reports counts, face lines and cleaned text with the same line numbers") {
  const obj_scan_result r = scan_obj("v 0 0 0\r\nv 1 0 0\rv 0 1 0\n\nf 1 2 3 # c\nfoo\nusemtl a#b\n", "x.obj");
  CHECK(r.vertices == 3);
  CHECK(r.face_lines == std::vector<std::size_t>{5});
  CHECK(r.cleaned == "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 3\n\nusemtl a#b\n");
}

TEST_CASE("mutated files either load into a valid scene or fail with input_error, never anything else") {
  // A small file using most of the syntax; 3000 deterministic mutations (byte flips to characters
  // that matter in OBJ, insertions, deletions, truncations), each loaded from memory.
  const std::string base =
      "mtllib m.mtl\r\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 1\nvn 0 0 1\n"
      "usemtl a\nf 1/1/1 2/2/1 3/1/1 4/2/1\nf -4 -3 -2\ng x\nf 1//1 3//1 4//1 # c\n";
  temp_dir d;
  d.write("m.mtl", "newmtl a\nKd 0.5 0.2 0.1\n");
  const char alphabet[] = " \t\r\n/-.#e0123456789vfnt\\";
  std::uint32_t state = 12345u;
  auto next = [&]() {  // xorshift32: fixed seed, reproducible
    state ^= state << 13;
    state ^= state >> 17;
    state ^= state << 5;
    return state;
  };
  std::size_t loaded = 0, refused = 0;
  for (int i = 0; i < 3000; ++i) {
    std::string text = base;
    const int edits = 1 + static_cast<int>(next() % 3);
    for (int e = 0; e < edits && !text.empty(); ++e) {
      const std::size_t at = next() % text.size();
      switch (next() % 4) {
        case 0: text[at] = alphabet[next() % (sizeof alphabet - 1)]; break;
        case 1: text.insert(at, 1, alphabet[next() % (sizeof alphabet - 1)]); break;
        case 2: text.erase(at, 1 + next() % 4); break;
        default: text.resize(at); break;
      }
    }
    try {
      const scene s = load_obj_text(text, "fuzz.obj", d.path());
      CHECK_NOTHROW(validate_geometry(s));
      ++loaded;
    } catch (const input_error& e) {
      const std::string m = e.what();
      CHECK(m.find('\n') == std::string::npos);
      ++refused;
    }
  }
  CHECK(loaded + refused == 3000);
  CHECK(loaded > 100);
  CHECK(refused > 100);
}

TEST_CASE("malformed MTL statements are errors naming the MTL file and line") {
  CHECK(mtl_error("newmtl a\nKd abc\n") == ":2: malformed Kd: 'abc' is not a number");
  CHECK(mtl_error("newmtl a\nKd nan nan nan\n") == ":2: malformed Kd: 'nan' is not a number");
  CHECK(mtl_error("newmtl a\nKd 1 2\n") == ":2: malformed Kd: expected 1 or 3 numbers, got 2");
  CHECK(mtl_error("newmtl a\nKd 1 2 3 4\n") == ":2: malformed Kd: expected 1 or 3 numbers, got 4");
  CHECK(mtl_error("newmtl a\nKd\n") == ":2: malformed Kd: expected 1 or 3 numbers, got 0");
  CHECK(mtl_error("newmtl a\nKd 0 0 1e39\n") == ":2: Kd value '1e39' is out of range (not a finite float)");
  CHECK(mtl_error("newmtl a\nKd inf 0 0\n") == ":2: malformed Kd: 'inf' is not a number");
  CHECK(mtl_error("newmtl a\r\n\r\nKe 1 x 1\r\n") == ":3: malformed Ke: 'x' is not a number");
  CHECK(mtl_error("newmtl a\nKd spectral white.rfl\n") == ":2: Kd spectral is not supported; give Kd r g b");
  CHECK(mtl_error("newmtl a\nKd xyz 0.5 0.5 0.5\n") == ":2: Kd xyz is not supported; give Kd r g b");
  CHECK(mtl_error("newmtl\n") == ":1: newmtl without a material name");
  CHECK(mtl_error("newmtl a\nmap_Kd\n") == ":2: map_Kd without a file name");
  CHECK(mtl_error("newmtl a\nmap_Kd -s 2 3 1\n") == ":2: map_Kd without a file name");
  CHECK(mtl_error("newmtl a\nmap_Kd -s tex.png\n") == ":2: malformed map_Kd: -s needs 1 to 3 numbers");
  CHECK(mtl_error("newmtl a\nmap_Kd -o 1e40 tex.png\n") ==
        ":2: map_Kd -o value '1e40' is out of range (not a finite float)");
  CHECK(mtl_error("newmtl a\nmap_Kd -bm\n") == ":2: malformed map_Kd: -bm needs 1 value and a file name after it");
  CHECK(mtl_error("newmtl a\nmap_Kd -mm 0 x tex.png\n") == ":2: malformed map_Kd -mm: 'x' is not a number");
  CHECK(mtl_error(std::string("newmtl a\nKd 1\0 1 1\n", 19)) == ":2: NUL byte: this is not a text MTL file");
  CHECK(mtl_error("newmtl a\nKd 1 1 \\\n1\n") == ":2: line continuation with '\\' is not supported");
}

TEST_CASE("MTL: one-number Kd is grey, unused statements are ignored, orphans and unknowns warn") {
  temp_dir d;
  const unsigned char px[] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255};
  REQUIRE(stbi_write_png(d.file("tex.png").c_str(), 2, 2, 3, px, 6));
  d.write("m.mtl",
          "Kd 0.1 0.1 0.1\n"                              // before any newmtl: no material
          "newmtl grey # comment\nKd 0.5 # one number: grey\nKa abc\nNs x\nillum 2\nfoo 1\nfoo 2\n"
          "newmtl tex\nKd 0.2 0.3 0.4\nmap_Kd -s 2 -blendu off tex.png\n"
          "newmtl hot\nKd 0 0 0\nKe 1 2\t3\n");
  const std::string obj = "mtllib m.mtl\n" + std::string(kQuad) + "vt 0 0\nvt 1 0\nvt 1 1\n" +
                          "usemtl grey\nf 1 2 3\nusemtl tex\nf 1/1 2/2 3/3\nusemtl hot\nf 1 3 4\n";
  const scene s = load_obj_scene(d.write("m.obj", obj));
  REQUIRE(s.triangles.size() == 3);
  const material& grey = s.materials[s.triangles[0].material];
  CHECK(grey.name == "grey");
  CHECK(grey.kd == vec3(0.5f));
  // map_Kd -s 2 means a scale of (2, 1, 1) and still names tex.png (tinyobjloader alone loses it).
  const material& tex = s.materials[s.triangles[1].material];
  CHECK(tex.texture == 0);
  CHECK(s.triangles[1].uv[1] == vec2(2.0f, 0.0f));
  CHECK(s.triangles[1].uv[2] == vec2(2.0f, 1.0f));
  CHECK(s.materials[s.triangles[2].material].ke == vec3(1.0f, 2.0f, 3.0f));
  CHECK(has_warning(s, "m.mtl:1: 1 Kd/Ke/map_Kd statement(s) before the first newmtl belong to no material"));
  CHECK(has_warning(s, "m.mtl:7: unknown statement 'foo' ignored (2 lines)"));
  CHECK(s.warnings.size() == 2);  // Ka abc and Ns x are not used: no word about them
  // Names after mtllib may be separated by tabs (tinyobjloader alone splits on spaces only).
  const scene tabbed = load_obj_scene(d.write("tab.obj", "mtllib\tnowhere.mtl\tm.mtl\n" + obj.substr(obj.find('\n') + 1)));
  CHECK(tabbed.materials[tabbed.triangles[0].material].name == "grey");
  CHECK(has_warning(tabbed, "material library 'nowhere.mtl' not found"));
}

TEST_CASE("a scene file that is not a regular file is refused at once: FIFO, /dev/zero, directory") {
  temp_dir d;
  const std::string fifo = d.file("scene.obj");
  fifo_with_watchdog guard(fifo);
  const auto t0 = std::chrono::steady_clock::now();
  CHECK_THROWS_WITH(load_obj_scene(fifo), fifo + ": is not a regular file (a named pipe)");
  CHECK(seconds_since(t0) < 2.0);
  CHECK_FALSE(guard.released());
  // /dev/zero never ends: it must be refused before a byte is read.
  CHECK_THROWS_WITH(load_obj_scene("/dev/zero"), "/dev/zero: is not a regular file (a character device)");
  CHECK_THROWS_WITH(load_texture("/dev/zero"), "/dev/zero: is not a regular file (a character device)");
  CHECK_THROWS_WITH(load_texture(fifo), fifo + ": is not a regular file (a named pipe)");
  CHECK_FALSE(guard.released());
  // A link to a device is judged by what it points to.
  REQUIRE(::symlink("/dev/zero", d.file("link.obj").c_str()) == 0);
  CHECK_THROWS_WITH(load_obj_scene(d.file("link.obj")),
                    d.file("link.obj") + ": is not a regular file (a character device)");
}

TEST_CASE("an MTL library or texture that is not a regular file is a warning, never a wait") {
  temp_dir d;
  fifo_with_watchdog mtl_fifo(d.file("pipe.mtl"));
  fifo_with_watchdog tex_fifo(d.file("pipe.png"));
  REQUIRE(::symlink("/dev/zero", d.file("zero.mtl").c_str()) == 0);
  REQUIRE(::symlink("/dev/zero", d.file("zero.png").c_str()) == 0);
  d.write("ok.mtl", "newmtl a\nKd 0.25 0.5 0.75\nmap_Kd pipe.png\nnewmtl b\nKd 0.5 0.5 0.5\nmap_Kd zero.png\n");
  const std::string obj = "mtllib pipe.mtl zero.mtl ok.mtl\n" + std::string(kQuad) + "vt 0 0\n" +
                          "usemtl a\nf 1/1 2/1 3/1\nusemtl b\nf 1/1 3/1 4/1\n";
  const auto t0 = std::chrono::steady_clock::now();
  const scene s = load_obj_scene(d.write("p.obj", obj));
  CHECK(seconds_since(t0) < 2.0);
  CHECK_FALSE(mtl_fifo.released());
  CHECK_FALSE(tex_fifo.released());
  REQUIRE(s.triangles.size() == 2);
  CHECK(has_warning(s, ":1: material library 'pipe.mtl' (" + d.file("pipe.mtl") +
                           ") is not a regular file (a named pipe); its materials fall back to the default"));
  CHECK(has_warning(s, ":1: material library 'zero.mtl' (" + d.file("zero.mtl") +
                           ") is not a regular file (a character device)"));
  // ok.mtl still loads; its textures are refused with the reason, and the materials use Kd.
  const material& a = s.materials[s.triangles[0].material];
  CHECK(a.name == "a");
  CHECK(a.texture == -1);
  CHECK(a.kd == vec3(0.25f, 0.5f, 0.75f));
  CHECK(has_warning(s, "texture 'pipe.png' of material 'a' unreadable: " + d.file("pipe.png") +
                           " is not a regular file (a named pipe); using Kd"));
  CHECK(has_warning(s, "texture 'zero.png' of material 'b' unreadable: " + d.file("zero.png") +
                           " is not a regular file (a character device); using Kd"));
  CHECK(s.textures.empty());
}
