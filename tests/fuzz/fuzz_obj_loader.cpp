// SPDX-License-Identifier: MIT
// libFuzzer harness: the example renderer's OBJ/MTL loader (load_obj_text: obj_scan, mtl_scan,
// tinyobjloader, triangulation, textures). The input is an OBJ text, a NUL byte, then the text of
// m.mtl, written beside it (with a 2x2 tex.png that map_Kd may name). Contract: the loader returns
// a valid scene or throws input_error with a one-line message naming a file, nothing else; a
// returned scene has finite positions, unit normals, finite texcoords, Kd in [0, 1], indices in
// range, one-line warnings, and passes validate_geometry.
#include "fuzz_check.hpp"

#include "io/errors.hpp"
#include "scene/obj_loader.hpp"
#include "scene/scene.hpp"

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

using vplkit_fuzz::write_file;

const std::string& work_dir() {
  static const std::string dir = [] {
    const fs::path d = vplkit_fuzz::make_temp_dir("vplkit_fuzz_obj");
    // A 2x2 RGB PNG (red, green / blue, white), the smallest texture map_Kd can name.
    static const unsigned char png[] = {
        0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00,
        0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x02, 0x08, 0x02, 0x00, 0x00, 0x00, 0xfd, 0xd4, 0x9a, 0x73, 0x00,
        0x00, 0x00, 0x12, 0x49, 0x44, 0x41, 0x54, 0x78, 0x9c, 0x63, 0xf8, 0xcf, 0xc0, 0xc0, 0x00, 0xc2, 0x0c,
        0xff, 0x81, 0x00, 0x00, 0x1f, 0xee, 0x05, 0xfb, 0x0b, 0xd9, 0x68, 0x8b, 0x00, 0x00, 0x00, 0x00, 0x49,
        0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
    write_file(d / "tex.png", std::string(reinterpret_cast<const char*>(png), sizeof png));
    return d.string();
  }();
  return dir;
}

bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

void check_scene(const vplrender::scene& s) {
  VPLKIT_FUZZ_CHECK(!s.triangles.empty());
  for (const std::string& w : s.warnings) VPLKIT_FUZZ_CHECK(w.find('\n') == std::string::npos);
  for (const vplrender::material& m : s.materials) {
    VPLKIT_FUZZ_CHECK(finite3(m.kd) && finite3(m.ke));
    VPLKIT_FUZZ_CHECK(glm::all(glm::greaterThanEqual(m.kd, glm::vec3(0.0f))) &&
                      glm::all(glm::lessThanEqual(m.kd, glm::vec3(1.0f))));
    VPLKIT_FUZZ_CHECK(m.texture >= -1 && m.texture < static_cast<int>(s.textures.size()));
  }
  for (const vplrender::triangle& t : s.triangles) {
    VPLKIT_FUZZ_CHECK(t.material < s.materials.size());
    for (int c = 0; c < 3; ++c) {
      VPLKIT_FUZZ_CHECK(finite3(t.p[c]));
      VPLKIT_FUZZ_CHECK(finite3(t.n[c]) && std::fabs(glm::length(t.n[c]) - 1.0f) < 1e-3f);
      VPLKIT_FUZZ_CHECK(std::isfinite(t.uv[c].x) && std::isfinite(t.uv[c].y));
    }
  }
  for (const vplrender::texture_rgb8& t : s.textures)
    VPLKIT_FUZZ_CHECK(t.texels.size() == std::size_t(t.width) * std::size_t(t.height) * 3u);
  vplrender::validate_geometry(s);  // throws input_error, which the caller would report as a crash
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  // mtllib and map_Kd may name any path: keep to regular files of our own (/proc/kcore is a huge
  // "regular file"; devices and FIFOs are refused by the loader and have their own tests).
  for (const char* outside : {"/proc", "/sys", "/dev", "/run", ".."})
    if (input.find(outside) != std::string::npos) return 0;
  const std::size_t nul = input.find('\0');
  const std::string obj = input.substr(0, nul);
  const std::string& dir = work_dir();
  write_file(fs::path(dir) / "m.mtl", nul == std::string::npos ? std::string() : input.substr(nul + 1));
  try {
    const vplrender::scene s = vplrender::load_obj_text(obj, "fuzz.obj", dir);
    check_scene(s);
  } catch (const vplrender::input_error& e) {
    const std::string m = e.what();
    VPLKIT_FUZZ_CHECK(m.find('\n') == std::string::npos);
    VPLKIT_FUZZ_CHECK(m.rfind("fuzz.obj", 0) == 0 || m.rfind(dir, 0) == 0 || m.rfind("/", 0) == 0);
  }
  return 0;
}
