// SPDX-License-Identifier: MIT
#include "analysis_writer.hpp"

#include "junction_band.hpp"
#include "metrics.hpp"
#include "pareto.hpp"
#include "report_format.hpp"
#include "svg_plot.hpp"

#include "cli/render_options.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>
#include <sstream>

namespace speed_vs_error {

using namespace vplrender;

namespace {

// PREFIX.csv: one row per run.
void write_runs_csv(const sweep_options& so, const prepared_scene& p, const sweep_frame& f,
                    const std::vector<run_row>& rows) {
  const options& base = so.base;
  std::ostringstream csv;
  csv << "scene,backend,method,samples,seed,width,height,dprsm,voxels,eps,local_combination,gbg_accumulator,"
         "cdf_search,visibility,prepare_ms,build_ms,estimate_ms,total_ms,wall_ms,rmse_vplsum,relmse_vplsum,rmse_gather,"
         "relmse_gather,rmse_exact,relmse_exact,total_ms_min,repeats,gpu_peak_bytes,clamp_compensation,mean,band_mean,"
         "rmse_gather_net,relmse_gather_net,rmse_exact_net,relmse_exact_net,vpls,dirs,stages\n";
  for (const run_row& r : rows)
    csv << base_name(p.s.name) << "," << to_string(base.back) << "," << to_string(r.meth) << "," << r.samples << ","
        << r.seed << "," << base.width << "," << base.height << "," << base.dprsm << "," << base.voxels << ","
        << num(base.eps) << "," << to_string(base.local_combination) << "," << to_string(base.gbg_accumulator) << ","
        << to_string(base.cdf_search) << "," << to_string(base.visibility) << "," << num(f.prepare_ms) << "," << num(r.build_ms) << "," << num(r.estimate_ms) << "," << num(r.total_ms) << ","
        << num(r.wall_ms) << "," << num(r.vs_vpl.rmse) << "," << num(r.vs_vpl.relmse) << "," << num(r.vs_gather.rmse)
        << "," << num(r.vs_gather.relmse) << "," << num(r.vs_exact.rmse) << "," << num(r.vs_exact.relmse) << ","
        << num(r.total_ms_min) << "," << r.repeats << "," << r.gpu_peak_bytes << ","
        << to_string(r.compensation) << "," << num(r.mean) << ","
        << num(r.band_mean) << "," << num(r.vs_gather_net.rmse) << "," << num(r.vs_gather_net.relmse) << ","
        << num(r.vs_exact_net.rmse) << "," << num(r.vs_exact_net.relmse) << "," << r.vpls << "," << r.dirs << "," << r.stages << "\n";
  write_text(so.out + ".csv", csv.str());
}

// PREFIX_bias_variance.csv, only when there are rows (2 or more seeds): per method and sample count.
void write_bias_variance_csv(const sweep_options& so, const prepared_scene& p,
                             const std::vector<bias_variance_row>& bv_rows) {
  const options& base = so.base;
  if (!bv_rows.empty()) {
    std::ostringstream bv;
    bv << "scene,backend,method,samples,seeds,eps,local_combination,gbg_accumulator,cdf_search,variance,"
          "bias2_vplsum,bias2_gather,bias2_exact,clamp_compensation,bias2_gather_net,bias2_exact_net\n";
    for (const bias_variance_row& r : bv_rows)
      bv << base_name(p.s.name) << "," << to_string(base.back) << "," << to_string(r.meth) << "," << r.samples << ","
         << r.seeds << "," << num(base.eps) << "," << to_string(base.local_combination) << ","
         << to_string(base.gbg_accumulator) << "," << to_string(base.cdf_search) << "," << num(r.variance) << "," << num(r.bias2_vpl) << "," << num(r.bias2_gather) << ","
         << num(r.bias2_exact) << "," << to_string(r.compensation) << "," << num(r.bias2_gather_net) << ","
         << num(r.bias2_exact_net) << "\n";
    write_text(so.out + "_bias_variance.csv", bv.str());
  }
}

// PREFIX.md: the frame, the references and the runs' table.
void write_summary_md(const sweep_options& so, const prepared_scene& p, const sweep_frame& f,
                      const sweep_references& refs, const std::vector<run_row>& rows) {
  const options& base = so.base;
  const reference_image& ref_vpl = refs.vplsum;
  const reference_image& ref_gather = refs.gather;
  const reference_image& ref_exact = refs.exact;
  const bool both = so.compensations.size() > 1;
  std::ostringstream md;
  md << "Scene `" << p.s.name << "`, " << base.width << "x" << base.height << ", DPRSM 2x" << base.dprsm << "x"
     << base.dprsm << ", " << base.voxels << "^3 voxels, backend `" << to_string(base.back) << "`, GL `"
     << f.buffers.gl_renderer << "`, eps " << num(base.eps) << ", local combination `" << to_string(base.local_combination)
     << "`, GBG accumulator `" << to_string(base.gbg_accumulator) << "`, CDF search `" << to_string(base.cdf_search)
     << "`. Prepare (G-buffer + DPRSM + voxels, once): " << fixed(f.prepare_ms, 1) << " ms. References: VPL sum "
     << (!so.ref_vplsum ? "skipped" : ref_vpl.hit ? "from cache" : fixed(ref_vpl.ms, 0) + " ms") << ", gathering at "
     << so.ref_dirs << " dirs "
     << (!so.ref_gather ? "skipped" : ref_gather.hit ? "from cache" : fixed(ref_gather.ms, 0) + " ms")
     << ", exact at " << so.ref_exact_dirs << " dirs "
     << (!so.ref_exact ? "skipped" : ref_exact.hit ? "from cache" : fixed(ref_exact.ms, 0) + " ms")
     << ". Visibility `" << to_string(base.visibility)
     << (base.visibility == visibility_choice::voxels && base.voxel_contract == voxel_contract_choice::exact
             ? "` (exact contract)"
             : "`")
     << ", lit test `" << to_string(base.lit_test)
     << "`, VPL mode `" << to_string(base.vpl_mode) << "`";
  const auto swept = [&](method m) { return std::find(so.methods.begin(), so.methods.end(), m) != so.methods.end(); };
  if (swept(method::ris))
    md << ", ris: " << base.candidates << " candidates per sample from `" << to_string(base.candidate_source)
       << "`, spatial reuse " << (base.spatial > 0 ? std::to_string(base.spatial) + " neighbours" : std::string("off"));
  if (swept(method::ris_mis))
    md << ", ris-mis: " << base.candidates << " candidates per RIS sample from `" << to_string(base.candidate_source)
       << "`, " << (so.dirs_per_sample == 1 ? std::string("as many gathering directions as RIS samples")
                                             : std::to_string(so.dirs_per_sample) + " gathering directions per RIS sample")
       << ", spatial reuse "
       << (base.spatial > 0 ? std::to_string(base.spatial) + " neighbours" : std::string("off"))
       << (base.candidate_pool > 0 ? ", candidates from a pool of " + std::to_string(base.candidate_pool) + " per frame"
                                   : std::string());
  if (so.dirs_per_sample != 1 && (swept(method::mis) || swept(method::mis_as_published)))
    md << ", mis: " << so.dirs_per_sample << " gathering directions per VPL sample";
  md << ". Image means: VPL sum " << (so.ref_vplsum ? sci(image_mean(ref_vpl.img)) : "-") << ", gathering "
     << (so.ref_gather ? sci(image_mean(ref_gather.img)) : "-") << ", exact "
     << (so.ref_exact ? sci(image_mean(ref_exact.img)) : "-");
  if (so.ref_vplsum && so.ref_gather)
    md << ". Between the references: RMSE " << sci(compare(ref_gather.img, ref_vpl.img).rmse);
  if (so.ref_exact && so.ref_vplsum) {
    md << "; VPL sum vs exact " << sci(compare(ref_vpl.img, ref_exact.img).rmse);
    // With (c)'s second render: the VPL estimand's squared relative bias against the truth, the
    // floor of every VPL method's net relMSE, and the most that removing the clamp can gain.
    if (refs.exact_noise)
      md << " (relMSE net of exact's noise " << sci(compare_net(ref_vpl.img, ref_exact.img, refs.exact2.img).relmse)
         << ")";
  }
  if (so.ref_exact && so.ref_gather)
    md << "; gathering vs exact " << sci(compare(ref_gather.img, ref_exact.img).rmse);
  if (!f.band.empty()) {
    std::size_t n = 0;
    for (std::uint8_t m : f.band) n += m;
    md << ". Junction band (" << num(k_band_voxels) << " voxels): " << n << " pixels, means: VPL sum "
       << (so.ref_vplsum ? sci(band_mean(ref_vpl.img, f.band)) : "-") << ", gathering "
       << (so.ref_gather ? sci(band_mean(ref_gather.img, f.band)) : "-") << ", exact "
       << (so.ref_exact ? sci(band_mean(ref_exact.img, f.band)) : "-");
  }
  md << ". Clamp compensation ";
  if (so.compensations.empty()) md << "`" << to_string(make_render_settings(base, p.s).clamp_compensation) << "`";
  else md << "`" << to_string(so.compensations.front()) << (both ? "` and `" + std::string(to_string(so.compensations.back())) : "") << "`";
  md << " (for global, local, gbg, ris" << (both ? "; METHOD-clamped: without it)" : ")");
  // The references' own noise (--ref-noise), which the "net" errors leave out.
  const auto noise_text = [](const reference_image& second, const std::optional<reference_noise>& n) {
    return "MSE " + sci(n->mse) + ", relMSE " + sci(n->relmse) + " +- " + sci(n->relmse_se) + " (second render " +
           (second.hit ? std::string("from cache") : fixed(second.ms, 0) + " ms") + ")";
  };
  if (refs.gather_noise || refs.exact_noise) {
    md << ". Reference noise (a second render at the same directions, independent seed; metrics.hpp): ";
    if (refs.gather_noise) md << "gathering " << noise_text(refs.gather2, refs.gather_noise);
    if (refs.gather_noise && refs.exact_noise) md << "; ";
    if (refs.exact_noise) md << "exact " << noise_text(refs.exact2, refs.exact_noise);
    md << "; the net columns subtract it";
  }
  md << ". Times: the median of " << so.repeats << " repeat(s) of each run.\n\n";
  const bool exact_net = refs.exact_noise.has_value();
  md << "| method | samples | seed | build ms | estimate ms | total ms | mean | band mean | RMSE vs VPL sum | relMSE vs VPL sum | RMSE vs "
        "gathering | relMSE vs gathering | RMSE vs exact | relMSE vs exact |"
     << (exact_net ? " RMSE vs exact, net | relMSE vs exact, net |" : "")
     << "\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|" << (exact_net ? "---:|---:|" : "")
     << "\n";
  for (const run_row& r : rows)
    md << "| " << r.label << " | " << r.samples << " | " << r.seed << " | " << fixed(r.build_ms, 1) << " | "
       << fixed(r.estimate_ms, 1) << " | " << fixed(r.total_ms, 1) << " | " << sci(r.mean) << " | " << sci(r.band_mean) << " | " << sci(r.vs_vpl.rmse) << " | "
       << sci(r.vs_vpl.relmse) << " | " << sci(r.vs_gather.rmse) << " | " << sci(r.vs_gather.relmse) << " | "
       << sci(r.vs_exact.rmse) << " | " << sci(r.vs_exact.relmse) << " |"
       << (exact_net ? " " + sci(r.vs_exact_net.rmse) + " | " + sci(r.vs_exact_net.relmse) + " |" : "") << "\n";
  write_text(so.out + ".md", md.str());
}

}  // namespace

void write_sweep_outputs(const sweep_options& so, const prepared_scene& p, const sweep_frame& f,
                         const sweep_references& refs, const sweep_result& result) {
  const options& base = so.base;
  const std::vector<run_row>& rows = result.rows;
  const std::vector<bias_variance_row>& bv_rows = result.bias_variance;
  write_runs_csv(so, p, f, rows);
  write_bias_variance_csv(so, p, bv_rows);
  write_summary_md(so, p, f, refs, rows);
  const std::vector<std::string>& labels = result.labels;
  const std::string caption = base_name(p.s.name) + " " + std::to_string(base.width) + "x" +
                              std::to_string(base.height) + ", backend " + to_string(base.back) + ", " + f.buffers.gl_renderer;
  const std::string scene_line = "Scene `" + p.s.name + "`, " + std::to_string(base.width) + "x" +
                                 std::to_string(base.height) + ", backend `" + to_string(base.back) + "`.";
  const std::vector<std::string> plots =
      write_analysis(rows, labels, so.samples, so.ref_vplsum, so.ref_gather, so.ref_exact, so.ref_dirs, caption,
                     scene_line, so.out);
  std::cout << "wrote " << so.out << ".csv, " << so.out << ".md";
  for (const std::string& file : plots) std::cout << ", " << file;
  std::cout << (bv_rows.empty() ? "" : ", " + so.out + "_bias_variance.csv") << "\n";
}

std::vector<std::string> write_analysis(const std::vector<run_row>& rows, const std::vector<std::string>& labels,
                                        const std::vector<int>& samples, bool has_vplsum, bool has_gather,
                                        bool has_exact, int ref_dirs,
                                        const std::string& caption, const std::string& scene_line,
                                        const std::string& out) {
  struct reference_view {
    bool on;
    std::string title;
    image_error run_row::*err;
  };
  // Against gathering and exact, the errors with the reference's noise removed where it was
  // measured (--ref-noise): otherwise every method meets the reference's noise as a floor.
  const auto measured = [&rows](image_error run_row::*e) {
    return std::any_of(rows.begin(), rows.end(), [e](const run_row& r) { return !std::isnan((r.*e).rmse); });
  };
  const bool gather_net = measured(&run_row::vs_gather_net), exact_net = measured(&run_row::vs_exact_net);
  const std::string net = ", its reference's noise removed";
  const std::vector<reference_view> refs = {
      {has_vplsum, "RMSE vs exhaustive VPL sum", &run_row::vs_vpl},
      {has_gather,
       (ref_dirs > 0 ? "RMSE vs converged gathering (" + std::to_string(ref_dirs) + " dirs)"
                     : std::string("RMSE vs converged gathering")) +
           (gather_net ? net : ""),
       gather_net ? &run_row::vs_gather_net : &run_row::vs_gather},
      {has_exact, "RMSE vs exact (ground truth)" + (exact_net ? net : ""),
       exact_net ? &run_row::vs_exact_net : &run_row::vs_exact}};
  std::vector<panel> by_time, by_samples;
  std::ostringstream pareto;
  pareto << scene_line << " Time = build + estimate (ms, mean over seeds of the median repeat); error = mean RMSE "
         << "over seeds.\n";
  for (const reference_view& ref : refs) {
    if (!ref.on) continue;
    panel pt, ps;
    pt.title = ps.title = ref.title;
    pt.x_label = "time per frame, ms (build + estimate)";
    ps.x_label = "samples per pixel (VPLs; directions for gather; both for mis)";
    pt.y_label = ps.y_label = "RMSE (linear HDR)";
    std::vector<cost_error_point> points;
    for (const std::string& l : labels) {
      series lt{l, {}, {}}, ls{l, {}, {}};
      for (int n : samples) {
        double t = 0, e = 0;
        int c = 0;
        for (const run_row& r : rows)
          if (r.label == l && r.samples == n) t += r.total_ms, e += (r.*ref.err).rmse, ++c;
        if (c == 0) continue;
        lt.x.push_back(t / c), lt.y.push_back(e / c);
        ls.x.push_back(n), ls.y.push_back(e / c);
        points.push_back({l, n, t / c, e / c});
      }
      pt.lines.push_back(lt);
      ps.lines.push_back(ls);
    }
    by_time.push_back(pt);
    by_samples.push_back(ps);

    pareto << "\n### " << ref.title << "\n\nPareto front (no other run is both faster and more accurate):\n\n"
           << "| method | samples | ms | RMSE |\n|---|---:|---:|---:|\n";
    for (const cost_error_point& q : pareto_front(points))
      pareto << "| " << q.method << " | " << q.samples << " | " << fixed(q.ms, 1) << " | " << sci(q.error) << " |\n";
    pareto << "\nEqual error: time (ms) each method needs to reach the RMSE of the row (log-log interpolation "
              "between measured points; '-' = not reached in this sweep):\n\n| RMSE |";
    for (const std::string& l : labels) pareto << " " << l << " |";
    pareto << " fastest |\n|---:|";
    for (std::size_t i = 0; i < labels.size(); ++i) pareto << "---:|";
    pareto << "---|\n";
    for (double target : error_targets(points, 4)) {
      pareto << "| " << sci(target) << " |";
      std::string best;
      double best_ms = 0;
      for (const std::string& l : labels) {
        std::vector<cost_error_point> mine;
        for (const auto& q : points)
          if (q.method == l) mine.push_back(q);
        const std::optional<double> t = time_to_error(mine, target);
        pareto << " " << (t ? fixed(*t, 1) : std::string("-")) << " |";
        if (t && (best.empty() || *t < best_ms)) best = l, best_ms = *t;
      }
      pareto << " " << (best.empty() ? "-" : best) << " |\n";
    }
  }
  if (by_time.empty()) return {};
  write_text(out + ".svg", svg_loglog(by_time, caption));
  write_text(out + "_samples.svg", svg_loglog(by_samples, caption));
  write_text(out + "_pareto.md", pareto.str());
  return {out + ".svg", out + "_samples.svg", out + "_pareto.md"};
}

}  // namespace speed_vs_error
