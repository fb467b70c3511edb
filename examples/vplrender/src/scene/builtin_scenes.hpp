// SPDX-License-Identifier: MIT
#pragma once
// The two procedural scenes the renderer carries, so it runs (and its tests pass) without any
// file. Geometry is listed in docs/renderer.md.
#include "scene/scene.hpp"

#include <string>

namespace vplrender {

// A closed Cornell-style room (red left wall, green right wall, white floor, ceiling, back and
// front walls), deeper than wide so a camera inside it near the front wall sees the whole back
// wall and both blocks; a point light just below the ceiling. Closed: every ray from inside hits
// a front face, so no light escapes.
scene make_cornell_scene();

// An open scene: a floor, a back wall, a side wall, an overhanging panel and two blocks, with the
// light in mid-air so that every hemisphere around it (along any axis) sees geometry, while many
// rays escape to the sky.
scene make_open_scene();

// "cornell" or "open"; throws input_error for any other name.
scene make_builtin_scene(const std::string& name);

bool is_builtin_scene_name(const std::string& name);

}  // namespace vplrender
