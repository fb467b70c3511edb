// SPDX-License-Identifier: MIT
#pragma once
// Diffuse textures: loading (stb_image, any format it reads, reduced to 8-bit RGB) and the CPU
// lookup that mirrors the GPU one (GL_SRGB8, GL_LINEAR, GL_REPEAT, no mipmaps).
#include "scene/scene.hpp"

#include <string>

namespace vplrender {

// Throws input_error ("file: reason") if the file is missing, unreadable, not an image, or
// larger than 16384 texels on a side. Rows are flipped so row 0 is v = 0.
texture_rgb8 load_texture(const std::string& path);

// Bilinear, repeat-wrapped lookup of the linear albedo at uv (v up). Texels are decoded from sRGB
// before filtering, as the GPU does for an sRGB texture.
vec3 sample_texture(const texture_rgb8& tex, vec2 uv);

// Albedo of material m at uv: the texture if it has one, else Kd.
vec3 albedo(const scene& s, const material& m, vec2 uv);

}  // namespace vplrender
