// SPDX-License-Identifier: MIT
#include "raster/gpu_scene_shading.hpp"

#include "io/color.hpp"

#include <vplkit/core/float_bits.hpp>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace vplrender {

namespace {

// ray_scene.glsl's vr_triangle_shading.
struct triangle_shading {
  float n0[4], n1[4], n2[4];
  float uv01[4];
  float uv2[2];
  std::uint32_t material;
  std::uint32_t unused;
};
static_assert(sizeof(triangle_shading) == 80, "vr_triangle_shading is 80 bytes in std430");

std::size_t texel_words(const scene& s) {
  std::size_t n = 0;
  for (const texture_rgb8& t : s.textures) n += static_cast<std::size_t>(t.width) * static_cast<std::size_t>(t.height);
  return n;
}

std::size_t pool_words(const scene& s) { return gpu_shading_material_base + 8 * s.materials.size() + texel_words(s); }

}  // namespace

std::size_t scene_shading_bytes(const scene& s) {
  return sizeof(triangle_shading) * std::max<std::size_t>(s.triangles.size(), 1) + 4 * pool_words(s);
}

gpu_scene_shading upload_scene_shading(const scene& s) {
  gpu_scene_shading g;
  std::vector<triangle_shading> tris(std::max<std::size_t>(s.triangles.size(), 1), triangle_shading{});
  for (std::size_t i = 0; i < s.triangles.size(); ++i) {
    const triangle& t = s.triangles[i];
    triangle_shading& o = tris[i];
    float* n[3] = {o.n0, o.n1, o.n2};
    for (int c = 0; c < 3; ++c) {
      n[c][0] = t.n[c].x;
      n[c][1] = t.n[c].y;
      n[c][2] = t.n[c].z;
      n[c][3] = 0.0f;
    }
    o.uv01[0] = t.uv[0].x;
    o.uv01[1] = t.uv[0].y;
    o.uv01[2] = t.uv[1].x;
    o.uv01[3] = t.uv[1].y;
    o.uv2[0] = t.uv[2].x;
    o.uv2[1] = t.uv[2].y;
    o.material = t.material;
    o.unused = 0u;
  }
  g.triangles = vplkit::gl::buffer::from_vector(tris);

  // A storage block larger than the driver's limit would not bind: say so instead (the triangles
  // above are far smaller than any limit a GL 4.3 device has, 2^24 bytes and up).
  GLint64 limit = 0;
  glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &limit);
  const std::size_t words = pool_words(s);
  if (limit > 0 && 4 * words > static_cast<std::uint64_t>(limit)) {
    g.unavailable = "the scene's textures (" + std::to_string(texel_words(s)) + " texels, " +
                    std::to_string((4 * words) >> 20) + " MiB packed) exceed the GPU's largest storage buffer (" +
                    std::to_string(limit >> 20) + " MiB); use --backend cpu";
    g.pool = vplkit::gl::buffer::filled(4, 0);
    return g;
  }
  std::vector<std::uint32_t> pool(words, 0u);
  for (int i = 0; i < 256; ++i)
    pool[static_cast<std::size_t>(i)] = vplkit::float_bits(srgb_to_linear(static_cast<float>(i) / 255.0f));
  std::size_t texel_at = gpu_shading_material_base + 8 * s.materials.size();
  std::vector<std::size_t> first(s.textures.size());
  for (std::size_t k = 0; k < s.textures.size(); ++k) {
    const texture_rgb8& t = s.textures[k];
    first[k] = texel_at;
    const std::size_t n = static_cast<std::size_t>(t.width) * static_cast<std::size_t>(t.height);
    for (std::size_t i = 0; i < n; ++i)
      pool[texel_at + i] = std::uint32_t(t.texels[3 * i]) | std::uint32_t(t.texels[3 * i + 1]) << 8 |
                           std::uint32_t(t.texels[3 * i + 2]) << 16;
    texel_at += n;
  }
  for (std::size_t m = 0; m < s.materials.size(); ++m) {
    const material& mat = s.materials[m];
    std::uint32_t* rec = &pool[gpu_shading_material_base + 8 * m];
    rec[0] = vplkit::float_bits(mat.kd.x);
    rec[1] = vplkit::float_bits(mat.kd.y);
    rec[2] = vplkit::float_bits(mat.kd.z);
    if (mat.texture >= 0) {
      const std::size_t k = static_cast<std::size_t>(mat.texture);
      rec[3] = static_cast<std::uint32_t>(first[k]);
      rec[4] = static_cast<std::uint32_t>(s.textures[k].width);
      rec[5] = static_cast<std::uint32_t>(s.textures[k].height);
      rec[6] = 1u;
    }
  }
  g.pool = vplkit::gl::buffer::from_vector(pool);
  return g;
}

}  // namespace vplrender
