// SPDX-License-Identifier: MIT
#include "raster_program.hpp"

#include <filesystem>
#include <map>
#include <mutex>
#include <tuple>
#include <utility>

namespace vplkit::gl {

namespace {

program link_stages(const std::string& name, const glsl::resolved_source& vertex,
                    const glsl::resolved_source& fragment) {
  const GLuint v = compile_shader(GL_VERTEX_SHADER, vertex.text, name + ": vertex shader", &vertex);
  GLuint f = 0;
  try {
    f = compile_shader(GL_FRAGMENT_SHADER, fragment.text, name + ": fragment shader", &fragment);
  } catch (...) {
    glDeleteShader(v);
    throw;
  }
  // A link log names no source strings that one table could map: it is left as the driver wrote it.
  program p = program::link({v, f}, name + ": program");
  check_gl(("building raster program " + name).c_str());
  return p;
}

}  // namespace

program raster_program(const std::string& name, const std::string& vertex_source,
                       const std::string& fragment_source, const std::vector<std::string>& include_dirs) {
  std::vector<std::string> dirs = include_dirs;
  if (dirs.empty()) dirs.push_back(glsl_source_dir());
  return link_stages(name, glsl::resolve_includes(vertex_source, name + ".vert", dirs),
                     glsl::resolve_includes(fragment_source, name + ".frag", dirs));
}

const program& cached_raster_program(const std::string& vertex_path, const std::string& fragment_path,
                                     const std::string& preamble) {
  static std::mutex mutex;
  static std::map<std::tuple<std::string, std::string, std::string>, program> cache;
  const std::lock_guard<std::mutex> lock(mutex);
  const auto key = std::make_tuple(vertex_path, fragment_path, preamble);
  const auto it = cache.find(key);
  if (it != cache.end()) return it->second;
  const std::string vertex_stem = std::filesystem::path(vertex_path).stem().string();
  const std::string fragment_stem = std::filesystem::path(fragment_path).stem().string();
  const std::string name = vertex_stem == fragment_stem ? vertex_stem : vertex_stem + "+" + fragment_stem;
  const std::string version = "#version 430 core\n";
  program p = link_stages(name, resolve_shader_file(vertex_path, version, preamble),
                          resolve_shader_file(fragment_path, version, preamble));
  return cache.emplace(key, std::move(p)).first->second;
}

}  // namespace vplkit::gl
