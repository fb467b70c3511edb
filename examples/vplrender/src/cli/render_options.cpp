// SPDX-License-Identifier: MIT
#include "cli/render_options.hpp"

#include "render/method_traits.hpp"

namespace vplrender {

frame_settings make_frame_settings(const options& o) {
  frame_settings f;
  f.width = o.width;
  f.height = o.height;
  f.dprsm = o.dprsm;
  f.voxels = o.voxels;
  f.back = o.back;
  f.exact_rays = o.visibility == visibility_choice::exact || traits(o.meth).exact_rays;
  return f;
}

render_settings make_render_settings(const options& o, const scene& s) {
  render_settings e;
  static_cast<render_choices&>(e) = o;  // the shared choices, as given (the backends resolve sampler)
  e.eps = static_cast<float>(o.eps);
  e.clamp_compensation = o.clamp_compensation.value_or(clamp_compensation_choice::on);
  e.ris_candidates = o.candidates;
  e.ris_source = o.candidate_source;
  e.ris_spatial = o.spatial;
  e.ris_pool = o.candidate_pool;
  e.global_subset = o.global_subset;
  e.local_subset = o.local_subset;
  region_grid(o.tiles, e.tiles_x, e.tiles_y);
  e.tile_points = o.tile_points;
  e.tile_block = o.tile_block;
  // The VPL clamp of docs/math.md section 2: --dmin (default 1%) of the scene diagonal (a documented,
  // tunable bias; the reference uses the same value, so the CDF methods converge to it exactly).
  e.scene_diagonal = bounds(s).diagonal();
  e.dmin = static_cast<float>(o.dmin_fraction) * e.scene_diagonal;
  return e;
}

frame_buffers prepare_buffers(const options& o, const prepared_scene& p, stage_timer& timer, nlohmann::json& det) {
  return prepare_buffers(p.s, make_frame_settings(o), timer, det);
}

render_result run_estimator(const options& o, const prepared_scene& p, const frame_buffers& b, stage_timer& timer,
                            const progress_fn& progress, nlohmann::json& det) {
  return run_estimator(b, make_render_settings(o, p.s), timer, progress, det);
}

pipeline_result run_pipeline(const options& o, const prepared_scene& p, stage_timer& timer,
                             const progress_fn& progress) {
  return run_pipeline(p.s, make_frame_settings(o), make_render_settings(o, p.s), timer, progress);
}

}  // namespace vplrender
