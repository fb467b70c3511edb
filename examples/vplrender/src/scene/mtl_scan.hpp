// SPDX-License-Identifier: MIT
#pragma once
// Our own pass over an MTL file before tinyobjloader sees it (the MTL side of obj_scan.hpp).
// tinyobjloader 2.0.0rc10 reads "Kd abc" and "Kd nan nan nan" as 0 (a black material, no word
// said), "Kd 1 2" as (1, 2, 0), and "map_Kd -s 2 tex.png" as a scale of (2, 1, 1) with no file
// name. This scan rejects those with "file:line: message" and hands tinyobjloader a cleaned text
// in which every statement the renderer uses is in the one form tinyobjloader reads right.
#include <string>
#include <vector>

namespace vplrender {

struct mtl_scan_result {
  std::vector<std::string> warnings;
  // The same lines (so the same numbers), each ending in '\n': newmtl as written (less a trailing
  // comment); Kd and Ke with three numbers ("Kd 0.5" means grey, as the MTL format says);
  // map_Kd with only its -s and -o options, three numbers each, then the file name; every other
  // statement blanked (the renderer is diffuse-only, and tinyobjloader never parses what we did
  // not validate).
  std::string cleaned;
};

// Throws input_error("file:line: ...") on: NUL bytes, a '\' line continuation, newmtl without a
// name, Kd/Ke with other than 1 or 3 numbers, a non-number, a value that is no finite float, the
// unsupported "spectral"/"xyz" colour forms, map_Kd without a file name or with a malformed
// option. Statements that need a material before the first newmtl, and unknown statements, are
// ignored with one warning each; the other standard statements (Ka, Ks, Ns, d, illum, bump
// maps, ...) are ignored silently.
mtl_scan_result scan_mtl(const std::string& text, const std::string& filename);

}  // namespace vplrender
