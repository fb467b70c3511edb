// SPDX-License-Identifier: MIT
// vplrender: a surface's albedo in the raster passes' fragment shaders (gbuffer.frag, dprsm.frag).
// The host sets the uniforms per material range (raster/gl_raster.cpp): Kd, or the map_Kd texture
// when there is one.
#ifndef VPLRENDER_MATERIAL_GLSL
#define VPLRENDER_MATERIAL_GLSL

uniform vec3 u_kd;
uniform int u_textured;
uniform sampler2D u_texture;  // GL_SRGB8, GL_LINEAR, GL_REPEAT, no mipmaps: texture.cpp's lookup
vec3 vr_material_albedo(vec2 uv) { return u_textured != 0 ? texture(u_texture, uv).rgb : u_kd; }

#endif  // VPLRENDER_MATERIAL_GLSL
