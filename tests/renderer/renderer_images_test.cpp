// SPDX-License-Identifier: MIT
// Outputs: OpenEXR round trip, the Reinhard PNG preview, the JSON report, and the temporary file +
// rename discipline (a failed write leaves nothing behind and never clobbers an older file).
#include <catch2/catch.hpp>

#include "app/report.hpp"
#include "cli/scene_setup.hpp"
#include "io/atomic_file.hpp"
#include "io/errors.hpp"
#include "io/exr_io.hpp"
#include "io/image.hpp"
#include "io/json_file.hpp"
#include "io/png_preview.hpp"
#include "io/text_file.hpp"
#include "renderer_test_util.hpp"

#include <stb_image.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <memory>

using namespace vplrender;
using vplrender_test::temp_dir;

namespace {

image_rgb test_image(int w, int h) {
  image_rgb img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) img.at(x, y)[c] = 0.01f * static_cast<float>(x) + 0.1f * static_cast<float>(y) + static_cast<float>(c);
  return img;
}

std::vector<unsigned char> read_png(const std::string& path, int& w, int& h) {
  int n = 0;
  std::unique_ptr<unsigned char, void (*)(void*)> data(stbi_load(path.c_str(), &w, &h, &n, 3), stbi_image_free);
  REQUIRE(data);
  return std::vector<unsigned char>(data.get(), data.get() + static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3);
}

}  // namespace

TEST_CASE("OpenEXR round trip is exact in float, extreme values included") {
  temp_dir d;
  image_rgb img = test_image(7, 5);
  img.at(0, 0)[0] = 1e-40f;  // denormal
  img.at(1, 0)[1] = 3e38f;   // far beyond half's 65504
  img.at(2, 0)[2] = 0.0f;
  img.at(3, 0)[0] = -0.25f;  // written as is (tone mapping clamps, the EXR does not)
  const std::string path = d.file("img.exr");
  write_exr(path, img, {{"vplrender:method", "mis"}});
  const image_rgb back = read_exr(path);
  REQUIRE(back.width == 7);
  REQUIRE(back.height == 5);
  CHECK(std::memcmp(back.rgb.data(), img.rgb.data(), img.rgb.size() * sizeof(float)) == 0);
  // Row 0 is the top row in the file too (checked by the value written there).
  CHECK(back.at(6, 4)[2] == img.at(6, 4)[2]);
  // Only the final file remains: no temporary left over.
  CHECK(d.entries() == std::vector<std::string>{"img.exr"});
}

TEST_CASE("images with NaN or Inf are refused before anything is written") {
  temp_dir d;
  const std::string path = d.file("bad.exr");
  image_rgb img = test_image(4, 3);
  img.at(2, 1)[1] = std::numeric_limits<float>::quiet_NaN();
  img.at(3, 2)[0] = std::numeric_limits<float>::infinity();
  CHECK_THROWS_WITH(write_exr(path, img), path + ": refusing to write an image with 2 non-finite value(s); first NaN at "
                                                 "pixel (2, 1) channel G");
  CHECK_THROWS_AS(write_png_preview(d.file("bad.png"), img), output_error);
  CHECK(d.entries().empty());
  const auto r = find_non_finite(img);
  REQUIRE(r.has_value());
  CHECK(r->count == 2);
  img.at(2, 1)[1] = 0.0f;
  CHECK_THROWS_WITH(require_finite(img, "x"), Catch::Contains("first Inf at pixel (3, 2) channel R"));
  // A buffer that does not match its size is refused too.
  image_rgb wrong(4, 3);
  wrong.rgb.pop_back();
  CHECK_THROWS_AS(require_finite(wrong, "x"), output_error);
  CHECK_THROWS_AS(require_finite(image_rgb(), "x"), output_error);
  CHECK(image_rgb(-5, 3).rgb.empty());
  CHECK_THROWS_AS(require_finite(image_rgb(-5, 3), "x"), output_error);
}

TEST_CASE("a failed write keeps the previous file and leaves no temporary") {
  temp_dir d;
  const std::string path = d.write("keep.exr", "old contents");
  image_rgb nan_img = test_image(2, 2);
  nan_img.rgb[5] = std::nanf("");
  CHECK_THROWS_AS(write_exr(path, nan_img), output_error);
  CHECK(read_file_bytes(path) == "old contents");

  // The writer fails half way: the partial temporary is removed, the old file stays.
  CHECK_THROWS_WITH(write_atomically(path,
                                     [](const std::string& temp) {
                                       std::FILE* f = std::fopen(temp.c_str(), "wb");
                                       std::fputs("partial", f);
                                       std::fclose(f);
                                       throw std::runtime_error("disk full");
                                     }),
                    "disk full");
  CHECK(read_file_bytes(path) == "old contents");
  CHECK(d.entries() == std::vector<std::string>{"keep.exr"});

  // A writer that produces nothing is an error too.
  CHECK_THROWS_WITH(write_atomically(d.file("empty.exr"), [](const std::string&) {}),
                    Catch::Contains("the writer produced an empty file"));
  CHECK(d.entries() == std::vector<std::string>{"keep.exr"});
}

TEST_CASE("writing into a missing directory fails cleanly") {
  temp_dir d;
  const std::string path = d.file("no/such/dir/img.exr");
  CHECK_THROWS_WITH(write_exr(path, test_image(2, 2)), Catch::Contains("cannot create a temporary file beside it"));
  CHECK_THROWS_AS(write_png_preview(d.file("no/img.png"), test_image(2, 2)), output_error);
  CHECK_THROWS_AS(write_json(d.file("no/x.json"), nlohmann::json::object()), output_error);
  CHECK(d.entries().empty());
}

TEST_CASE("the temporary name lives beside the target and is hidden") {
  const std::string t = temporary_name_for("/some/dir/out.exr");
  CHECK(t.rfind("/some/dir/.out.exr.", 0) == 0);
  CHECK(t.size() > 4);
  CHECK(t.compare(t.size() - 4, 4, ".tmp") == 0);
}

TEST_CASE("Reinhard on luminance, then sRGB: known values") {
  image_rgb img(5, 1);
  const float vals[5][3] = {{0, 0, 0}, {1, 1, 1}, {3, 3, 3}, {1e30f, 1e30f, 1e30f}, {-1, -2, -3}};
  for (int x = 0; x < 5; ++x)
    for (int c = 0; c < 3; ++c) img.at(x, 0)[c] = vals[x][c];
  const std::vector<std::uint8_t> ldr = tonemap_reinhard(img, 1.0f);
  CHECK(int(ldr[0]) == 0);
  // L = 1 -> 0.5 -> sRGB 0.7354 -> 188
  CHECK(int(ldr[3]) == 188);
  CHECK(int(ldr[4]) == 188);
  // L = 3 -> 0.75 -> sRGB 0.8808 -> 225
  CHECK(int(ldr[6]) == 225);
  CHECK(int(ldr[9]) == 255);   // saturates, no overflow
  CHECK(int(ldr[12]) == 0);    // negatives clamp to black
  // Exposure scales before the curve: exposure 3 on L = 1 is L = 3.
  CHECK(int(tonemap_reinhard(img, 3.0f)[3]) == 225);
  // Hue is kept: a pure red pixel stays pure red.
  image_rgb red(1, 1);
  red.at(0, 0)[0] = 2.0f;
  const std::vector<std::uint8_t> r = tonemap_reinhard(red, 1.0f);
  CHECK(int(r[0]) > 0);
  CHECK(int(r[1]) == 0);
  CHECK(int(r[2]) == 0);
}

TEST_CASE("the PNG preview is written and reads back with the tone-mapped values") {
  temp_dir d;
  const image_rgb img = test_image(6, 4);
  const std::string path = d.file("prev.png");
  write_png_preview(path, img, 0.5f);
  int w = 0, h = 0;
  const std::vector<unsigned char> back = read_png(path, w, h);
  CHECK(w == 6);
  CHECK(h == 4);
  CHECK(back == tonemap_reinhard(img, 0.5f));
  CHECK_THROWS_AS(write_png_preview(path, img, 0.0f), output_error);
  CHECK_THROWS_AS(write_png_preview(path, img, std::nanf("")), output_error);
}

TEST_CASE("the JSON report holds parameters, scene, GL renderer and stage times") {
  temp_dir d;
  const parse_result pr = parse_command_line({"vplrender", "--scene", "open", "--vpls", "33", "--light", "0.3,1.6,0.6"});
  const prepared_scene p = prepare_scene(pr.opts);
  stage_timer timer;
  {
    auto s = timer.scoped("scene");
  }
  timer.add("gbuffer", 1.5, "gpu");
  run_info run;
  run.stages = timer.stages();
  run.outputs = {"a.exr"};
  const nlohmann::json cpu = make_report(pr.opts, p, run);
  CHECK(cpu["gl_renderer"].is_null());
  run.gl_renderer = "llvmpipe (LLVM 15.0.6, 256 bits)";
  const nlohmann::json j = make_report(pr.opts, p, run);
  const std::string path = d.file("r.json");
  write_json(path, j);
  const nlohmann::json back = nlohmann::json::parse(read_file_bytes(path));
  CHECK(back == j);
  CHECK(back["parameters"]["vpls"] == 33);
  CHECK(back["parameters"]["scene"] == "open");
  CHECK(back["parameters"]["method"] == "mis");
  CHECK(back["parameters"]["light"]["intensity"].is_null());
  CHECK(back["scene"]["triangles"] == p.s.triangles.size());
  CHECK(back["scene"]["light"]["rule"] == "--light position, built-in intensity");
  CHECK(back["gl_renderer"] == "llvmpipe (LLVM 15.0.6, 256 bits)");
  REQUIRE(back["stages"].size() == 2);
  CHECK(back["stages"][0]["name"] == "scene");
  CHECK(back["stages"][0]["clock"] == "cpu-wall");
  CHECK(back["stages"][0]["ms"].get<double>() >= 0.0);
  CHECK(back["stages"][1]["ms"] == 1.5);
  CHECK(back["total_ms"].get<double>() >= 1.5);
  CHECK(d.entries() == std::vector<std::string>{"r.json"});
}
