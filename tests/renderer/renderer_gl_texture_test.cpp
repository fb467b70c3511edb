// SPDX-License-Identifier: MIT
// A textured OBJ through the G-buffer shader (GL_SRGB8, GL_LINEAR, GL_REPEAT, no mipmaps): the
// albedo buffer shows the map_Kd picture decoded to linear, the right way up, and agrees with the
// CPU lookup sample_texture at every pixel's texcoord; a missing texture falls back to Kd.
// Fixtures (OBJ, MTL, PNG) are written by the test into a temporary directory.
#include "raster/gl_raster.hpp"
#include "render/pipeline.hpp"
#include "renderer_test_util.hpp"
#include "scene/obj_loader.hpp"
#include "scene/texture.hpp"

#include <catch2/catch.hpp>

#include <stb_image_write.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

using namespace vplrender;
using vplrender_test::temp_dir;

namespace {

// One unit quad in z = 0 facing +z, texcoords = (x, y), so a G-buffer pixel's texcoord is its
// position's xy.
const char* kQuadObj =
    "mtllib q.mtl\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    "vn 0 0 1\n"
    "usemtl m\nf 1/1/1 2/2/1 3/3/1 4/4/1\n";

// The 2x2 checker as the PNG file shows it: cells[row][col], row 0 = the TOP of the picture.
const unsigned char kCells[2][2][3] = {{{200, 30, 30}, {30, 200, 30}},     // top: red, green
                                       {{30, 30, 200}, {220, 220, 40}}};  // bottom: blue, yellow
constexpr int kTexels = 8;  // 8x8 texels, each cell 4x4: cell interiors filter to the pure colour

double srgb_decode(unsigned char c) {  // IEC 61966-2-1, in double: independent of color.hpp
  const double x = c / 255.0;
  return x <= 0.04045 ? x / 12.92 : std::pow((x + 0.055) / 1.055, 2.4);
}

std::string write_checker_png(const temp_dir& d) {
  std::vector<unsigned char> px(kTexels * kTexels * 3);
  for (int y = 0; y < kTexels; ++y)  // y = file row, 0 at the top
    for (int x = 0; x < kTexels; ++x)
      for (int k = 0; k < 3; ++k)
        px[static_cast<std::size_t>((y * kTexels + x) * 3 + k)] = kCells[y / (kTexels / 2)][x / (kTexels / 2)][k];
  const std::string p = d.file("checker.png");
  REQUIRE(stbi_write_png(p.c_str(), kTexels, kTexels, 3, px.data(), kTexels * 3));
  return p;
}

// The G-buffer of the quad seen straight on from +z (camera up +y: image right = +x, top = +y).
gbuffer_data render_quad(const scene& s, int W, int H) {
  pipeline_gl_context();
  camera cam;
  cam.eye = vec3(0.5f, 0.5f, 1.6f);
  cam.target = vec3(0.5f, 0.5f, 0.0f);
  cam.up = vec3(0.0f, 1.0f, 0.0f);
  cam.vfov_deg = 45.0f;
  gl_rasterizer r(s);
  return r.render_gbuffer(cam, W, H);
}

// Pixels over the quad whose texcoord (= position xy) is at least `inset` inside [0, 1]^2.
template <class F>
int for_quad_pixels(const gbuffer_data& g, float inset, F&& f) {
  int n = 0;
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y * g.width + x);
      if (g.normal[i] == vec3(0.0f)) continue;  // background
      const vec2 uv(g.position[i].x, g.position[i].y);
      if (uv.x < inset || uv.x > 1.0f - inset || uv.y < inset || uv.y > 1.0f - inset) continue;
      f(x, y, i, uv);
      ++n;
    }
  return n;
}

}  // namespace

TEST_CASE("a map_Kd texture reaches the G-buffer albedo decoded to linear and the right way up") {
  temp_dir d;
  write_checker_png(d);
  d.write("q.mtl", "newmtl m\nKd 0.5 0.5 0.5\nmap_Kd checker.png\n");
  const scene s = load_obj_scene(d.write("q.obj", kQuadObj));
  REQUIRE(s.textures.size() == 1);
  REQUIRE(s.warnings.empty());
  const int W = 64, H = 64;
  const gbuffer_data g = render_quad(s, W, H);

  // 1. Cell interiors: a texcoord more than half a texel (1/16) from every cell border (and from
  // the wrap at 0 / 1) filters to one texel colour only. Cell (row r, col c) of the FILE lies at
  // u in [c/2, c/2 + 1/2], v in [1/2 - r/2, 1 - r/2]: file row 0 (top) is v = 1 (the loader puts
  // the bottom row at v = 0, as OBJ texcoords expect), and the camera shows v = 1 at the top.
  // Bound: 4e-3, the GPU's sRGB decode (llvmpipe's is approximate: measured worst 1.2e-3) and float
  // rounding; a third of one 8-bit step at the top of the range (0.013), far below a wrong cell.
  const double half_texel = 0.5 / kTexels;
  int per_cell[2][2] = {{0, 0}, {0, 0}};
  double worst = 0.0;
  for_quad_pixels(g, 0.0f, [&](int x, int y, std::size_t i, vec2 uv) {
    const int col = uv.x < 0.5f ? 0 : 1;
    const int row = uv.y >= 0.5f ? 0 : 1;  // file row
    const double fu = uv.x - 0.5 * col, fv = uv.y - 0.5 * (1 - row);
    if (fu < half_texel + 1e-3 || fu > 0.5 - half_texel - 1e-3 || fv < half_texel + 1e-3 || fv > 0.5 - half_texel - 1e-3)
      return;
    ++per_cell[row][col];
    for (int k = 0; k < 3; ++k) {
      const double want = srgb_decode(kCells[row][col][k]);
      const double err = std::abs(double(g.albedo[i][k]) - want);
      worst = std::max(worst, err);
      INFO("pixel (" << x << ", " << y << ") uv (" << uv.x << ", " << uv.y << ") cell row " << row << " col " << col
                     << " channel " << k);
      CHECK(err <= 4e-3);
    }
    // Screen orientation as well: the top half of the image shows the top of the picture.
    CHECK((y < H / 2) == (row == 0));
    CHECK((x < W / 2) == (col == 0));
  });
  std::cout << "cell interiors: worst |albedo - srgb_decode(cell)| = " << worst << "\n";
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 2; ++c) CHECK(per_cell[r][c] >= 50);  // each cell covered by many pixels

  // 2. Every pixel over the quad (borders and wrap included) against the CPU lookup at the
  // pixel's texcoord. Bound 0.01: GL filters with fixed-point weights (llvmpipe: 8 bits, 1/256 of
  // a texel), so across a cell border, where neighbouring texels differ by up to 0.58 (linear),
  // the blend may be off by 0.58 / 256 ~ 2.3e-3 plus the decode error (measured worst on llvmpipe:
  // 1.2e-3, all from the decode); 0.01 leaves room, a wrong flip, wrap or decode is off by ~0.2-0.6.
  double worst_lookup = 0.0;
  const int n = for_quad_pixels(g, 1e-3f, [&](int x, int y, std::size_t i, vec2 uv) {
    const vec3 cpu = sample_texture(s.textures[0], uv);
    for (int k = 0; k < 3; ++k) {
      const double err = std::abs(double(g.albedo[i][k]) - double(cpu[k]));
      worst_lookup = std::max(worst_lookup, err);
      INFO("pixel (" << x << ", " << y << ") uv (" << uv.x << ", " << uv.y << ") channel " << k);
      CHECK(err <= 0.01);
    }
  });
  std::cout << "all " << n << " quad pixels: worst |albedo - sample_texture(uv)| = " << worst_lookup << "\n";
  CHECK(n > W * H / 4);
}

TEST_CASE("a missing map_Kd texture is a warning and the G-buffer albedo is Kd") {
  temp_dir d;
  d.write("q.mtl", "newmtl m\nKd 0.2 0.4 0.6\nmap_Kd no_such_texture.png\n");
  const scene s = load_obj_scene(d.write("q.obj", kQuadObj));
  CHECK(s.textures.empty());
  REQUIRE(s.warnings.size() == 1);
  CHECK(s.warnings[0].find("no_such_texture.png") != std::string::npos);
  CHECK(s.warnings[0].find("using Kd") != std::string::npos);
  const gbuffer_data g = render_quad(s, 32, 32);
  const int n = for_quad_pixels(g, 0.0f, [&](int, int, std::size_t i, vec2) {
    CHECK(g.albedo[i].x == Approx(0.2f).margin(1e-6));
    CHECK(g.albedo[i].y == Approx(0.4f).margin(1e-6));
    CHECK(g.albedo[i].z == Approx(0.6f).margin(1e-6));
  });
  CHECK(n > 32 * 32 / 4);
}
