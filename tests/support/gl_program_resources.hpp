// SPDX-License-Identifier: MIT
// What the GL driver says of a linked program's interface (glGetProgramResourceiv), for the tests
// that check a *_params.h struct against the block the GLSL side declares: each member's name and
// C++ offset, and one property of one named resource. Needs a current GL context.
#pragma once

#include <headless_gl/compute.hpp>

#include <catch2/catch.hpp>

#include <cstddef>
#include <string>

namespace vplkit_test {

// A struct member the GLSL block must have at the same byte offset.
struct block_member {
  std::string name;
  std::size_t offset;  // the C++ offsetof
};

// property of the resource `name` in `interface` of program `prog`; the resource must exist.
inline GLint resource_value(GLuint prog, GLenum interface, const std::string& name, GLenum property) {
  const GLuint index = glGetProgramResourceIndex(prog, interface, name.c_str());
  INFO(name);
  REQUIRE(index != GL_INVALID_INDEX);
  GLint value = -1;
  glGetProgramResourceiv(prog, interface, index, 1, &property, 1, nullptr, &value);
  vplkit::gl::check_gl("glGetProgramResourceiv");
  return value;
}

// How many resources of `interface` (GL_UNIFORM_BLOCK, GL_SHADER_STORAGE_BLOCK, ...) prog has.
inline GLint active_resources(GLuint prog, GLenum interface) {
  GLint n = -1;
  glGetProgramInterfaceiv(prog, interface, GL_ACTIVE_RESOURCES, &n);
  vplkit::gl::check_gl("glGetProgramInterfaceiv");
  return n;
}

}  // namespace vplkit_test

// block_member{"field", offsetof(type, field)}
#define VPLKIT_TEST_BLOCK_MEMBER(type, field) vplkit_test::block_member{#field, offsetof(type, field)}
