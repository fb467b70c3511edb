// SPDX-License-Identifier: MIT
#include "sweep.hpp"

#include "junction_band.hpp"
#include "metrics.hpp"
#include "report_format.hpp"

#include "render/stage_timer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <limits>
#include <optional>
#include <utility>

namespace speed_vs_error {

using namespace vplrender;

sweep_frame prepare_sweep_frame(const sweep_options& so, const prepared_scene& p) {
  const options& base = so.base;
  stage_timer prep_timer;
  nlohmann::json prep_det;
  // The exact reference needs the frame's exact rays (Embree), made with the other buffers.
  options prep = base;
  if (so.ref_exact ||
      std::any_of(so.methods.begin(), so.methods.end(), [](method m) { return traits(m).exact_rays; }))
    prep.meth = method::exact;
  frame_buffers b = prepare_buffers(prep, p, prep_timer, prep_det);
  double prepare_ms = 0.0;
  for (const stage_time& st : prep_timer.stages()) prepare_ms += st.ms;
  // The junction band (junction_band.hpp): within k_band_voxels voxels of another surface, where
  // the exact rays can tell.
  // A GPU frame keeps its G-buffer on the GPU: the band reads a host copy of it.
  std::vector<std::uint8_t> band;
  if (b.rays) {
    const float radius = k_band_voxels * b.grid.occupancy().voxel_length();
    if (b.has_host_copies()) {
      band = junction_band(b, radius);
    } else {
      frame_buffers host = b;
      read_back_host_copies(host);
      band = junction_band(host, radius);
    }
  }
  std::cout << "scene " << p.s.name << ", " << base.width << "x" << base.height << ", DPRSM 2x" << base.dprsm << "^2, "
            << base.voxels << "^3 voxels, backend " << to_string(base.back) << "\nGL: " << b.gl_renderer
            << "\nprepare (G-buffer, DPRSM, voxels): " << num(prepare_ms) << " ms" << std::endl;
  return sweep_frame{std::move(b), prepare_ms, std::move(band)};
}

sweep_references get_references(const sweep_options& so, const prepared_scene& p, const sweep_frame& f) {
  const options& base = so.base;
  sweep_references r;
  if (so.ref_vplsum) r.vplsum = get_reference(base, p, f.buffers, so.cache_dir, "vplsum", 0, k_vplsum_reference_seed);
  if (so.ref_gather)
    r.gather = get_reference(base, p, f.buffers, so.cache_dir, "gather", so.ref_dirs, k_gather_reference_seed);
  if (so.ref_exact)
    r.exact = get_reference(base, p, f.buffers, so.cache_dir, "exact", so.ref_exact_dirs, k_exact_reference_seed);
  // --ref-noise: a second render of each Monte Carlo reference, same directions, independent seed.
  if (so.ref_noise && so.ref_gather) {
    r.gather2 =
        get_reference(base, p, f.buffers, so.cache_dir, "gather", so.ref_dirs, k_gather_reference_noise_seed);
    r.gather_noise = estimate_noise(r.gather.img, r.gather2.img);
  }
  if (so.ref_noise && so.ref_exact) {
    r.exact2 =
        get_reference(base, p, f.buffers, so.cache_dir, "exact", so.ref_exact_dirs, k_exact_reference_noise_seed);
    r.exact_noise = estimate_noise(r.exact.img, r.exact2.img);
  }
  return r;
}

sweep_result run_sweep(const sweep_options& so, const prepared_scene& p, const sweep_frame& f,
                       const sweep_references& refs) {
  const options& base = so.base;
  const reference_image& ref_vpl = refs.vplsum;
  const reference_image& ref_gather = refs.gather;
  const reference_image& ref_exact = refs.exact;
  // Against a skipped reference every error is NaN, written as an empty field.
  const auto against = [](const image_rgb& img, const reference_image& ref) {
    if (ref.img.rgb.empty()) {
      const double nan = std::numeric_limits<double>::quiet_NaN();
      return image_error{nan, nan};
    }
    return compare(img, ref.img);
  };

  sweep_result out;
  std::vector<run_row>& rows = out.rows;
  std::vector<bias_variance_row>& bv_rows = out.bias_variance;
  std::vector<std::string>& labels = out.labels;
  const bool both = so.compensations.size() > 1;
  // (method, clamp compensation) pairs: global, local, gbg and ris once per listed setting, the others once.
  std::vector<std::pair<method, std::optional<clamp_compensation_choice>>> sweep;
  for (method m : so.methods)
    for (std::size_t ci = 0; ci < std::max<std::size_t>(1, so.compensations.size()); ++ci)
      if (ci == 0 || series_label(m, clamp_compensation_choice::off, true) != to_string(m))
        sweep.push_back({m, so.compensations.empty() ? std::nullopt : std::optional(so.compensations[ci])});
  for (const auto& [m, compensation] : sweep)
    for (int n : so.samples) {
      std::vector<image_rgb> group;  // this (method, samples) over the seeds
      for (std::uint32_t seed : so.seeds) {
        options o = base;
        o.meth = m;
        o.seed = seed;
        if (compensation) o.clamp_compensation = compensation;
        const sweep_count what = traits(m).sweep;
        if (what != sweep_count::dirs) o.vpls = n;
        if (what != sweep_count::vpls) o.dirs = what == sweep_count::vpls_and_dirs ? so.dirs_per_sample * n : n;
        // --repeats: the same run K times (same seed, same image); the median run's times are
        // reported, and the fastest total beside them (the machines are noisy).
        image_rgb img;
        std::vector<run_row> timed;
        for (int k = 0; k < so.repeats; ++k) {
          stage_timer t;
          nlohmann::json det;
          const auto start = std::chrono::steady_clock::now();
          image_rgb im = run_estimator(o, p, f.buffers, t, {}, det).image;
          run_row r;
          r.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
          for (const stage_time& st : t.stages()) {
            (st.name.rfind("estimate", 0) == 0 ? r.estimate_ms : r.build_ms) += st.ms;
            r.stages += (r.stages.empty() ? "" : "|") + st.name + "=" + num(st.ms);
          }
          r.total_ms = r.build_ms + r.estimate_ms;
          if (det.contains("memory")) r.gpu_peak_bytes = det["memory"].value("gpu_peak_bytes_estimator", 0LL);
          if (k == 0) img = std::move(im);
          timed.push_back(std::move(r));
        }
        std::sort(timed.begin(), timed.end(), [](const run_row& x, const run_row& y) { return x.total_ms < y.total_ms; });
        run_row r = timed[(timed.size() - 1) / 2];
        r.total_ms_min = timed.front().total_ms;
        r.repeats = static_cast<int>(timed.size());
        r.meth = m;
        r.samples = n;
        r.vpls = o.vpls;
        r.dirs = o.dirs;
        r.seed = seed;
        r.compensation = uses_clamp_compensation(make_render_settings(o, p.s)) ? clamp_compensation_choice::on
                                                                                : clamp_compensation_choice::off;
        r.label = series_label(m, r.compensation, both);
        if (std::find(labels.begin(), labels.end(), r.label) == labels.end()) labels.push_back(r.label);
        r.vs_vpl = against(img, ref_vpl);
        r.vs_gather = against(img, ref_gather);
        r.vs_exact = against(img, ref_exact);
        if (refs.gather_noise) r.vs_gather_net = compare_net(img, ref_gather.img, refs.gather2.img);
        if (refs.exact_noise) r.vs_exact_net = compare_net(img, ref_exact.img, refs.exact2.img);
        r.mean = image_mean(img);
        if (!f.band.empty()) r.band_mean = band_mean(img, f.band);
        std::cout << r.label << " samples " << n
                  << (what == sweep_count::vpls_and_dirs && so.dirs_per_sample != 1
                          ? " (" + std::to_string(o.dirs) + " directions)"
                          : std::string())
                  << " seed " << seed << ": " << fixed(r.total_ms, 1)
                  << " ms, RMSE vs VPL sum " << sci(r.vs_vpl.rmse) << ", vs gathering " << sci(r.vs_gather.rmse)
                  << ", vs exact " << sci(r.vs_exact.rmse) << std::endl;
        rows.push_back(r);
        if (so.seeds.size() >= 2) group.push_back(img);
      }
      if (group.size() >= 2) {
        const double nan = std::numeric_limits<double>::quiet_NaN();
        const bias_variance a =
            ref_vpl.img.rgb.empty() ? bias_variance{nan, nan} : split(group, ref_vpl.img);
        const bias_variance g = ref_gather.img.rgb.empty()
                                                    ? bias_variance{nan, nan}
                                                    : split(group, ref_gather.img);
        const bias_variance e = ref_exact.img.rgb.empty()
                                                    ? bias_variance{nan, nan}
                                                    : split(group, ref_exact.img);
        const double variance = !std::isnan(a.variance) ? a.variance : !std::isnan(g.variance) ? g.variance : e.variance;
        const run_row& last = rows.back();
        bias_variance_row row{m, last.label, last.compensation, n, static_cast<int>(group.size()), variance,
                              a.bias2, g.bias2, e.bias2};
        if (refs.gather_noise) row.bias2_gather_net = g.bias2 - refs.gather_noise->mse;
        if (refs.exact_noise) row.bias2_exact_net = e.bias2 - refs.exact_noise->mse;
        bv_rows.push_back(row);
      }
    }

  return out;
}

}  // namespace speed_vs_error
