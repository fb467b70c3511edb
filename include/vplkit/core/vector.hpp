// SPDX-License-Identifier: MIT
#pragma once
// GLM is vplkit's vector vocabulary because GLM mirrors GLSL: vplkit::vec3<T> on the CPU reads
// like vec3 in the matching glsl/vplkit file.
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/geometric.hpp>

#include <cstdint>

namespace vplkit {

template <class T> using vec2 = glm::vec<2, T, glm::defaultp>;
template <class T> using vec3 = glm::vec<3, T, glm::defaultp>;
using ivec2 = glm::vec<2, int, glm::defaultp>;
using ivec3 = glm::vec<3, int, glm::defaultp>;
using uvec3 = glm::vec<3, std::uint32_t, glm::defaultp>;

}  // namespace vplkit
