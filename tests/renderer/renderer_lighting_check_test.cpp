// SPDX-License-Identifier: MIT
// Warnings for a frame that shows nothing lit (app/lighting_check.hpp): which one, and that each
// says what to try for how the camera and the light were chosen.
#include "app/lighting_check.hpp"

#include <catch2/catch.hpp>

#include <string>

using namespace vplrender;

namespace {
prepared_scene obj_scene(const std::string& camera_rule, const std::string& light_rule) {
  prepared_scene p;
  p.s.light.position = vec3(0.5f, 0.75f, 0.5f);
  p.camera_rule = camera_rule;
  p.light_rule = light_rule;
  return p;
}
lighting_facts facts(std::size_t visible, std::size_t lit, bool black) {
  lighting_facts f;
  f.pixels = 100;
  f.visible_pixels = visible;
  f.directly_lit_pixels = lit;
  f.image_black = black;
  return f;
}
bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }
}  // namespace

TEST_CASE("a healthy frame gets no lighting warning", "[renderer][lighting]") {
  const options o;
  CHECK(lighting_warnings(obj_scene("automatic: x", "automatic: y"), o, facts(80, 30, false)).empty());
}

TEST_CASE("no geometry in view: the image is black, try --camera", "[renderer][lighting]") {
  const auto w = lighting_warnings(obj_scene("--camera", "built-in"), options{}, facts(0, 0, true));
  REQUIRE(w.size() == 1);
  CHECK(contains(w[0], "the image is black: the camera sees no geometry"));
  CHECK(contains(w[0], "try --camera"));
}

TEST_CASE("nothing lit under an OBJ's automatic camera names the automatic camera and the light", "[renderer][lighting]") {
  const auto w = lighting_warnings(
      obj_scene("automatic: frames the bounding sphere from +Z", "automatic: free point"), options{}, facts(64, 0, true));
  REQUIRE(w.size() == 1);
  CHECK(contains(w[0], "the camera sees nothing lit: none of the 64 pixels"));
  CHECK(contains(w[0], "and the image is black"));
  CHECK(contains(w[0], "the automatic camera frames the bounding sphere from +Z"));
  CHECK(contains(w[0], "--light X,Y,Z to move the light (now at (0.5, 0.75, 0.5), automatic: free point)"));
}

TEST_CASE("nothing lit under --camera: no word about the automatic camera", "[renderer][lighting]") {
  // Indirect light may still show (a lit wall out of view): the image need not be black.
  const auto w = lighting_warnings(obj_scene("--camera", "--light"), options{}, facts(64, 0, false));
  REQUIRE(w.size() == 1);
  CHECK(contains(w[0], "the camera sees nothing lit"));
  CHECK_FALSE(contains(w[0], "image is black"));
  CHECK_FALSE(contains(w[0], "automatic camera"));
  CHECK(contains(w[0], "--camera EX,EY,EZ,TX,TY,TZ,UX,UY,UZ,FOV to look at surfaces the light reaches"));
}

TEST_CASE("lit surfaces but a black indirect-only image suggests --direct", "[renderer][lighting]") {
  options o;
  auto w = lighting_warnings(obj_scene("built-in", "built-in"), o, facts(64, 10, true));
  REQUIRE(w.size() == 1);
  CHECK(contains(w[0], "10 of 64 visible pixels are lit directly"));
  CHECK(contains(w[0], "add --direct"));
  o.direct = true;
  w = lighting_warnings(obj_scene("built-in", "built-in"), o, facts(64, 10, true));
  REQUIRE(w.size() == 1);
  CHECK_FALSE(contains(w[0], "add --direct"));
}

TEST_CASE("image_is_black: any non-zero value is light", "[renderer][lighting]") {
  image_rgb img(3, 2);
  CHECK(image_is_black(img));
  img.at(2, 1)[1] = 1e-30f;
  CHECK_FALSE(image_is_black(img));
}
