// SPDX-License-Identifier: MIT
// The common ground of the kernels' parameter headers (<kernel>_params.h, docs/glsl.md "Kernel
// parameters"): one struct definition compiles as GLSL, where it is the type of the kernel's
// std140 uniform block, and as C++, where the host fills it and uploads its bytes. On the C++ side
// this header supplies the GLSL type names in namespace vplkit::gpu; every struct spells its
// padding out and checks its size with static_assert, so both layouts agree member for member.
// Every kernel's default bindings give each resource, storage buffers and the uniform block alike,
// its own number: a Vulkan descriptor set holds one descriptor per binding, so only distinct numbers
// form a valid set 0 (OpenGL keeps uniform-block and storage-buffer binding points apart, and would
// accept a shared number). C++ reaches these headers through the vplkit::vplkit target (the pack
// root is on its include path): #include <vplkit/builders/gbg_accumulate_params.h>.
#ifndef VPLKIT_CORE_PARAMS_H
#define VPLKIT_CORE_PARAMS_H

#ifdef __cplusplus
#include <glm/vec4.hpp>

#include <cstdint>

namespace vplkit::gpu {
using uint = std::uint32_t;
using vec4 = glm::vec4;
using ivec4 = glm::ivec4;
using uvec4 = glm::uvec4;
static_assert(sizeof(vec4) == 16 && sizeof(ivec4) == 16 && sizeof(uvec4) == 16);
}  // namespace vplkit::gpu
#endif

#endif  // VPLKIT_CORE_PARAMS_H
