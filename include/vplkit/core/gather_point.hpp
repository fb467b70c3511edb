#pragma once
// What builders and estimators know of the camera's visible points: a non-owning G-buffer view
// (the host renderer owns the image) and the result type of the host's ray-casting callable.
#include <vplkit/core/error.hpp>
#include <vplkit/core/vector.hpp>

#include <cmath>
#include <string>

namespace vplkit {

template <class T>
struct gather_point {
  vec3<T> position;
  vec3<T> normal;  // need not be unit length; zero means "no surface" (background pixel)
  vec3<T> albedo;  // diffuse reflectance rho_x
};

// Background pixels (zero or non-finite normal) are skipped by every builder and estimator.
template <class T>
inline bool gather_point_valid(const gather_point<T>& g) {
  const T n2 = glm::dot(g.normal, g.normal);
  return n2 > T(0) && std::isfinite(n2) && std::isfinite(g.position.x) &&
         std::isfinite(g.position.y) && std::isfinite(g.position.z);
}

// Row-major width x height image of gather points (index = y * width + x), as three arrays the
// way a G-buffer read back from the GPU is laid out.
template <class T>
struct gbuffer_view {
  int width = 0;
  int height = 0;
  const vec3<T>* position = nullptr;
  const vec3<T>* normal = nullptr;
  const vec3<T>* albedo = nullptr;

  int pixel_count() const { return width * height; }
  gather_point<T> at(int index) const { return gather_point<T>{position[index], normal[index], albedo[index]}; }
  gather_point<T> at(int x, int y) const { return at(y * width + x); }

  // Throws invalid_input for a bad size or null arrays. Non-finite entries are not an error:
  // such pixels are treated as background (gather_point_valid).
  void validate() const {
    if (width <= 0 || height <= 0 || width > (1 << 15) || height > (1 << 15))
      throw invalid_input("gbuffer_view: size " + std::to_string(width) + "x" + std::to_string(height) +
                          " is not in [1, 32768]^2");
    if (position == nullptr || normal == nullptr || albedo == nullptr)
      throw invalid_input("gbuffer_view: null position, normal or albedo array");
  }
};

// What a host's ray-casting callable returns: the first surface point along a ray, if any.
template <class T>
struct ray_hit {
  bool hit = false;
  vec3<T> position{T(0)};
};

}  // namespace vplkit
