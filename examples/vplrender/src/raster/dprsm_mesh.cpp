// SPDX-License-Identifier: MIT
#include "raster/dprsm_mesh.hpp"

#include "raster/on_all_cores.hpp"

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <utility>

namespace vplrender {

namespace {

bool same_params(const tessellation_params& a, const tessellation_params& b) {
  return a.max_angle == b.max_angle && a.max_depth == b.max_depth && a.min_edge == b.min_edge;
}

}  // namespace

dprsm_mesh::dprsm_mesh(const std::vector<triangle>& scene_triangles)
    : sorted_(scene_triangles), min_edge_(tessellation_min_edge(scene_triangles)) {
  std::stable_sort(sorted_.begin(), sorted_.end(),
                   [](const triangle& a, const triangle& b) { return a.material < b.material; });
}

dprsm_mesh::~dprsm_mesh() {
  if (ahead_job_.valid()) ahead_job_.wait();  // its exception, if any, goes with it
}

void dprsm_mesh::split_into(split_set& out, vec3 light, const tessellation_params& params) const {
  tessellation_params p = params;
  if (!(p.min_edge > 0.0)) p.min_edge = min_edge_;
  const chunk_plan plan = plan_chunks(sorted_.size());
  out.split.resize(plan.chunks);
  out.verts.resize(plan.chunks);
  std::vector<tessellation_stats> st(plan.chunks);
  run_chunks(plan, [&](std::size_t c) {
    std::vector<triangle>& tris = out.split[c];
    tris.clear();
    tessellate_append(sorted_.data() + plan.begin(c, sorted_.size()), sorted_.data() + plan.end(c, sorted_.size()),
                      light, p, tris, st[c]);
    std::vector<gl_mesh_vertex>& v = out.verts[c];
    v.resize(3 * tris.size());
    for (std::size_t k = 0; k < tris.size(); ++k) mesh_vertices(tris[k], &v[3 * k]);
  });
  // Draw ranges: one per material, in order (the chunks follow the sorted scene).
  out.ranges.clear();
  out.stats = tessellation_stats{};
  std::size_t at = 0;
  for (std::size_t c = 0; c < plan.chunks; ++c) {
    for (const triangle& t : out.split[c]) {
      if (out.ranges.empty() || out.ranges.back().material != t.material)
        out.ranges.push_back({t.material, static_cast<GLint>(3 * at), 0});
      out.ranges.back().count += 3;
      ++at;
    }
    out.stats.input += st[c].input;
    out.stats.capped += st[c].capped;
  }
  out.stats.output = at;
}

void dprsm_mesh::drop_ahead() {
  if (!ahead_job_.valid()) return;
  ahead_job_.wait();
  ahead_job_ = std::future<double>();  // a failure of a split nobody takes is not this frame's
}

void dprsm_mesh::split_ahead(vec3 light, const tessellation_params& params) {
  drop_ahead();
  ahead_light_ = light;
  ahead_params_ = params;
  ahead_job_ = std::async(std::launch::async, [this, light, params] {
    const auto start = std::chrono::steady_clock::now();
    split_into(ahead_, light, params);
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  });
}

dprsm_mesh::build_report dprsm_mesh::build(vec3 light, const tessellation_params& params, tessellation_stats* stats) {
  build_report r;
  if (ahead_job_.valid() && ahead_light_ == light && same_params(ahead_params_, params)) {
    r.ahead_ms = ahead_job_.get();
    r.ahead = true;
    std::swap(now_, ahead_);
  } else {
    drop_ahead();
    split_into(now_, light, params);
  }
  mesh_.upload_vertices(now_.verts, now_.ranges);
  if (stats) *stats = now_.stats;
  return r;
}

}  // namespace vplrender
