// speed_vs_error: for one scene, every requested method over a sweep of sample counts in one
// process. The scene, G-buffer, DPRSM and voxel grid are prepared once (prepare_buffers) and every
// run reuses them (run_estimator); each run is timed per stage and compared with two references
// (DESIGN 3.8): (a) the exhaustive VPL sum (method reference) and (b) converged gathering (method
// gather at --ref-dirs directions). Writes PREFIX.csv, PREFIX.md and PREFIX.svg.
#include "metrics.hpp"
#include "svg_plot.hpp"

#include "errors.hpp"
#include "exr_io.hpp"
#include "options.hpp"
#include "pipeline.hpp"
#include "scene_setup.hpp"
#include "stage_timer.hpp"

#include <headless_gl/compute.hpp>

#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace vplrender;
namespace fs = std::filesystem;

// The gathering reference's seed: fixed and far from the usual sweep seeds, so the reference's
// random streams are independent of the runs it judges.
constexpr std::uint32_t k_gather_reference_seed = 0x5EED0F1Eu;

const char* k_help = R"(speed_vs_error: error against time for each method on one scene, in one process.

Usage: speed_vs_error [options] [vplrender scene options]

Sweep options:
  --methods LIST     comma-separated methods (default global,local,gbg,gather,mis);
                     any of global local gbg gather mis mis-as-published
  --samples LIST     comma-separated sample counts (default 1,4,16,64). A count n means:
                     global/local/gbg: --vpls n; gather: --dirs n; mis and
                     mis-as-published: --vpls n and --dirs n
  --seeds LIST       comma-separated seeds, each run once per (method, samples) (default 1)
  --ref-dirs N       directions of the converged-gathering reference (default 4096)
  --cache-dir DIR    reference cache (default speed_vs_error_cache); references are EXR files
                     named by a hash of scene, size, DPRSM, voxels, backend, light, camera,
                     --direct, and for the gathering reference its directions and seed
  --out PREFIX       writes PREFIX.csv, PREFIX.md, PREFIX.svg (default speed_vs_error), and
                     with 2 or more seeds PREFIX_bias_variance.csv
  --help             this text

Scene options, passed to vplrender's parser with its defaults and limits (vplrender --help):
  --scene --backend --size --dprsm --voxels --regions --dirs (mis only when not swept) --eps
  --camera --light --paper --direct.  Not allowed: --method --vpls --seed --out --window.

Error metrics, on linear HDR values, over all pixels p and channels c (x = run, r = reference):
  RMSE   = sqrt( mean_{p,c} (x_pc - r_pc)^2 )
  relMSE = mean_{p,c} (x_pc - r_pc)^2 / (r_pc^2 + 1e-2)
Reported against (a) the exhaustive VPL sum (method reference: the estimand of global, local,
gbg) and (b) converged gathering (gather at --ref-dirs, seed 0x5EED0F1E: the estimand of gather
and mis; it differs from (a) by the VPL discretisation and the distance clamp).

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
  for (method m : {method::global, method::local, method::gbg, method::gather, method::mis, method::mis_as_published})
    if (t == to_string(m)) return m;
  if (t == "reference") bad("--methods: 'reference' is the reference (always computed), not a swept method");
  bad("--methods: unknown method '" + t + "'");
}

struct sweep_options {
  std::vector<method> methods{method::global, method::local, method::gbg, method::gather, method::mis};
  std::vector<int> samples{1, 4, 16, 64};
  std::vector<std::uint32_t> seeds{1};
  int ref_dirs = 4096;
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
    } else if (a == "--ref-dirs") {
      so.ref_dirs = static_cast<int>(to_int(a, value(), 1, limits::max_dirs));
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
  return true;
}

std::string num(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
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
  if (kind == "gather") k += "|dirs=" + std::to_string(dirs) + "|seed=" + std::to_string(seed);
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

reference_image get_reference(const options& base, const prepared_scene& p, const pipeline_buffers& b,
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
  o.meth = kind == "gather" ? method::gather : method::reference;
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
  int samples = 0;
  std::uint32_t seed = 0;
  double build_ms = 0, estimate_ms = 0, total_ms = 0, wall_ms = 0;
  std::string stages;
  speed_vs_error::image_error vs_vpl, vs_gather;
};

struct bias_variance_row {
  method meth;
  int samples = 0, seeds = 0;
  double variance = 0, bias2_vpl = 0, bias2_gather = 0;
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
  char b[40];
  std::snprintf(b, sizeof b, "%.3e", v);
  return b;
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
    const pipeline_buffers b = prepare_buffers(base, p, prep_timer, prep_det);
    double prepare_ms = 0.0;
    for (const stage_time& st : prep_timer.stages()) prepare_ms += st.ms;
    std::cout << "scene " << p.s.name << ", " << base.width << "x" << base.height << ", DPRSM 2x" << base.dprsm << "^2, "
              << base.voxels << "^3 voxels, backend " << to_string(base.back) << "\nGL: " << b.gl_renderer
              << "\nprepare (G-buffer, DPRSM, voxels): " << num(prepare_ms) << " ms" << std::endl;

    const reference_image ref_vpl = get_reference(base, p, b, so.cache_dir, "vplsum", 0, 0);
    const reference_image ref_gather = get_reference(base, p, b, so.cache_dir, "gather", so.ref_dirs, k_gather_reference_seed);

    std::vector<run_row> rows;
    std::vector<bias_variance_row> bv_rows;
    for (method m : so.methods)
      for (int n : so.samples) {
        std::vector<image_rgb> group;  // this (method, samples) over the seeds
        for (std::uint32_t seed : so.seeds) {
          options o = base;
          o.meth = m;
          o.seed = seed;
          if (m == method::gather) o.dirs = n;
          else o.vpls = n;
          if (m == method::mis || m == method::mis_as_published) o.dirs = n;
          stage_timer t;
          nlohmann::json det;
          const auto start = std::chrono::steady_clock::now();
          const image_rgb img = run_estimator(o, p, b, t, {}, det).image;
          run_row r;
          r.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
          r.meth = m;
          r.samples = n;
          r.seed = seed;
          for (const stage_time& st : t.stages()) {
            (st.name.rfind("estimate", 0) == 0 ? r.estimate_ms : r.build_ms) += st.ms;
            r.stages += (r.stages.empty() ? "" : "|") + st.name + "=" + num(st.ms);
          }
          r.total_ms = r.build_ms + r.estimate_ms;
          r.vs_vpl = speed_vs_error::compare(img, ref_vpl.img);
          r.vs_gather = speed_vs_error::compare(img, ref_gather.img);
          std::cout << to_string(m) << " samples " << n << " seed " << seed << ": " << fixed(r.total_ms, 1)
                    << " ms, RMSE vs VPL sum " << sci(r.vs_vpl.rmse) << ", vs gathering " << sci(r.vs_gather.rmse)
                    << std::endl;
          rows.push_back(r);
          if (so.seeds.size() >= 2) group.push_back(img);
        }
        if (group.size() >= 2) {
          const speed_vs_error::bias_variance a = speed_vs_error::split(group, ref_vpl.img);
          const speed_vs_error::bias_variance g = speed_vs_error::split(group, ref_gather.img);
          bv_rows.push_back({m, n, static_cast<int>(group.size()), a.variance, a.bias2, g.bias2});
        }
      }

    // CSV
    std::ostringstream csv;
    csv << "scene,backend,method,samples,seed,width,height,dprsm,voxels,prepare_ms,build_ms,estimate_ms,total_ms,"
           "wall_ms,rmse_vplsum,relmse_vplsum,rmse_gather,relmse_gather,stages\n";
    for (const run_row& r : rows)
      csv << base_name(p.s.name) << "," << to_string(base.back) << "," << to_string(r.meth) << "," << r.samples << ","
          << r.seed << "," << base.width << "," << base.height << "," << base.dprsm << "," << base.voxels << ","
          << num(prepare_ms) << "," << num(r.build_ms) << "," << num(r.estimate_ms) << "," << num(r.total_ms) << ","
          << num(r.wall_ms) << "," << num(r.vs_vpl.rmse) << "," << num(r.vs_vpl.relmse) << "," << num(r.vs_gather.rmse)
          << "," << num(r.vs_gather.relmse) << "," << r.stages << "\n";
    write_text(so.out + ".csv", csv.str());

    if (!bv_rows.empty()) {
      std::ostringstream bv;
      bv << "scene,backend,method,samples,seeds,variance,bias2_vplsum,bias2_gather\n";
      for (const bias_variance_row& r : bv_rows)
        bv << base_name(p.s.name) << "," << to_string(base.back) << "," << to_string(r.meth) << "," << r.samples << ","
           << r.seeds << "," << num(r.variance) << "," << num(r.bias2_vpl) << "," << num(r.bias2_gather) << "\n";
      write_text(so.out + "_bias_variance.csv", bv.str());
    }

    // Markdown
    std::ostringstream md;
    md << "Scene `" << p.s.name << "`, " << base.width << "x" << base.height << ", DPRSM 2x" << base.dprsm << "x"
       << base.dprsm << ", " << base.voxels << "^3 voxels, backend `" << to_string(base.back) << "`, GL `"
       << b.gl_renderer << "`. Prepare (G-buffer + DPRSM + voxels, once): " << fixed(prepare_ms, 1)
       << " ms. References: VPL sum " << (ref_vpl.hit ? "from cache" : fixed(ref_vpl.ms, 0) + " ms")
       << ", gathering at " << so.ref_dirs << " dirs " << (ref_gather.hit ? "from cache" : fixed(ref_gather.ms, 0) + " ms")
       << ". Between the references: RMSE " << sci(speed_vs_error::compare(ref_gather.img, ref_vpl.img).rmse) << ".\n\n";
    md << "| method | samples | seed | build ms | estimate ms | total ms | RMSE vs VPL sum | relMSE vs VPL sum | RMSE vs "
          "gathering | relMSE vs gathering |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const run_row& r : rows)
      md << "| " << to_string(r.meth) << " | " << r.samples << " | " << r.seed << " | " << fixed(r.build_ms, 1) << " | "
         << fixed(r.estimate_ms, 1) << " | " << fixed(r.total_ms, 1) << " | " << sci(r.vs_vpl.rmse) << " | "
         << sci(r.vs_vpl.relmse) << " | " << sci(r.vs_gather.rmse) << " | " << sci(r.vs_gather.relmse) << " |\n";
    write_text(so.out + ".md", md.str());

    // SVG: per method, the mean over seeds of time and error at each sample count.
    std::vector<speed_vs_error::panel> panels(2);
    panels[0].title = "RMSE vs exhaustive VPL sum";
    panels[1].title = "RMSE vs converged gathering (" + std::to_string(so.ref_dirs) + " dirs)";
    for (auto& pn : panels) {
      pn.x_label = "time per frame, ms (build + estimate)";
      pn.y_label = "RMSE (linear HDR)";
    }
    for (method m : so.methods) {
      speed_vs_error::series a{to_string(m), {}, {}}, g{to_string(m), {}, {}};
      for (int n : so.samples) {
        double t = 0, ea = 0, eg = 0;
        int c = 0;
        for (const run_row& r : rows)
          if (r.meth == m && r.samples == n) t += r.total_ms, ea += r.vs_vpl.rmse, eg += r.vs_gather.rmse, ++c;
        if (c == 0) continue;
        a.x.push_back(t / c), a.y.push_back(ea / c), g.x.push_back(t / c), g.y.push_back(eg / c);
      }
      panels[0].lines.push_back(a);
      panels[1].lines.push_back(g);
    }
    const std::string caption = base_name(p.s.name) + " " + std::to_string(base.width) + "x" +
                                std::to_string(base.height) + ", backend " + to_string(base.back) + ", " + b.gl_renderer;
    write_text(so.out + ".svg", speed_vs_error::svg_loglog(panels, caption));
    std::cout << "wrote " << so.out << ".csv, " << so.out << ".md, " << so.out << ".svg"
              << (bv_rows.empty() ? "" : ", " + so.out + "_bias_variance.csv") << "\n";
    return 0;
  } catch (const usage_error& e) {
    std::cerr << "speed_vs_error: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "speed_vs_error: error: " << e.what() << "\n";
    return 1;
  }
}
