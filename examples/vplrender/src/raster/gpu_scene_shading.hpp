// SPDX-License-Identifier: MIT
#pragma once
// What the GPU's --method exact needs to shade a hit the way the CPU's ray_scene does
// (ray_scene::shading_normal, ray_scene::albedo_at): the scene's per-triangle corner normals, uvs
// and material, and every material's Kd and texture, uploaded once per frame beside the BVH. The
// kernel reads them through examples/vplrender/shaders/ray_scene.glsl, which repeats the CPU's
// lookup (scene/texture.cpp: bilinear, repeat-wrapped, texels decoded from sRGB before filtering)
// float for float. The textures are packed into one storage buffer rather than bound as samplers:
// indexing an array of samplers by a per-invocation material is not portable in GL 4.3, and a
// sampler's filtering would not be the CPU's to rounding.
//
// Layouts (std430; ray_scene.glsl declares the same):
//   triangles: vr_triangle_shading { vec4 n0, n1, n2; vec4 uv01; vec2 uv2; uint material; uint unused; }
//              (80 bytes, indexed by the scene's triangle index, the BVH's triangle id)
//   pool (uint words): [0, 256) the sRGB decode table, srgb_to_linear(i / 255.0f) as float bits
//              (the CPU's decode of byte i); at material_base + 8 m material m: kd.xyz as float bits,
//              its texture's first texel word, width, height, 1 if it has a texture (else all four
//              0), 0; then the textures' texels, one word each, r | g << 8 | b << 16, row 0 = v = 0
//              as on the CPU.
#include "scene/scene.hpp"

#include <headless_gl/compute.hpp>

#include <cstddef>
#include <string>

namespace vplrender {

struct gpu_scene_shading {
  vplkit::gl::buffer triangles;  // at least one entry (Mesa binds no empty buffer)
  vplkit::gl::buffer pool;
  // Empty when uploaded; else why it could not be (the pool is larger than the GPU's largest
  // storage buffer): --method exact on the GPU then refuses with this text.
  std::string unavailable;
  std::size_t size_bytes() const { return triangles.size_bytes() + pool.size_bytes(); }
};

// Word of the pool where the materials start (after the decode table).
constexpr unsigned gpu_shading_material_base = 256;

// Bytes upload_scene_shading asks for.
std::size_t scene_shading_bytes(const scene& s);

// Packs and uploads (needs the current GL context).
gpu_scene_shading upload_scene_shading(const scene& s);

}  // namespace vplrender
