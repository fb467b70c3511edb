// SPDX-License-Identifier: MIT
#pragma once
// Our own pass over an OBJ file before tinyobjloader sees it. tinyobjloader 2.0.0rc10 is silent
// where the renderer must not be: a malformed number reads as 0, "nan" reads as 0, 1e39 becomes
// Inf, an out-of-range index only earns one warning that names the LAST line of the file (and a
// face using it is skipped or read out of bounds), a face with two vertices is dropped quietly.
// This scan rejects all of those with "file:line: message", and numbers lines exactly as
// tinyobjloader does (\n, \r\n and a lone \r all end a line), so both agree on line numbers.
#include <cstddef>
#include <string>
#include <vector>

namespace vplrender {

struct obj_scan_result {
  std::size_t vertices = 0, normals = 0, texcoords = 0;
  std::vector<std::size_t> face_lines;  // line of every face statement, in file order
  struct library {
    std::string name;
    std::size_t line;
  };
  std::vector<library> mtllibs;  // every name on every mtllib line
  std::vector<std::string> warnings;
  // The text to hand to tinyobjloader: the same lines (so the same numbers), each ending in '\n',
  // with trailing "# comments" cut (tinyobjloader fails a face line that has one) and every
  // statement we ignore blanked (so tinyobjloader never parses what we did not validate).
  std::string cleaned;
};

// Throws input_error("file:line: ...") on: NUL bytes, a backslash line continuation, a v/vn/vt
// with missing, extra, non-numeric, non-finite or out-of-float-range values, a face with fewer than
// three vertices, a malformed vertex reference, index 0, or an index (absolute or relative) that
// refers to no element. Unknown and unsupported statements (curves, surfaces, lines, points,
// tinyobjloader's vw/t) are ignored with one warning per keyword.
obj_scan_result scan_obj(const std::string& text, const std::string& filename);

}  // namespace vplrender
