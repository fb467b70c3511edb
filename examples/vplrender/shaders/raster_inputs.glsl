// SPDX-License-Identifier: MIT
// vplrender: the vertex inputs of both raster passes (gbuffer.vert, dprsm.vert), the layout that
// raster/gl_mesh.cpp uploads: position, shading normal, texcoord, and the plane of the (parent)
// triangle (unit geometric normal n, n . p), the same at all three corners.
#ifndef VPLRENDER_RASTER_INPUTS_GLSL
#define VPLRENDER_RASTER_INPUTS_GLSL

layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;
layout(location = 3) in vec4 a_plane;

#endif  // VPLRENDER_RASTER_INPUTS_GLSL
