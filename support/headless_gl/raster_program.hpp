// SPDX-License-Identifier: MIT
#pragma once
// Vertex + fragment programs for rasterisation passes, built the way compute.hpp builds compute
// programs: #includes resolved (include_resolver.hpp) against the pack root, the driver's logs
// mapped back to file:line, errors naming the program and the stage:
//   "<name>: vertex shader failed to compile:\n<file>:12(3): error: ..."
//   "<name>: program failed to link:\n<log>"
// The result is compute.hpp's `program` (RAII, use(), uniform_location()).
#include "compute.hpp"

#include <string>
#include <vector>

namespace vplkit::gl {

// `vertex_source` and `fragment_source` are whole shaders (#version first); their #includes are
// resolved against `include_dirs` (default: the pack root). `name` labels the program in errors and
// its two sources as name.vert / name.frag.
program raster_program(const std::string& name, const std::string& vertex_source,
                       const std::string& fragment_source,
                       const std::vector<std::string>& include_dirs = {});

// The program of a vertex and a fragment shader file, compiled once and kept for the life of the
// process, under cached_kernel's rules (compute.hpp): the key is the two paths and the preamble;
// the files are #version-free and get "#version 430 core" first (resolve_shader_file); their
// #includes resolve against the pack root, quoted ones first beside the file; the program belongs
// to the context current at its first use. Its name in errors is the files' common stem ("gbuffer"
// for gbuffer.vert + gbuffer.frag). Thread-safe. Throws gl_error when a file cannot be read, a
// stage does not compile or the program does not link.
const program& cached_raster_program(const std::string& vertex_path, const std::string& fragment_path,
                                     const std::string& preamble = {});

}  // namespace vplkit::gl
