// SPDX-License-Identifier: MIT
#include "junction_band.hpp"

#include "render/cpu/cpu_visibility.hpp"
#include "render/cpu/ray_scene.hpp"

#include <vplkit/core/error.hpp>
#include <vplkit/core/gather_point.hpp>
#include <vplkit/sampling/cosine_hemisphere.hpp>
#include <vplkit/sampling/orthonormal_basis.hpp>

#include <cstddef>
#include <limits>

namespace speed_vs_error {

namespace {
constexpr int k_side = 32;  // directions per side of the midpoint grid
}

std::vector<std::uint8_t> junction_band(const vplrender::frame_buffers& b, float radius) {
  const vplrender::ray_scene& rays = vplrender::frame_ray_scene(b, "the junction band");
  if (!b.has_host_copies())
    throw vplkit::invalid_input("the junction band: the frame's G-buffer is not on the host (read_back_host_copies)");
  const vplkit::gbuffer_view<float> g = b.gbuf.view();
  std::vector<std::uint8_t> band(static_cast<std::size_t>(g.pixel_count()), 0);
  for (int p = 0; p < g.pixel_count(); ++p) {
    const vplkit::gather_point<float> gp = g.at(p);
    if (!vplkit::gather_point_valid(gp)) continue;
    const vplkit::orthonormal_basis<float> frame = vplkit::make_orthonormal_basis(gp.normal);
    for (int k = 0; k < k_side * k_side && band[static_cast<std::size_t>(p)] == 0; ++k) {
      const vplkit::vec2<float> u((static_cast<float>(k % k_side) + 0.5f) / k_side,
                                  (static_cast<float>(k / k_side) + 0.5f) / k_side);
      const glm::vec3 dir = vplkit::to_world(frame, vplkit::sample_cosine_hemisphere(u));
      const vplkit::ray_hit<float> h = rays.trace(gp.position, gp.normal, dir, radius);
      if (h.hit && glm::length(h.position - gp.position) <= radius) band[static_cast<std::size_t>(p)] = 1;
    }
  }
  return band;
}

double band_mean(const vplrender::image_rgb& img, const std::vector<std::uint8_t>& band) {
  double s = 0.0;
  std::size_t n = 0;
  for (std::size_t p = 0; p < band.size() && 3 * p + 2 < img.rgb.size(); ++p)
    if (band[p] != 0) {
      s += static_cast<double>(img.rgb[3 * p]) + img.rgb[3 * p + 1] + img.rgb[3 * p + 2];
      n += 3;
    }
  return n > 0 ? s / static_cast<double>(n) : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace speed_vs_error
