// SPDX-License-Identifier: MIT
#pragma once
// The scene model the renderer needs, and nothing more: triangles with normals, diffuse
// materials (a constant Kd or an 8-bit texture), one point light and a pinhole camera.
// Conventions: right-handed, +Y up (the OBJ habit), lengths in scene units, angles in degrees
// at the interface, light intensity in W/sr (RGB).
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace vplrender {

using vec2 = glm::vec2;
using vec3 = glm::vec3;

// 8-bit RGB texels, sRGB-encoded as authored. Row 0 is v = 0 (the bottom of the picture, as OBJ
// texture coordinates and glTexImage2D both expect), so a GPU upload needs no flip.
struct texture_rgb8 {
  std::string source;  // file it came from, for messages
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> texels;  // width * height * 3
};

struct material {
  std::string name;
  vec3 kd{0.8f};     // linear diffuse albedo in [0,1]; used where there is no texture
  int texture = -1;  // index into scene::textures, or -1; when set it replaces kd (docs/renderer.md)
  vec3 ke{0.0f};     // emitted radiance from the MTL; only used to place an automatic light
};

// Non-indexed on purpose: three corners, three shading normals (unit), three texcoords, one
// material. Normals point to the side the surface was authored to face.
struct triangle {
  std::array<vec3, 3> p;
  std::array<vec3, 3> n;
  std::array<vec2, 3> uv{};
  std::uint32_t material = 0;
};

struct point_light {
  vec3 position{0.0f};
  vec3 intensity{0.0f};  // I_s, W/sr per channel
};

struct camera {
  vec3 eye{0.0f, 0.0f, 1.0f};
  vec3 target{0.0f};
  vec3 up{0.0f, 1.0f, 0.0f};
  float vfov_deg = 45.0f;  // full vertical field of view
};

struct aabb {
  vec3 lo{0.0f};
  vec3 hi{0.0f};
  vec3 center() const { return 0.5f * (lo + hi); }
  vec3 extent() const { return hi - lo; }
  float diagonal() const;
};

struct scene {
  std::string name;  // "cornell", "open" or the OBJ path
  std::vector<triangle> triangles;
  std::vector<material> materials;
  std::vector<texture_rgb8> textures;
  point_light light;
  camera cam;
  std::vector<std::string> warnings;  // non-fatal problems met while building it
};

aabb bounds(const std::vector<triangle>& triangles);
inline aabb bounds(const scene& s) { return bounds(s.triangles); }

// Twice the area, as |(p1 - p0) x (p2 - p0)|, computed in double so slivers are judged fairly.
double triangle_double_area(const triangle& t);

// The geometric normal (unit), flipped to agree with the mean of the shading normals: the side the
// triangle was authored to face. Zero for a degenerate triangle.
vec3 facing_normal(const triangle& t);

// Throws input_error naming the first offence: no triangles, non-finite or non-unit data, a
// material index out of range, Kd outside [0,1], a texture of the wrong size, a zero-size or
// infinite bounding box.
void validate_geometry(const scene& s);

// validate_geometry, plus a non-finite or negative light and a degenerate camera.
void validate_scene(const scene& s);

// Throws input_error if the camera cannot form a frame (eye == target, up parallel to the view
// direction, fov outside (0, 180), non-finite values). `what` names the source ("--camera").
void validate_camera(const camera& c, const std::string& what);

}  // namespace vplrender
