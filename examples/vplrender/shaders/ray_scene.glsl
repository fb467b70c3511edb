// SPDX-License-Identifier: MIT
// vplrender: shading a BVH hit on the GPU as render/cpu/ray_scene.cpp shades an Embree hit, float
// for float: the interpolated corner normal (ray_scene::shading_normal) and the material's albedo
// at the interpolated uv (ray_scene::albedo_at, with scene/texture.cpp's sample_texture: bilinear,
// GL_REPEAT wrap, texels decoded from sRGB before filtering). The buffers are
// raster/gpu_scene_shading.hpp's (its header states the layouts). `precise` keeps the compiler
// from fusing the CPU's separately rounded products and sums.
//
// ACCESSORS (the including kernel defines them; it chooses the buffers and bindings):
//   vr_triangle_shading vr_load_triangle_shading(uint triangle);  // by the scene's triangle index
//   uint vr_load_shading_word(uint index);                        // the pool
#ifndef VPLRENDER_RAY_SCENE_GLSL
#define VPLRENDER_RAY_SCENE_GLSL

#include "vplkit/visibility/bvh_traverse.glsl"

struct vr_triangle_shading {
  vec4 n0;  // corner normals (w unused)
  vec4 n1;
  vec4 n2;
  vec4 uv01;  // uv of corners 0 (xy) and 1 (zw)
  vec2 uv2;
  uint material;
  uint unused;
};

vr_triangle_shading vr_load_triangle_shading(uint triangle);
uint vr_load_shading_word(uint index);

const uint vr_shading_material_base = 256u;  // gpu_shading_material_base

struct vr_texture {
  uint first;  // word of texel (0, 0)
  int width;
  int height;
};

// scene/texture.cpp's texel(): srgb_to_linear(byte / 255.0f) per channel, read from the table the
// host filled with that very function.
vec3 vr_texel(vr_texture t, int x, int y) {
  uint w = vr_load_shading_word(t.first + uint(y) * uint(t.width) + uint(x));
  return vec3(uintBitsToFloat(vr_load_shading_word(w & 0xFFu)),
              uintBitsToFloat(vr_load_shading_word((w >> 8u) & 0xFFu)),
              uintBitsToFloat(vr_load_shading_word((w >> 16u) & 0xFFu)));
}

// i mod n in [0, n) (GLSL's % is undefined for negative operands).
int vr_wrap(int i, int n) {
  return i >= 0 ? i % n : (n - 1) - ((-(i + 1)) % n);
}

// wrap(int(fmod(double(f), n)), n) of texture.cpp for an integral float f: f mod n, exactly. Below
// 2^24 f converts to int exactly; above, f = m 2^e with an integer m of 24 bits, and m 2^e mod n
// is m mod n doubled e times mod n (e <= 104 iterations, only for uv beyond 2^24 / size).
int vr_wrap_integral(float f, int n) {
  if (abs(f) < 16777216.0) return vr_wrap(int(f), n);
  if (!vplkit_bvh_isfinite(f)) return 0;
  int e = 0;
  float m = frexp(f, e);  // f = m 2^e, 0.5 <= |m| < 1
  int r = vr_wrap(int(m * 16777216.0), n);
  for (int k = 24; k < e; ++k) r = (2 * r) % n;
  return r;
}

// scene/texture.cpp's sample_texture.
vec3 vr_sample_texture(vr_texture tex, vec2 uv) {
  if (tex.width <= 0 || tex.height <= 0) return vec3(0.0);
  // GL_LINEAR: texel centres at (i + 0.5) / size.
  precise float x = uv.x * float(tex.width) - 0.5;
  precise float y = uv.y * float(tex.height) - 0.5;
  float fx = floor(x), fy = floor(y);
  precise float ax = x - fx;
  precise float ay = y - fy;
  int x0 = vr_wrap_integral(fx, tex.width);
  int y0 = vr_wrap_integral(fy, tex.height);
  int x1 = vr_wrap(x0 + 1, tex.width), y1 = vr_wrap(y0 + 1, tex.height);
  precise vec3 a = vr_texel(tex, x0, y0) * (1.0 - ax) + vr_texel(tex, x1, y0) * ax;
  precise vec3 b = vr_texel(tex, x0, y1) * (1.0 - ax) + vr_texel(tex, x1, y1) * ax;
  precise vec3 r = a * (1.0 - ay) + b * ay;
  return r;
}

// scene/texture.cpp's albedo(): the texture if material m has one, else Kd.
vec3 vr_material_albedo(uint m, vec2 uv) {
  uint rec = vr_shading_material_base + 8u * m;
  if (vr_load_shading_word(rec + 6u) != 0u)
    return vr_sample_texture(vr_texture(vr_load_shading_word(rec + 3u), int(vr_load_shading_word(rec + 4u)),
                                        int(vr_load_shading_word(rec + 5u))),
                             uv);
  return vec3(uintBitsToFloat(vr_load_shading_word(rec)), uintBitsToFloat(vr_load_shading_word(rec + 1u)),
              uintBitsToFloat(vr_load_shading_word(rec + 2u)));
}

// ray_scene::shading_normal: corner normals interpolated, unit; the geometric normal where that
// has no length.
vec3 vr_shading_normal(vplkit_bvh_hit h) {
  vr_triangle_shading tri = vr_load_triangle_shading(h.triangle);
  precise vec3 n = (1.0 - h.u - h.v) * tri.n0.xyz + h.u * tri.n1.xyz + h.v * tri.n2.xyz;
  precise float len = sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
  return len > 0.0 && vplkit_bvh_isfinite(len) ? n / len : h.normal;
}

// ray_scene::albedo_at: the material's albedo at the interpolated uv.
vec3 vr_albedo_at(vplkit_bvh_hit h) {
  vr_triangle_shading tri = vr_load_triangle_shading(h.triangle);
  precise vec2 uv = (1.0 - h.u - h.v) * tri.uv01.xy + h.u * tri.uv01.zw + h.v * tri.uv2;
  return vr_material_albedo(tri.material, uv);
}

#endif  // VPLRENDER_RAY_SCENE_GLSL
