// SPDX-License-Identifier: MIT
#include "raster/dprsm_mesh.hpp"

#include "raster/on_all_cores.hpp"

#include <algorithm>
#include <cstddef>
#include <utility>

namespace vplrender {

dprsm_mesh::dprsm_mesh(const std::vector<triangle>& scene_triangles)
    : sorted_(scene_triangles), min_edge_(tessellation_min_edge(scene_triangles)) {
  std::stable_sort(sorted_.begin(), sorted_.end(),
                   [](const triangle& a, const triangle& b) { return a.material < b.material; });
}

void dprsm_mesh::build(vec3 light, const tessellation_params& params, tessellation_stats* stats) {
  tessellation_params p = params;
  if (!(p.min_edge > 0.0)) p.min_edge = min_edge_;
  const chunk_plan plan = plan_chunks(sorted_.size());
  split_.resize(plan.chunks);
  verts_.resize(plan.chunks);
  std::vector<tessellation_stats> st(plan.chunks);
  run_chunks(plan, [&](std::size_t c) {
    std::vector<triangle>& out = split_[c];
    out.clear();
    tessellate_append(sorted_.data() + plan.begin(c, sorted_.size()), sorted_.data() + plan.end(c, sorted_.size()),
                      light, p, out, st[c]);
    std::vector<gl_mesh_vertex>& v = verts_[c];
    v.resize(3 * out.size());
    for (std::size_t k = 0; k < out.size(); ++k) mesh_vertices(out[k], &v[3 * k]);
  });
  // Draw ranges: one per material, in order (the chunks follow the sorted scene).
  std::vector<gl_mesh::range> ranges;
  tessellation_stats total;
  std::size_t at = 0;
  for (std::size_t c = 0; c < plan.chunks; ++c) {
    for (const triangle& t : split_[c]) {
      if (ranges.empty() || ranges.back().material != t.material)
        ranges.push_back({t.material, static_cast<GLint>(3 * at), 0});
      ranges.back().count += 3;
      ++at;
    }
    total.input += st[c].input;
    total.capped += st[c].capped;
  }
  total.output = at;
  mesh_.upload_vertices(verts_, std::move(ranges));
  if (stats) *stats = total;
}

}  // namespace vplrender
