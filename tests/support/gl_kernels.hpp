// SPDX-License-Identifier: MIT
#pragma once
// Driving the GLSL pack's compute kernels (glsl/vplkit/**/*.comp) from the GPU tests and the GPU
// benchmarks (not part of the library): a program cache, the buffers a kernel binds -- shader
// storage and uniform blocks (the kernel parameter headers *_params.h compile as C++, so a block
// is uploaded as the very struct the kernel reads) -- and dispatches that respect GL's limits.
// Everything here needs a current context (support/headless_gl/context.hpp).
#include <headless_gl/compute.hpp>

#include <std430_types.hpp>

#include <algorithm>
#include <array>
#include <cstddef>
#include <initializer_list>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

namespace vplkit_test {

// The kernel `file` (relative to the pack root, e.g. "vplkit/builders/gbg_finish.comp") with
// `defines` after its #version line, compiled once per (file, defines) and kept with the context.
inline const vplkit::gl::program& pack_kernel(const std::string& file, const std::string& defines = "") {
  static auto* cache = new std::map<std::string, vplkit::gl::program>();
  const std::string key = file + '\x01' + defines;
  auto it = cache->find(key);
  if (it == cache->end()) {
    it = cache
             ->emplace(key, vplkit::gl::program::compute_with_includes(
                                "#version 430\n#include \"" + file + "\"\n", file,
                                {vplkit::gl::glsl_source_dir()}, defines))
             .first;
  }
  return it->second;
}

// A uniform block's contents: the kernel's parameter struct, as it is.
template <class P>
vplkit::gl::buffer uniform_buffer(const P& block) {
  static_assert(std::is_trivially_copyable<P>::value, "a uniform block must be trivially copyable");
  return vplkit::gl::buffer::from_bytes(&block, sizeof block);
}

// One buffer at one binding point of a dispatch.
struct binding {
  GLenum target;
  GLuint index;
  const vplkit::gl::buffer* buffer;
};
inline binding storage_at(GLuint index, const vplkit::gl::buffer& b) {
  return {GL_SHADER_STORAGE_BUFFER, index, &b};
}
inline binding uniform_at(GLuint index, const vplkit::gl::buffer& b) { return {GL_UNIFORM_BUFFER, index, &b}; }

inline void bind(std::initializer_list<binding> bindings) {
  for (const binding& b : bindings) glBindBufferBase(b.target, b.index, b.buffer->id());
  vplkit::gl::check_gl("glBindBufferBase");
}

// Binds every buffer, then dispatches `groups` work groups (with a memory barrier after it).
inline void dispatch(const vplkit::gl::program& p, std::array<GLuint, 3> groups,
                     std::initializer_list<binding> bindings) {
  bind(bindings);
  vplkit::gl::dispatch(p, groups[0], groups[1], groups[2]);
}

// Work groups for `count` items of `local_size` each, at most 65535 along x (the smallest
// GL_MAX_COMPUTE_WORK_GROUP_COUNT a GL 4.3 device may have) and the rest folded into y: the kernel
// numbers its group gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x and skips groups
// past its count (voxelize.comp: one group per triangle).
inline std::array<GLuint, 3> spread_groups(std::size_t count, std::size_t local_size = 1) {
  const std::size_t groups = (count + local_size - 1) / local_size;  // 0 items: an empty dispatch
  return {GLuint(std::min<std::size_t>(groups, 65535)), GLuint((groups + 65534) / 65535), 1};
}

}  // namespace vplkit_test
