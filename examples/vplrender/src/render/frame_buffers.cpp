// SPDX-License-Identifier: MIT
#include "render/frame_buffers.hpp"

#include "render/lighting_facts.hpp"

#include <vplkit/core/error.hpp>
#include <vplkit/core/gather_point.hpp>

#include <glm/geometric.hpp>

#include <algorithm>

namespace vplrender {

frame_facts host_frame_facts(const gbuffer_data& g, const dprsm_data& d) {
  frame_facts f;
  f.known = true;
  for (const vec3& n : g.normal) f.valid_pixels += n != vec3(0.0f) ? 1u : 0u;  // gbuffer_data::valid_count
  const vplkit::gbuffer_view<float> gv = g.view();
  for (int p = 0; p < gv.width * gv.height; ++p) f.gather_points += vplkit::gather_point_valid(gv.at(p)) ? 1u : 0u;
  f.directly_lit_pixels = count_directly_lit_pixels(g, d);
  for (std::size_t t = 0; t < d.albedo.size(); ++t)
    if (d.albedo[t] != vec3(0.0f))
      f.nearest_lit_distance = std::min(f.nearest_lit_distance, glm::length(d.position[t] - d.light.position));
  return f;
}

frame_facts facts_of(const frame_buffers& b) {
  if (b.facts.known) return b.facts;
  if (!b.has_host_copies())
    throw vplkit::invalid_input("frame facts: the frame has neither counted facts nor its arrays on the host");
  return host_frame_facts(b.gbuf, b.dprsm);
}

const exact_ray_frame& frame_exact_rays(const frame_buffers& b, const char* who) {
  if (!b.rays)
    throw vplkit::invalid_input(std::string(who) +
                                ": exact visibility needs a frame prepared with exact rays (frame_settings::exact_rays)");
  return b.ray_frame;
}

}  // namespace vplrender
