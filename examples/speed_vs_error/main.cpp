// SPDX-License-Identifier: MIT
// speed_vs_error: for one scene, every requested method over a sweep of sample counts in one
// process. The scene, G-buffer, DPRSM and voxel grid are prepared once (prepare_buffers) and every
// run reuses them (run_estimator); each run is timed per stage and compared with three references
// (docs/math.md section 8): (a) the exhaustive VPL sum (method reference), (b) converged
// gathering (method gather at --ref-dirs directions) and (c) the ground truth (method exact at
// --ref-exact-dirs directions: exact visibility, no VPLs). Writes PREFIX.csv, PREFIX.md and PREFIX.svg.
#include "junction_band.hpp"
#include "metrics.hpp"
#include "pareto.hpp"
#include "svg_plot.hpp"

#include "cli/options.hpp"
#include "cli/render_options.hpp"
#include "cli/scene_setup.hpp"
#include "io/errors.hpp"
#include "io/exr_io.hpp"
#include "render/method_traits.hpp"
#include "render/stage_timer.hpp"

#include <headless_gl/compute.hpp>

#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace vplrender;
namespace fs = std::filesystem;

// The gathering reference's seed: fixed and far from the usual sweep seeds, so the reference's
// random streams are independent of the runs it judges.
constexpr std::uint32_t k_gather_reference_seed = 0x5EED0F1Eu;
// The exact reference's seed, for the same reason.
constexpr std::uint32_t k_exact_reference_seed = 0x5EED0E4Au;
// The patch VPL sum's seed (its jitter; --vpl-mode point draws nothing), for the same reason.
constexpr std::uint32_t k_vplsum_reference_seed = 0x5EED0A50u;
// The junction band's width in voxels of the frame's grid (junction_band.hpp).
constexpr float k_band_voxels = 2.0f;

const char* k_help = R"(speed_vs_error: error against time for each method on one scene, in one process.

Usage: speed_vs_error [options] [vplrender scene options]

Sweep options:
  --methods LIST     comma-separated methods (default global,local,gbg,gather,mis);
                     any of global local gbg gather mis mis-as-published exact ris
                     (ris: --backend cpu only for now)
  --samples LIST     comma-separated sample counts (default 1,4,16,64). A count n means:
                     global/local/gbg/ris: --vpls n; gather, exact: --dirs n; mis and
                     mis-as-published: --vpls n and --dirs n
  --seeds LIST       comma-separated seeds, each run once per (method, samples) (default 1)
  --clamp-compensation LIST
                     off, on or off,on: the VPL clamp's compensation for global, local,
                     gbg and ris (vplrender --clamp-compensation; default: vplrender's, on with
                     --backend cpu). With both, each of these methods runs twice and its
                     clamped runs are labelled METHOD-clamped (column clamp_compensation)
  --ref-dirs N       directions of the converged-gathering reference (default 4096)
  --ref-exact-dirs N directions of the exact reference (default 4096)
  --references LIST  which references to compute: any of vplsum, gather, exact; all
                     (default), both (= vplsum,gather) or none. The exhaustive VPL sum costs
                     2 R^2 VPLs per pixel: skip it at large DPRSM sizes; errors against a
                     skipped reference are left empty
  --replot CSV       render nothing: redraw PREFIX.svg, PREFIX_samples.svg and PREFIX_pareto.md
                     from a CSV this tool wrote (after changing the plots, or to merge sweeps)
  --repeats K        time every run K times (default 1): the CSV's times are the median run's,
                     total_ms_min the fastest; the image and its error are from the first run
  --cache-dir DIR    reference cache (default speed_vs_error_cache); references are EXR files
                     named by a hash of scene, size, DPRSM, voxels, backend, light, camera,
                     --direct, --visibility exact, and for the gathering and exact references
                     their directions and seed (gathering: and --lit-test; exact on the GPU:
                     also that), for the patch VPL
                     sum its mode and seed
  --out PREFIX       writes PREFIX.csv, PREFIX.md, PREFIX.svg (default speed_vs_error), and
                     with 2 or more seeds PREFIX_bias_variance.csv
  --help             this text

Scene options, passed to vplrender's parser with its defaults and limits (vplrender --help):
  --scene --backend --size --dprsm --voxels --regions --dirs (mis only when not swept) --eps --dmin
  --local-combination --gbg-accumulator --cdf-search --visibility --lit-test --vpl-mode --camera --light
  --candidates --candidate-source --spatial (ris) --paper --direct.
  Not allowed: --method --vpls --seed --out --window. The references do not depend on --eps,
  --local-combination, --gbg-accumulator or --cdf-search (one cache entry serves every choice).

Error metrics, on linear HDR values, over all pixels p and channels c (x = run, r = reference):
  RMSE   = sqrt( mean_{p,c} (x_pc - r_pc)^2 )
  relMSE = mean_{p,c} (x_pc - r_pc)^2 / (r_pc^2 + 1e-2)
Reported against (a) the exhaustive VPL sum (method reference with the runs' --vpl-mode: the
estimand of global, local, gbg; with patch one jittered point per texel, seed 0x5EED0A50, an
unbiased estimate of the continuous integral that (b) estimates; with the clamp compensation
(the last listed setting) plus 256 of its directions) and (b) converged gathering
(gather at --ref-dirs, seed 0x5EED0F1E: the estimand of gather and mis; with point VPLs it
differs from (a) by the VPL discretisation; with either by the distance clamp), both with the
chosen --visibility, and (c) the ground truth (exact at --ref-exact-dirs, seed 0x5EED0E4A: cosine
gathering against the triangles with exact visibility and no VPLs, on --backend's estimator; the
distance from (a) and (b) to (c) is what the VPLs, the DPRSM and the voxel grid cost in accuracy).

Bias/variance (2 or more seeds S, per method and sample count; m = mean image over the seeds):
  variance = mean_{p,c} sum_s (x_s,pc - m_pc)^2 / (S - 1)   (per-run variance, unbiased)
  bias2    = mean_{p,c} (m_pc - r_pc)^2 - variance / S      (unbiased; may be slightly negative)
so that the expected MSE of one run against r is bias2 + variance.

Times (ms): prepare = G-buffer + DPRSM + voxel grid, once for all runs (not in the totals);
per run, each estimator stage as vplrender reports it (GPU timer queries for GPU stages,
steady_clock for CPU ones); build = all stages but 'estimate*'; total = build + estimate.

Exit status: 0 success, 1 bad input or failed output, 2 bad command line.
)";

[[noreturn]] void bad(const std::string& m) { throw usage_error(m); }

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

long long to_int(const std::string& flag, const std::string& t, long long lo, long long hi) {
  char* end = nullptr;
  const long long v = std::strtoll(t.c_str(), &end, 10);
  if (t.empty() || end != t.c_str() + t.size() || v < lo || v > hi)
    bad(flag + ": expected whole numbers in " + std::to_string(lo) + ".." + std::to_string(hi) + ", got '" + t + "'");
  return v;
}

method parse_method(const std::string& t) {
  const std::optional<method> m = method_from_name(t);
  if (m && traits(*m).swept) return *m;
  if (m) bad("--methods: '" + t + "' is the reference (always computed), not a swept method");
  bad("--methods: unknown method '" + t + "'");
}

std::vector<method> default_methods() {
  std::vector<method> out;
  for (const method_traits& t : all_method_traits())
    if (t.swept_by_default) out.push_back(t.id);
  return out;
}

struct sweep_options {
  std::vector<method> methods = default_methods();
  std::vector<int> samples{1, 4, 16, 64};
  std::vector<std::uint32_t> seeds{1};
  std::vector<clamp_compensation_choice> compensations;  // empty: vplrender's default
  int ref_dirs = 4096;
  int ref_exact_dirs = 4096;
  bool ref_vplsum = true, ref_gather = true, ref_exact = true;
  int repeats = 1;
  std::string replot;  // --replot CSV
  std::string cache_dir = "speed_vs_error_cache";
  std::string out = "speed_vs_error";
  options base;
};

// Own flags here; the rest go to vplrender's parser (its validation, defaults and limits).
bool parse(const std::vector<std::string>& args, sweep_options& so) {
  std::vector<std::string> pass{"speed_vs_error"};
  for (std::size_t i = 1; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--help" || a == "-h") return false;
    const auto value = [&]() -> std::string {
      if (i + 1 >= args.size()) bad(a + ": needs a value");
      return args[++i];
    };
    if (a == "--methods") {
      so.methods.clear();
      for (const std::string& t : split(value())) so.methods.push_back(parse_method(t));
    } else if (a == "--samples") {
      so.samples.clear();
      for (const std::string& t : split(value())) so.samples.push_back(static_cast<int>(to_int(a, t, 1, limits::max_dirs)));
    } else if (a == "--seeds") {
      so.seeds.clear();
      for (const std::string& t : split(value())) so.seeds.push_back(static_cast<std::uint32_t>(to_int(a, t, 0, 4294967295LL)));
    } else if (a == "--clamp-compensation") {
      so.compensations.clear();
      for (const std::string& t : split(value())) {
        if (t != "off" && t != "on") bad("--clamp-compensation: unknown value '" + t + "' (off, on or off,on)");
        const clamp_compensation_choice c = t == "on" ? clamp_compensation_choice::on : clamp_compensation_choice::off;
        if (std::find(so.compensations.begin(), so.compensations.end(), c) == so.compensations.end())
          so.compensations.push_back(c);
      }
    } else if (a == "--ref-dirs") {
      so.ref_dirs = static_cast<int>(to_int(a, value(), 1, limits::max_dirs));
    } else if (a == "--ref-exact-dirs") {
      so.ref_exact_dirs = static_cast<int>(to_int(a, value(), 1, limits::max_dirs));
    } else if (a == "--references") {
      const std::string v = value();
      so.ref_vplsum = so.ref_gather = so.ref_exact = false;
      if (v == "all") so.ref_vplsum = so.ref_gather = so.ref_exact = true;
      else if (v == "both") so.ref_vplsum = so.ref_gather = true;
      else if (v != "none")
        for (const std::string& t : split(v)) {
          if (t == "vplsum") so.ref_vplsum = true;
          else if (t == "gather") so.ref_gather = true;
          else if (t == "exact") so.ref_exact = true;
          else bad("--references: unknown reference '" + t + "' (vplsum, gather, exact, all, both or none)");
        }
    } else if (a == "--replot") {
      so.replot = value();
    } else if (a == "--repeats") {
      so.repeats = static_cast<int>(to_int(a, value(), 1, 1000));
    } else if (a == "--cache-dir") {
      so.cache_dir = value();
    } else if (a == "--out") {
      so.out = value();
    } else if (a == "--method" || a == "--vpls" || a == "--seed" || a == "--window") {
      bad(a + ": not allowed here (the sweep sets it; see --methods, --samples, --seeds)");
    } else if (a == "--paper" || a == "--direct") {
      pass.push_back(a);
    } else {
      pass.push_back(a);
      pass.push_back(value());
    }
  }
  if (so.methods.empty() || so.samples.empty() || so.seeds.empty()) bad("--methods, --samples, --seeds: empty list");
  parse_result r = parse_command_line(pass);
  if (r.what == parse_result::action::help) return false;
  so.base = r.opts;
  so.base.progress = progress_mode::never;
  // The exhaustive VPL sum follows the last listed setting (on for off,on): the estimand of the
  // runs it labels with the method's own name.
  if (!so.compensations.empty()) so.base.clamp_compensation = so.compensations.back();
  if (so.base.back == backend::gpu &&
      std::find(so.compensations.begin(), so.compensations.end(), clamp_compensation_choice::on) != so.compensations.end())
    bad("--clamp-compensation: on needs --backend cpu (the GPU backend's estimate kernel does not have it yet)");
  if (so.base.back == backend::gpu)
    for (method m : so.methods)
      if (!traits(m).gpu)
        bad(std::string("--methods ") + to_string(m) + ": runs on --backend cpu only for now (its GPU kernels are not written yet)");
  return true;
}

std::string num(double v) {
  if (std::isnan(v)) return "";  // an error against a skipped reference
  char b[40];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}

double image_mean(const image_rgb& img) {
  double s = 0.0;
  for (float v : img.rgb) s += v;
  return img.rgb.empty() ? 0.0 : s / static_cast<double>(img.rgb.size());
}

std::string vec(const glm::vec3& v) { return num(v.x) + "," + num(v.y) + "," + num(v.z); }

std::uint64_t fnv1a(const std::string& s) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
  return h;
}

// Everything a reference image depends on (the scene as prepared: camera and light after framing).
std::string reference_key(const options& o, const prepared_scene& p, const std::string& kind, int dirs, std::uint32_t seed) {
  std::string k = "v1|kind=" + kind + "|scene=" + p.s.name;
  std::error_code ec;
  if (fs::is_regular_file(p.s.name, ec))
    k += "|file_bytes=" + std::to_string(fs::file_size(p.s.name, ec)) + "|file_mtime=" +
         std::to_string(fs::last_write_time(p.s.name, ec).time_since_epoch().count());
  k += "|size=" + std::to_string(o.width) + "x" + std::to_string(o.height) + "|dprsm=" + std::to_string(o.dprsm) +
       "|voxels=" + std::to_string(o.voxels) + "|backend=" + to_string(o.back) + "|light=" + vec(p.s.light.position) +
       "," + vec(p.s.light.intensity) + "|camera=" + vec(p.s.cam.eye) + "," + vec(p.s.cam.target) + "," +
       vec(p.s.cam.up) + "," + num(p.s.cam.vfov_deg) + "|direct=" + (o.direct ? "1" : "0");
  // Only when not the default, so the keys (and cached files) of earlier references stay what they were.
  if (kind == "vplsum" && o.dmin_fraction != 0.01) k += "|dmin=" + num(o.dmin_fraction);
  // Only when exact, so the keys (and cached files) of voxel references stay what they were.
  if (o.visibility == visibility_choice::exact && kind != "exact") k += "|visibility=exact";
  // Gathering references shade known hits as their own surface and take the lit test: keys of the
  // older ones (the texel's normal, the shadow map always) do not match them.
  if (kind == "gather") k += std::string("|hits=own-surface|lit=") + to_string(o.lit_test);
  if (kind == "gather" || kind == "exact") k += "|dirs=" + std::to_string(dirs) + "|seed=" + std::to_string(seed);
  // The exact reference runs on --backend's estimator; the GPU's differs from the CPU's at creases
  // (ties the two ray tracers break differently), and "backend=gpu" entries written before it had a
  // GPU kernel hold CPU images: a key of their own.
  if (kind == "exact" && o.back == backend::gpu) k += "|exact_estimator=gpu";
  // Only with the clamp compensation (the reference adds it as the VPL methods do), so the keys of
  // clamped sums stay what they were.
  if (kind == "vplsum") {
    options r = o;
    r.meth = method::reference;
    const render_settings rs = make_render_settings(r, p.s);
    if (uses_clamp_compensation(rs)) k += "|clamp_compensation_dirs=" + std::to_string(clamp_compensation_dirs(rs));
  }
  // Only for patch VPLs, so the keys of point VPL sums stay what they were.
  if (kind == "vplsum" && o.vpl_mode == vpl_mode_choice::patch)
    k += "|vpl_mode=patch|strata=" + std::to_string(reference_patch_strata) + "|seed=" + std::to_string(seed);
  return k;
}

std::string base_name(const std::string& scene_name) {
  std::string b = fs::path(scene_name).stem().string();
  for (char& c : b)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return b;
}

struct reference_image {
  image_rgb img;
  std::string path;
  bool hit = false;
  double ms = 0.0;  // time to compute it (0 on a cache hit)
};

reference_image get_reference(const options& base, const prepared_scene& p, const frame_buffers& b,
                              const std::string& cache_dir, const std::string& kind, int dirs, std::uint32_t seed) {
  const std::string key = reference_key(base, p, kind, dirs, seed);
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(fnv1a(key)));
  reference_image r;
  r.path = (fs::path(cache_dir) / ("ref_" + kind + "_" + base_name(p.s.name) + "_" + std::to_string(base.width) + "x" +
                                   std::to_string(base.height) + "_" + hex + ".exr"))
               .string();
  std::error_code ec;
  if (fs::is_regular_file(r.path, ec)) {
    r.img = read_exr(r.path);
    if (r.img.width == base.width && r.img.height == base.height) {
      r.hit = true;
      std::cout << "reference cache hit: " << kind << " <- " << r.path << "\n";
      return r;
    }
  }
  std::cout << "reference cache miss: computing " << kind << " -> " << r.path << std::endl;
  options o = base;
  o.meth = kind == "gather" ? method::gather : kind == "exact" ? method::exact : method::reference;
  o.dirs = dirs;
  o.seed = seed;
  stage_timer t;
  nlohmann::json det;
  const auto start = std::chrono::steady_clock::now();
  r.img = run_estimator(o, p, b, t, {}, det).image;
  r.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  fs::create_directories(cache_dir, ec);
  if (ec) throw output_error("--cache-dir: cannot create '" + cache_dir + "': " + ec.message());
  write_exr(r.path, r.img, {{"speed_vs_error:key", key}});
  return r;
}

struct run_row {
  method meth;
  std::string label;  // the method's name, or METHOD-clamped (its clamped runs when both are swept)
  clamp_compensation_choice compensation = clamp_compensation_choice::off;  // as the run used it
  int samples = 0;
  std::uint32_t seed = 0;
  double build_ms = 0, estimate_ms = 0, total_ms = 0, wall_ms = 0;
  double total_ms_min = 0;
  int repeats = 1;
  long long gpu_peak_bytes = 0;  // GPU buffers the estimator held at its peak (docs/results.md, memory)
  std::string stages;
  double mean = 0;  // the image's mean over pixels and channels (linear HDR)
  double band_mean = std::numeric_limits<double>::quiet_NaN();  // over the junction band's pixels
  speed_vs_error::image_error vs_vpl, vs_gather, vs_exact;
};

// A run's series: the method's name, or METHOD-clamped for the clamped runs of global, local, gbg
// and ris when both settings of the clamp compensation are swept.
std::string series_label(method m, clamp_compensation_choice c, bool both) {
  const bool clamped = m != method::reference && method_has_clamp(m);
  return std::string(to_string(m)) + (both && clamped && c == clamp_compensation_choice::off ? "-clamped" : "");
}

struct bias_variance_row {
  method meth;
  std::string label;
  clamp_compensation_choice compensation = clamp_compensation_choice::off;
  int samples = 0, seeds = 0;
  double variance = 0, bias2_vpl = 0, bias2_gather = 0, bias2_exact = 0;
};

void write_text(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f << text;
  if (!f) throw output_error("cannot write '" + path + "'");
}

std::string fixed(double v, int digits) {
  char b[40];
  std::snprintf(b, sizeof b, "%.*f", digits, v);
  return b;
}

std::string sci(double v) {
  if (std::isnan(v)) return "-";
  char b[40];
  std::snprintf(b, sizeof b, "%.3e", v);
  return b;
}


// Per reference and method, the mean over seeds of time and error at each sample count; from
// these: PREFIX.svg (error against time), PREFIX_samples.svg (error against samples: the paper's
// Fig. 8) and PREFIX_pareto.md (Pareto front, equal-error table). Returns the files written.
std::vector<std::string> write_analysis(const std::vector<run_row>& rows, const std::vector<std::string>& labels,
                                        const std::vector<int>& samples, bool has_vplsum, bool has_gather,
                                        bool has_exact, int ref_dirs,
                                        const std::string& caption, const std::string& scene_line,
                                        const std::string& out) {
  struct reference_view {
    bool on;
    std::string title;
    speed_vs_error::image_error run_row::*err;
  };
  const std::vector<reference_view> refs = {
      {has_vplsum, "RMSE vs exhaustive VPL sum", &run_row::vs_vpl},
      {has_gather,
       ref_dirs > 0 ? "RMSE vs converged gathering (" + std::to_string(ref_dirs) + " dirs)" : "RMSE vs converged gathering",
       &run_row::vs_gather},
      {has_exact, "RMSE vs exact (ground truth)", &run_row::vs_exact}};
  std::vector<speed_vs_error::panel> by_time, by_samples;
  std::ostringstream pareto;
  pareto << scene_line << " Time = build + estimate (ms, mean over seeds of the median repeat); error = mean RMSE "
         << "over seeds.\n";
  for (const reference_view& ref : refs) {
    if (!ref.on) continue;
    speed_vs_error::panel pt, ps;
    pt.title = ps.title = ref.title;
    pt.x_label = "time per frame, ms (build + estimate)";
    ps.x_label = "samples per pixel (VPLs; directions for gather; both for mis)";
    pt.y_label = ps.y_label = "RMSE (linear HDR)";
    std::vector<speed_vs_error::cost_error_point> points;
    for (const std::string& l : labels) {
      speed_vs_error::series lt{l, {}, {}}, ls{l, {}, {}};
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
    for (const speed_vs_error::cost_error_point& q : speed_vs_error::pareto_front(points))
      pareto << "| " << q.method << " | " << q.samples << " | " << fixed(q.ms, 1) << " | " << sci(q.error) << " |\n";
    pareto << "\nEqual error: time (ms) each method needs to reach the RMSE of the row (log-log interpolation "
              "between measured points; '-' = not reached in this sweep):\n\n| RMSE |";
    for (const std::string& l : labels) pareto << " " << l << " |";
    pareto << " fastest |\n|---:|";
    for (std::size_t i = 0; i < labels.size(); ++i) pareto << "---:|";
    pareto << "---|\n";
    for (double target : speed_vs_error::error_targets(points, 4)) {
      pareto << "| " << sci(target) << " |";
      std::string best;
      double best_ms = 0;
      for (const std::string& l : labels) {
        std::vector<speed_vs_error::cost_error_point> mine;
        for (const auto& q : points)
          if (q.method == l) mine.push_back(q);
        const std::optional<double> t = speed_vs_error::time_to_error(mine, target);
        pareto << " " << (t ? fixed(*t, 1) : std::string("-")) << " |";
        if (t && (best.empty() || *t < best_ms)) best = l, best_ms = *t;
      }
      pareto << " " << (best.empty() ? "-" : best) << " |\n";
    }
  }
  if (by_time.empty()) return {};
  write_text(out + ".svg", speed_vs_error::svg_loglog(by_time, caption));
  write_text(out + "_samples.svg", speed_vs_error::svg_loglog(by_samples, caption));
  write_text(out + "_pareto.md", pareto.str());
  return {out + ".svg", out + "_samples.svg", out + "_pareto.md"};
}


// --replot: the runs back from a CSV this tool wrote (columns found by name, so CSVs from older
// versions with fewer columns still load), then write_analysis.
std::vector<std::string> replot(const sweep_options& so) {
  std::ifstream f(so.replot, std::ios::binary);
  if (!f) throw input_error("--replot: cannot open '" + so.replot + "'");
  std::string line;
  const auto fields = [](const std::string& l) {
    std::vector<std::string> v;
    std::string cur;
    for (char c : l) {
      if (c == ',') v.push_back(cur), cur.clear();
      else if (c != '\r') cur += c;
    }
    v.push_back(cur);
    return v;
  };
  if (!std::getline(f, line)) throw input_error("--replot: '" + so.replot + "' is empty");
  const std::vector<std::string> header = fields(line);
  const auto col = [&](const std::string& name) -> std::size_t {
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return i;
    throw input_error("--replot: '" + so.replot + "' has no column '" + name + "'");
  };
  const std::size_t c_scene = col("scene"), c_backend = col("backend"), c_method = col("method"),
                    c_samples = col("samples"), c_width = col("width"), c_height = col("height"),
                    c_total = col("total_ms"), c_rv = col("rmse_vplsum"), c_lv = col("relmse_vplsum"),
                    c_rg = col("rmse_gather"), c_lg = col("relmse_gather");
  // Written since the exact reference exists; older CSVs have neither column.
  const auto optional_col = [&](const std::string& name) {
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return i;
    return header.size();
  };
  const std::size_t c_re = optional_col("rmse_exact"), c_le = optional_col("relmse_exact");
  const std::size_t c_cc = optional_col("clamp_compensation");  // since the clamp compensation exists
  const auto number = [&](const std::string& t, int line_no) {
    if (t.empty()) return std::numeric_limits<double>::quiet_NaN();
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    if (end == t.c_str() || *end != '\0')
      throw input_error("--replot: " + so.replot + ":" + std::to_string(line_no) + ": '" + t + "' is not a number");
    return v;
  };
  std::vector<run_row> rows;
  std::vector<int> samples;
  std::string scene, backend, size;
  bool has_vpl = false, has_gather = false, has_exact = false;
  int line_no = 1;
  while (std::getline(f, line)) {
    ++line_no;
    if (line.empty() || line == "\r") continue;
    const std::vector<std::string> v = fields(line);
    if (v.size() != header.size())
      throw input_error("--replot: " + so.replot + ":" + std::to_string(line_no) + ": " + std::to_string(v.size()) +
                        " fields, the header has " + std::to_string(header.size()));
    run_row r;
    try {
      r.meth = parse_method(v[c_method]);
    } catch (const usage_error& e) {
      throw input_error("--replot: " + so.replot + ":" + std::to_string(line_no) + ": " + e.what());
    }
    r.samples = static_cast<int>(number(v[c_samples], line_no));
    r.total_ms = number(v[c_total], line_no);
    r.vs_vpl = {number(v[c_rv], line_no), number(v[c_lv], line_no)};
    r.vs_gather = {number(v[c_rg], line_no), number(v[c_lg], line_no)};
    if (c_re < v.size() && c_le < v.size()) r.vs_exact = {number(v[c_re], line_no), number(v[c_le], line_no)};
    else r.vs_exact = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
    has_exact = has_exact || !std::isnan(r.vs_exact.rmse);
    has_vpl = has_vpl || !std::isnan(r.vs_vpl.rmse);
    has_gather = has_gather || !std::isnan(r.vs_gather.rmse);
    if (c_cc < v.size() && v[c_cc] == "on") r.compensation = clamp_compensation_choice::on;
    if (std::find(samples.begin(), samples.end(), r.samples) == samples.end()) samples.push_back(r.samples);
    scene = v[c_scene], backend = v[c_backend], size = v[c_width] + "x" + v[c_height];
    rows.push_back(r);
  }
  if (rows.empty()) throw input_error("--replot: '" + so.replot + "' has no rows");
  std::sort(samples.begin(), samples.end());
  bool any_on = false, any_off = false;
  for (const run_row& r : rows) {
    if (series_label(r.meth, clamp_compensation_choice::off, true) == to_string(r.meth)) continue;  // no clamp
    (r.compensation == clamp_compensation_choice::on ? any_on : any_off) = true;
  }
  std::vector<std::string> labels;
  for (run_row& r : rows) {
    r.label = series_label(r.meth, r.compensation, any_on && any_off);
    if (std::find(labels.begin(), labels.end(), r.label) == labels.end()) labels.push_back(r.label);
  }
  const std::string caption = scene + " " + size + ", backend " + backend + " (from " + base_name(so.replot) + ".csv)";
  return write_analysis(rows, labels, samples, has_vpl, has_gather, has_exact, 0, caption,
                        "Scene `" + scene + "`, " + size + ", backend `" + backend + "`.", so.out);
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv, argv + argc);
  sweep_options so;
  try {
    if (!parse(args, so)) {
      std::cout << k_help;
      return 0;
    }
  } catch (const usage_error& e) {
    std::cerr << "speed_vs_error: error: " << e.what() << "\n";
    return 2;
  }
  try {
    if (!so.replot.empty()) {
      const std::vector<std::string> files = replot(so);
      std::cout << "wrote";
      for (std::size_t i = 0; i < files.size(); ++i) std::cout << (i ? ", " : " ") << files[i];
      std::cout << "\n";
      return 0;
    }
    const options& base = so.base;
    {
      // Fail before the sweep, not after it.
      fs::path dir = fs::path(so.out).parent_path();
      std::error_code ec;
      if (!dir.empty() && !fs::is_directory(dir, ec))
        throw output_error("--out: directory '" + dir.string() + "' does not exist");
    }
    const prepared_scene p = prepare_scene(base);
    for (const std::string& w : p.s.warnings) std::cerr << "speed_vs_error: warning: " << w << "\n";

    stage_timer prep_timer;
    nlohmann::json prep_det;
    // The exact reference needs the frame's exact rays (Embree), made with the other buffers.
    options prep = base;
    if (so.ref_exact ||
        std::any_of(so.methods.begin(), so.methods.end(), [](method m) { return traits(m).exact_rays; }))
      prep.meth = method::exact;
    const frame_buffers b = prepare_buffers(prep, p, prep_timer, prep_det);
    double prepare_ms = 0.0;
    for (const stage_time& st : prep_timer.stages()) prepare_ms += st.ms;
    // The junction band (junction_band.hpp): within k_band_voxels voxels of another surface, where
    // the exact rays can tell.
    // A GPU frame keeps its G-buffer on the GPU: the band reads a host copy of it.
    std::vector<std::uint8_t> band;
    if (b.rays) {
      const float radius = k_band_voxels * b.grid.occupancy().voxel_length();
      if (b.has_host_copies()) {
        band = speed_vs_error::junction_band(b, radius);
      } else {
        frame_buffers host = b;
        read_back_host_copies(host);
        band = speed_vs_error::junction_band(host, radius);
      }
    }
    std::cout << "scene " << p.s.name << ", " << base.width << "x" << base.height << ", DPRSM 2x" << base.dprsm << "^2, "
              << base.voxels << "^3 voxels, backend " << to_string(base.back) << "\nGL: " << b.gl_renderer
              << "\nprepare (G-buffer, DPRSM, voxels): " << num(prepare_ms) << " ms" << std::endl;

    const reference_image ref_vpl =
        so.ref_vplsum ? get_reference(base, p, b, so.cache_dir, "vplsum", 0, k_vplsum_reference_seed) : reference_image{};
    const reference_image ref_gather =
        so.ref_gather ? get_reference(base, p, b, so.cache_dir, "gather", so.ref_dirs, k_gather_reference_seed)
                      : reference_image{};
    const reference_image ref_exact =
        so.ref_exact ? get_reference(base, p, b, so.cache_dir, "exact", so.ref_exact_dirs, k_exact_reference_seed)
                     : reference_image{};
    // Against a skipped reference every error is NaN, written as an empty field.
    const auto against = [](const image_rgb& img, const reference_image& ref) {
      if (ref.img.rgb.empty()) {
        const double nan = std::numeric_limits<double>::quiet_NaN();
        return speed_vs_error::image_error{nan, nan};
      }
      return speed_vs_error::compare(img, ref.img);
    };

    std::vector<run_row> rows;
    std::vector<bias_variance_row> bv_rows;
    std::vector<std::string> labels;
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
          if (what != sweep_count::vpls) o.dirs = n;
          // --repeats: the same run K times (same seed, same image); the median run's times are
          // reported, and the fastest total beside them (the machines are noisy).
          image_rgb img;
          std::vector<run_row> timed;
          for (int k = 0; k < so.repeats; ++k) {
            stage_timer t;
            nlohmann::json det;
            const auto start = std::chrono::steady_clock::now();
            image_rgb im = run_estimator(o, p, b, t, {}, det).image;
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
          r.seed = seed;
          r.compensation = uses_clamp_compensation(make_render_settings(o, p.s)) ? clamp_compensation_choice::on
                                                                                  : clamp_compensation_choice::off;
          r.label = series_label(m, r.compensation, both);
          if (std::find(labels.begin(), labels.end(), r.label) == labels.end()) labels.push_back(r.label);
          r.vs_vpl = against(img, ref_vpl);
          r.vs_gather = against(img, ref_gather);
          r.vs_exact = against(img, ref_exact);
          r.mean = image_mean(img);
          if (!band.empty()) r.band_mean = speed_vs_error::band_mean(img, band);
          std::cout << r.label << " samples " << n << " seed " << seed << ": " << fixed(r.total_ms, 1)
                    << " ms, RMSE vs VPL sum " << sci(r.vs_vpl.rmse) << ", vs gathering " << sci(r.vs_gather.rmse)
                    << ", vs exact " << sci(r.vs_exact.rmse) << std::endl;
          rows.push_back(r);
          if (so.seeds.size() >= 2) group.push_back(img);
        }
        if (group.size() >= 2) {
          const double nan = std::numeric_limits<double>::quiet_NaN();
          const speed_vs_error::bias_variance a =
              ref_vpl.img.rgb.empty() ? speed_vs_error::bias_variance{nan, nan} : speed_vs_error::split(group, ref_vpl.img);
          const speed_vs_error::bias_variance g = ref_gather.img.rgb.empty()
                                                      ? speed_vs_error::bias_variance{nan, nan}
                                                      : speed_vs_error::split(group, ref_gather.img);
          const speed_vs_error::bias_variance e = ref_exact.img.rgb.empty()
                                                      ? speed_vs_error::bias_variance{nan, nan}
                                                      : speed_vs_error::split(group, ref_exact.img);
          const double variance = !std::isnan(a.variance) ? a.variance : !std::isnan(g.variance) ? g.variance : e.variance;
          const run_row& last = rows.back();
          bv_rows.push_back({m, last.label, last.compensation, n, static_cast<int>(group.size()), variance, a.bias2,
                             g.bias2, e.bias2});
        }
      }

    // CSV
    std::ostringstream csv;
    csv << "scene,backend,method,samples,seed,width,height,dprsm,voxels,eps,local_combination,gbg_accumulator,"
           "cdf_search,visibility,prepare_ms,build_ms,estimate_ms,total_ms,wall_ms,rmse_vplsum,relmse_vplsum,rmse_gather,"
           "relmse_gather,rmse_exact,relmse_exact,total_ms_min,repeats,gpu_peak_bytes,clamp_compensation,mean,band_mean,"
           "stages\n";
    for (const run_row& r : rows)
      csv << base_name(p.s.name) << "," << to_string(base.back) << "," << to_string(r.meth) << "," << r.samples << ","
          << r.seed << "," << base.width << "," << base.height << "," << base.dprsm << "," << base.voxels << ","
          << num(base.eps) << "," << to_string(base.local_combination) << "," << to_string(base.gbg_accumulator) << ","
          << to_string(base.cdf_search) << "," << to_string(base.visibility) << "," << num(prepare_ms) << "," << num(r.build_ms) << "," << num(r.estimate_ms) << "," << num(r.total_ms) << ","
          << num(r.wall_ms) << "," << num(r.vs_vpl.rmse) << "," << num(r.vs_vpl.relmse) << "," << num(r.vs_gather.rmse)
          << "," << num(r.vs_gather.relmse) << "," << num(r.vs_exact.rmse) << "," << num(r.vs_exact.relmse) << ","
          << num(r.total_ms_min) << "," << r.repeats << "," << r.gpu_peak_bytes << ","
          << to_string(r.compensation) << "," << num(r.mean) << ","
          << num(r.band_mean) << "," << r.stages << "\n";
    write_text(so.out + ".csv", csv.str());

    if (!bv_rows.empty()) {
      std::ostringstream bv;
      bv << "scene,backend,method,samples,seeds,eps,local_combination,gbg_accumulator,cdf_search,variance,"
            "bias2_vplsum,bias2_gather,bias2_exact,clamp_compensation\n";
      for (const bias_variance_row& r : bv_rows)
        bv << base_name(p.s.name) << "," << to_string(base.back) << "," << to_string(r.meth) << "," << r.samples << ","
           << r.seeds << "," << num(base.eps) << "," << to_string(base.local_combination) << ","
           << to_string(base.gbg_accumulator) << "," << to_string(base.cdf_search) << "," << num(r.variance) << "," << num(r.bias2_vpl) << "," << num(r.bias2_gather) << ","
           << num(r.bias2_exact) << "," << to_string(r.compensation) << "\n";
      write_text(so.out + "_bias_variance.csv", bv.str());
    }

    // Markdown
    std::ostringstream md;
    md << "Scene `" << p.s.name << "`, " << base.width << "x" << base.height << ", DPRSM 2x" << base.dprsm << "x"
       << base.dprsm << ", " << base.voxels << "^3 voxels, backend `" << to_string(base.back) << "`, GL `"
       << b.gl_renderer << "`, eps " << num(base.eps) << ", local combination `" << to_string(base.local_combination)
       << "`, GBG accumulator `" << to_string(base.gbg_accumulator) << "`, CDF search `" << to_string(base.cdf_search)
       << "`. Prepare (G-buffer + DPRSM + voxels, once): " << fixed(prepare_ms, 1) << " ms. References: VPL sum "
       << (!so.ref_vplsum ? "skipped" : ref_vpl.hit ? "from cache" : fixed(ref_vpl.ms, 0) + " ms") << ", gathering at "
       << so.ref_dirs << " dirs "
       << (!so.ref_gather ? "skipped" : ref_gather.hit ? "from cache" : fixed(ref_gather.ms, 0) + " ms")
       << ", exact at " << so.ref_exact_dirs << " dirs "
       << (!so.ref_exact ? "skipped" : ref_exact.hit ? "from cache" : fixed(ref_exact.ms, 0) + " ms")
       << ". Visibility `" << to_string(base.visibility) << "`, lit test `" << to_string(base.lit_test)
       << "`, VPL mode `" << to_string(base.vpl_mode) << "`";
    if (std::find(so.methods.begin(), so.methods.end(), method::ris) != so.methods.end())
      md << ", ris: " << base.candidates << " candidates per sample from `" << to_string(base.candidate_source)
         << "`, spatial reuse " << (base.spatial > 0 ? std::to_string(base.spatial) + " neighbours" : std::string("off"));
    md << ". Image means: VPL sum " << (so.ref_vplsum ? sci(image_mean(ref_vpl.img)) : "-") << ", gathering "
       << (so.ref_gather ? sci(image_mean(ref_gather.img)) : "-") << ", exact "
       << (so.ref_exact ? sci(image_mean(ref_exact.img)) : "-");
    if (so.ref_vplsum && so.ref_gather)
      md << ". Between the references: RMSE " << sci(speed_vs_error::compare(ref_gather.img, ref_vpl.img).rmse);
    if (so.ref_exact && so.ref_vplsum) md << "; VPL sum vs exact " << sci(speed_vs_error::compare(ref_vpl.img, ref_exact.img).rmse);
    if (so.ref_exact && so.ref_gather)
      md << "; gathering vs exact " << sci(speed_vs_error::compare(ref_gather.img, ref_exact.img).rmse);
    if (!band.empty()) {
      std::size_t n = 0;
      for (std::uint8_t m : band) n += m;
      md << ". Junction band (" << num(k_band_voxels) << " voxels): " << n << " pixels, means: VPL sum "
         << (so.ref_vplsum ? sci(speed_vs_error::band_mean(ref_vpl.img, band)) : "-") << ", gathering "
         << (so.ref_gather ? sci(speed_vs_error::band_mean(ref_gather.img, band)) : "-") << ", exact "
         << (so.ref_exact ? sci(speed_vs_error::band_mean(ref_exact.img, band)) : "-");
    }
    md << ". Clamp compensation ";
    if (so.compensations.empty()) md << "`" << to_string(make_render_settings(base, p.s).clamp_compensation) << "`";
    else md << "`" << to_string(so.compensations.front()) << (both ? "` and `" + std::string(to_string(so.compensations.back())) : "") << "`";
    md << " (for global, local, gbg, ris" << (both ? "; METHOD-clamped: without it)" : ")");
    md << ". Times: the median of " << so.repeats << " repeat(s) of each run.\n\n";
    md << "| method | samples | seed | build ms | estimate ms | total ms | mean | band mean | RMSE vs VPL sum | relMSE vs VPL sum | RMSE vs "
          "gathering | relMSE vs gathering | RMSE vs exact | relMSE vs exact |\n"
          "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const run_row& r : rows)
      md << "| " << r.label << " | " << r.samples << " | " << r.seed << " | " << fixed(r.build_ms, 1) << " | "
         << fixed(r.estimate_ms, 1) << " | " << fixed(r.total_ms, 1) << " | " << sci(r.mean) << " | " << sci(r.band_mean) << " | " << sci(r.vs_vpl.rmse) << " | "
         << sci(r.vs_vpl.relmse) << " | " << sci(r.vs_gather.rmse) << " | " << sci(r.vs_gather.relmse) << " | "
         << sci(r.vs_exact.rmse) << " | " << sci(r.vs_exact.relmse) << " |\n";
    write_text(so.out + ".md", md.str());

    const std::string caption = base_name(p.s.name) + " " + std::to_string(base.width) + "x" +
                                std::to_string(base.height) + ", backend " + to_string(base.back) + ", " + b.gl_renderer;
    const std::string scene_line = "Scene `" + p.s.name + "`, " + std::to_string(base.width) + "x" +
                                   std::to_string(base.height) + ", backend `" + to_string(base.back) + "`.";
    const std::vector<std::string> plots =
        write_analysis(rows, labels, so.samples, so.ref_vplsum, so.ref_gather, so.ref_exact, so.ref_dirs, caption,
                       scene_line, so.out);
    std::cout << "wrote " << so.out << ".csv, " << so.out << ".md";
    for (const std::string& f : plots) std::cout << ", " << f;
    std::cout << (bv_rows.empty() ? "" : ", " + so.out + "_bias_variance.csv") << "\n";
    return 0;
  } catch (const usage_error& e) {
    std::cerr << "speed_vs_error: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "speed_vs_error: error: " << e.what() << "\n";
    return 1;
  }
}
