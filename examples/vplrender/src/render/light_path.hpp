// SPDX-License-Identifier: MIT
#pragma once
// Where the light is in frame k of `vplrender --frames N` (docs/renderer.md, "Frames"): a
// horizontal circle (+Y up) through the scene's light position p0, radius r = 0.05 of the scene
// box's diagonal, centre p0 - (r, 0, 0), walked once over the N frames:
//   light(k) = p0 + r (cos(2 pi k / N) - 1, 0, sin(2 pi k / N)),   k = 0 .. N - 1,
// evaluated in double and rounded to float. Frame 0 is the scene's own light, so it equals the
// single render; every position is what `--light X,Y,Z` would give (the same on both backends).
#include "scene/scene.hpp"

#include <string>

namespace vplrender {

struct light_path {
  vec3 start{0.0f};  // p0
  float radius = 0.0f;
  int count = 1;

  vec3 at(int k) const;  // light(k); k outside 0 .. count - 1 wraps around the circle
  // The rule above in words, with its numbers (for the JSON report).
  std::string rule() const;
};

// The path of s's light over `count` frames (count >= 1).
light_path make_light_path(const scene& s, int count);

}  // namespace vplrender
