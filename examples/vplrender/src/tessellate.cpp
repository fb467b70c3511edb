#include "tessellate.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace vplrender {

double tessellation_angle_for_resolution(int R) { return std::sqrt(2.0 / static_cast<double>(R > 0 ? R : 1)); }

namespace {

// Angle between two directions from the light, by atan2 (accurate for small and large angles).
double angle_between(const glm::dvec3& a, const glm::dvec3& b) {
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

void corner(double b0, double b1, double b2, const triangle& parent, int slot, triangle& out) {
  const glm::dvec3 p = b0 * glm::dvec3(parent.p[0]) + b1 * glm::dvec3(parent.p[1]) + b2 * glm::dvec3(parent.p[2]);
  glm::dvec3 n = b0 * glm::dvec3(parent.n[0]) + b1 * glm::dvec3(parent.n[1]) + b2 * glm::dvec3(parent.n[2]);
  const double ln = glm::length(n);
  n = ln > 0.0 ? n / ln : glm::dvec3(parent.n[0]);
  const glm::dvec2 uv = b0 * glm::dvec2(parent.uv[0]) + b1 * glm::dvec2(parent.uv[1]) + b2 * glm::dvec2(parent.uv[2]);
  out.p[static_cast<std::size_t>(slot)] = vec3(p);
  out.n[static_cast<std::size_t>(slot)] = vec3(n);
  out.uv[static_cast<std::size_t>(slot)] = vec2(uv);
}

}  // namespace

std::vector<triangle> tessellate_for_light(const std::vector<triangle>& tris, vec3 light,
                                           const tessellation_params& params, tessellation_stats* stats) {
  std::vector<triangle> out;
  tessellation_stats st;
  st.input = tris.size();
  const glm::dvec3 c(light);
  for (const triangle& t : tris) {
    int n = 1;
    if (params.max_angle > 0.0) {
      const glm::dvec3 a = glm::dvec3(t.p[0]) - c, b = glm::dvec3(t.p[1]) - c, d = glm::dvec3(t.p[2]) - c;
      const double m = std::max({angle_between(a, b), angle_between(b, d), angle_between(d, a)});
      const double k = std::ceil(m / params.max_angle);
      if (k > static_cast<double>(params.max_splits)) {
        n = params.max_splits;
        ++st.capped;
      } else if (k > 1.0) {
        n = static_cast<int>(k);
      }
    }
    if (n == 1) {
      out.push_back(t);
      continue;
    }
    // Grid of barycentric points (i, j) with i + j <= n: corner weights (n - i - j, i, j) / n.
    const double inv = 1.0 / n;
    auto emit = [&](int i0, int j0, int i1, int j1, int i2, int j2) {
      triangle s;
      s.material = t.material;
      corner((n - i0 - j0) * inv, i0 * inv, j0 * inv, t, 0, s);
      corner((n - i1 - j1) * inv, i1 * inv, j1 * inv, t, 1, s);
      corner((n - i2 - j2) * inv, i2 * inv, j2 * inv, t, 2, s);
      out.push_back(s);
    };
    for (int j = 0; j < n; ++j)
      for (int i = 0; i + j < n; ++i) {
        emit(i, j, i + 1, j, i, j + 1);  // same winding as the parent
        if (i + j + 1 < n) emit(i + 1, j, i + 1, j + 1, i, j + 1);
      }
  }
  st.output = out.size();
  if (stats) *stats = st;
  return out;
}

}  // namespace vplrender
