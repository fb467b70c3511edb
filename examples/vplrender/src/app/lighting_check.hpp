// SPDX-License-Identifier: MIT
#pragma once
// After a render: warnings for an image that shows nothing lit, each saying what to try. The facts
// come from the frame (render/lighting_facts.hpp).
#include "cli/options.hpp"
#include "cli/scene_setup.hpp"
#include "render/lighting_facts.hpp"

#include <string>
#include <vector>

namespace vplrender {

// One warning per problem (none for a healthy frame). The hints follow how the camera and the
// light were chosen (prepared_scene's rules): an OBJ's automatic camera, an automatic light, flags.
std::vector<std::string> lighting_warnings(const prepared_scene& p, const options& o, const lighting_facts& f);

}  // namespace vplrender
