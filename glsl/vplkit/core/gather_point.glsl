// vplkit GLSL pack: what builders and estimators know of the camera's visible points; mirrors
// include/vplkit/core/gather_point.hpp (T = float): vplkit_gather_point, vplkit_gather_point_valid
// (decided as the C++ decides it), vplkit_gbuffer_view (the sizes; the arrays are the accessor),
// vplkit_ray_hit. ACCESSOR, declared here and referenced only by builders/gather_subset.glsl:
//   vplkit_gather_point vplkit_load_gather_point(int pixel);   // pixel = y * width + x
// docs/glsl/core.md.
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
