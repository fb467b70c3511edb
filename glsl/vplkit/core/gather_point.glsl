// vplkit GLSL pack: what builders and estimators know of the camera's visible points; mirrors
// include/vplkit/core/gather_point.hpp (T = float).
//
//   gather_point<float>{position, normal, albedo} <-> vplkit_gather_point (normal any length; zero
//                                                     means background)
//   gather_point_valid(g)                          <-> vplkit_gather_point_valid(g)
//   gbuffer_view<float>{width, height, arrays}     <-> vplkit_gbuffer_view{width, height} + accessor
//   view.at(index), view.at(x, y)                  <-> vplkit_load_gather_point(index),
//                                                      vplkit_load_gather_point(y * width + x)
//   ray_hit<float>{hit, position}                  <-> vplkit_ray_hit
// gbuffer_view::validate() is host-side (it throws): upload only validated G-buffers.
//
// ACCESSOR, declared here and referenced only by builders/gather_subset.glsl (the estimators take
// one gather point by value). Mesa (22.3, measured) wants a definition for every function
// referenced anywhere in the shader, called or not, so a shader defines it exactly when it
// includes a file that references it:
//   vplkit_gather_point vplkit_load_gather_point(int pixel);
//     the G-buffer entry of flat pixel index pixel = y * width + x (row-major), e.g. from three
//     vec4 SSBOs (std430: a vec3 array element has a 16-byte stride).
//
// Validity, decided as the C++ decides it: n2 = dot(n, n) written out in glm's order and `precise`
// (so an overflow to +inf or an underflow to 0 happens where it happens in C++ float), n2 > 0,
// and n2 and the position finite, tested on the bits (GLSL compilers may assume no NaN/Inf in
// comparisons). A GPU that flushes denormals reads a normal with n2 < 2^-126 (components below
// about 1e-19) as zero, i.e. as background, where llvmpipe and the CPU still see a surface.
#ifndef VPLKIT_CORE_GATHER_POINT_GLSL
#define VPLKIT_CORE_GATHER_POINT_GLSL

struct vplkit_gather_point {
  vec3 position;
  vec3 normal;  // need not be unit length; zero means "no surface" (background pixel)
  vec3 albedo;  // diffuse reflectance rho_x
};

// What a ray cast returns: the first surface point along a ray, if any.
struct vplkit_ray_hit {
  bool hit;
  vec3 position;
};

// The C++ view's arrays are the accessor; the sizes remain.
struct vplkit_gbuffer_view {
  int width;
  int height;
};

vplkit_gather_point vplkit_load_gather_point(int pixel);

// Finite (not NaN, not +-inf), decided on the bits.
bool vplkit_gather_point_isfinite(float x) {
  return (floatBitsToUint(x) & 0x7F800000u) != 0x7F800000u;
}

// Background pixels (zero or non-finite normal, non-finite position) are skipped by every builder
// and estimator.
bool vplkit_gather_point_valid(vplkit_gather_point g) {
  precise float n2 = g.normal.x * g.normal.x + g.normal.y * g.normal.y + g.normal.z * g.normal.z;
  return n2 > 0.0 && vplkit_gather_point_isfinite(n2) && vplkit_gather_point_isfinite(g.position.x) &&
         vplkit_gather_point_isfinite(g.position.y) && vplkit_gather_point_isfinite(g.position.z);
}

int vplkit_gbuffer_view_pixel_count(vplkit_gbuffer_view v) {
  return v.width * v.height;
}

#endif  // VPLKIT_CORE_GATHER_POINT_GLSL
