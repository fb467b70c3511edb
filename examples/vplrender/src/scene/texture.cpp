// SPDX-License-Identifier: MIT
#include "scene/texture.hpp"

#include "io/color.hpp"
#include "io/errors.hpp"
#include "io/text_file.hpp"

#include <stb_image.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <memory>

namespace vplrender {

texture_rgb8 load_texture(const std::string& path) {
  // Our reader, not stbi_load's fopen: a FIFO or a device is refused instead of read (or waited
  // on) forever.
  const std::string bytes = read_file_bytes(path);
  if (bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw input_error(path + ": cannot load texture (file larger than 2 GiB)");
  int w = 0, h = 0, channels = 0;
  // The _thread variant keeps the flip setting local; we flip by hand anyway for clarity.
  stbi_set_flip_vertically_on_load_thread(0);
  std::unique_ptr<stbi_uc, void (*)(void*)> data(
      stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()), static_cast<int>(bytes.size()), &w, &h,
                            &channels, 3),
      stbi_image_free);
  if (!data) {
    const char* why = stbi_failure_reason();
    throw input_error(path + ": cannot load texture (" + (why ? why : "unknown reason") + ")");
  }
  if (w <= 0 || h <= 0 || w > 16384 || h > 16384)
    throw input_error(path + ": texture size " + std::to_string(w) + "x" + std::to_string(h) +
                      " is outside 1..16384");
  texture_rgb8 t;
  t.source = path;
  t.width = w;
  t.height = h;
  const std::size_t row = static_cast<std::size_t>(w) * 3u;
  t.texels.resize(row * static_cast<std::size_t>(h));
  for (int y = 0; y < h; ++y)
    std::memcpy(t.texels.data() + row * static_cast<std::size_t>(h - 1 - y), data.get() + row * static_cast<std::size_t>(y), row);
  return t;
}

namespace {

vec3 texel(const texture_rgb8& t, int x, int y) {
  const std::size_t i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(t.width) + static_cast<std::size_t>(x)) * 3u;
  return vec3(srgb_to_linear(t.texels[i] / 255.0f), srgb_to_linear(t.texels[i + 1] / 255.0f),
              srgb_to_linear(t.texels[i + 2] / 255.0f));
}

int wrap(int i, int n) {
  const int m = i % n;
  return m < 0 ? m + n : m;
}

}  // namespace

vec3 sample_texture(const texture_rgb8& tex, vec2 uv) {
  if (tex.width <= 0 || tex.height <= 0) return vec3(0.0f);
  // GL_LINEAR: texel centres at (i + 0.5) / size.
  const float x = uv.x * static_cast<float>(tex.width) - 0.5f;
  const float y = uv.y * static_cast<float>(tex.height) - 0.5f;
  const float fx = std::floor(x), fy = std::floor(y);
  const float ax = x - fx, ay = y - fy;
  // Huge uv would overflow int; reduce the integer part modulo the size in double first.
  const int x0 = wrap(static_cast<int>(std::fmod(static_cast<double>(fx), tex.width)), tex.width);
  const int y0 = wrap(static_cast<int>(std::fmod(static_cast<double>(fy), tex.height)), tex.height);
  const int x1 = wrap(x0 + 1, tex.width), y1 = wrap(y0 + 1, tex.height);
  const vec3 a = texel(tex, x0, y0) * (1.0f - ax) + texel(tex, x1, y0) * ax;
  const vec3 b = texel(tex, x0, y1) * (1.0f - ax) + texel(tex, x1, y1) * ax;
  return a * (1.0f - ay) + b * ay;
}

vec3 albedo(const scene& s, const material& m, vec2 uv) {
  if (m.texture >= 0) return sample_texture(s.textures[static_cast<std::size_t>(m.texture)], uv);
  return m.kd;
}

}  // namespace vplrender
