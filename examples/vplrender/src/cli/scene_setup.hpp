// SPDX-License-Identifier: MIT
#pragma once
// From options to a ready scene: build or load it, frame it, light it, apply --camera/--light,
// validate it, and check the light's position.
#include "cli/options.hpp"
#include "scene/scene.hpp"

#include <string>

namespace vplrender {

struct prepared_scene {
  scene s;
  std::string camera_rule;  // "built-in", "automatic: ...", "--camera"
  std::string light_rule;
  bool light_outside_bounds = false;  // well-defined: see docs/renderer.md
};

// Throws input_error for a bad scene file or a light that lies inside a solid or on a surface
// (the message names --light when the position came from it), usage_error never.
prepared_scene prepare_scene(const options& o);

// Light position check shared by prepare_scene and the tests. `who` names the source in messages.
void check_light_position(const scene& s, const std::string& who);

// A few lines for stdout: scene, geometry, materials, camera, light, parameters.
std::string describe(const prepared_scene& p, const options& o);

}  // namespace vplrender
