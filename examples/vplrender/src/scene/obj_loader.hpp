// SPDX-License-Identifier: MIT
#pragma once
// OBJ/MTL scenes through tinyobjloader, after our own validation pass (obj_scan.hpp).
#include "scene/scene.hpp"

#include <string>

namespace vplrender {

// Loads triangles, materials and textures; the light and camera are left for the caller (see
// framing.hpp). Rules (docs/renderer.md has the full list):
// - polygons are triangulated by ear clipping in their own plane (triangulate.hpp);
// - missing normals (no vn on a corner, or a zero one): the flat normal of the face, following its
//   winding (counter-clockwise = front); given normals are normalised and kept as authored;
// - faces with no usemtl, or an unknown material, get the material "default" (Kd 0.8);
// - MTL files pass our own validation first (mtl_scan.hpp): malformed Kd/Ke/map_Kd is an error
//   naming the MTL file and line;
// - a missing MTL or texture is a warning and the material falls back to Kd (so is one that is not
//   a regular file: a FIFO or a device is never opened); a texture replaces Kd;
//   Kd outside [0,1] is clamped with a warning; map_Kd -s/-o options are applied to the texcoords;
// - triangles whose height is below 1e-9 of their longest edge are dropped with a warning.
// Throws input_error naming file and line for malformed input, and "file: ..." for an empty or
// wholly degenerate scene.
scene load_obj_scene(const std::string& path);

// The same, from text already in memory; `name` is used in messages (as the file name) and
// `base_dir` is where mtllib and map_Kd names are looked up.
scene load_obj_text(const std::string& text, const std::string& name, const std::string& base_dir);

}  // namespace vplrender
