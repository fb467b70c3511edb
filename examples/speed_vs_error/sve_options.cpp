// SPDX-License-Identifier: MIT
#include "sve_options.hpp"

#include "io/errors.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdlib>
#include <optional>
#include <sstream>

namespace speed_vs_error {

using namespace vplrender;

const char* const k_help = R"(speed_vs_error: error against time for each method on one scene, in one process.

Usage: speed_vs_error [options] [vplrender scene options]

Sweep options:
  --methods LIST     comma-separated methods (default global,local,gbg,gather,mis);
                     any of global local gbg gather mis mis-as-published exact ris ris-mis
  --samples LIST     comma-separated sample counts (default 1,4,16,64). A count n means:
                     global/local/gbg/ris: --vpls n; gather, exact: --dirs n; mis,
                     mis-as-published and ris-mis: --vpls n and --dirs R n (R from
                     --dirs-per-sample)
  --dirs-per-sample R
                     gathering directions per VPL sample of mis, mis-as-published and
                     ris-mis (default 1; 1..65536, R times the largest count at most 65536):
                     how the samples are shared between the two strategies. Gathering is the
                     better strategy where the indirect light comes from large, smoothly lit
                     surfaces, VPL sampling where it comes from small bright ones
  --seeds LIST       comma-separated seeds, each run once per (method, samples) (default 1)
  --clamp-compensation LIST
                     off, on or off,on: the VPL clamp's compensation for global, local,
                     gbg and ris (vplrender --clamp-compensation; default: vplrender's, on on
                     both backends). With both, each of these methods runs twice and its
                     clamped runs are labelled METHOD-clamped (column clamp_compensation)
  --ref-dirs N       directions of the converged-gathering reference (default 4096)
  --ref-exact-dirs N directions of the exact reference (default 4096)
  --ref-noise on|off measure the gathering and exact references' own noise by rendering each
                     a second time (same directions, seeds 0x5EED2F1E and 0x5EED2E4A; cached
                     like them) and report the errors against them with it removed: the
                     "net" columns, which the plots and Pareto tables use (default on)
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
  --scene --backend --size --dprsm --voxels --regions --global-subset --local-subset
  --dirs (mis only when not swept) --eps --dmin
  --local-combination --gbg-accumulator --cdf-search --visibility --voxel-contract --lit-test --vpl-mode
  --camera --light
  --candidates --candidate-source (ris, ris-mis) --spatial (ris, ris-mis) --candidate-pool (ris-mis)
  --tiles --tile-points --tile-block (ris-mis with --candidate-source tiles)
  --clamp-compensation-dirs
  --paper --direct.
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

With --ref-noise on, r2 = the reference's second render, v_pc = (r_pc - r2_pc)^2 / 2 (an unbiased
estimate of the reference's variance per pixel and channel), m_pc = (r_pc + r2_pc) / 2, and
  net MSE    = mean_{p,c} ((x_pc - r_pc)^2 - v_pc)            (RMSE net = its root, 0 if not > 0)
  net relMSE = mean_{p,c} ((x_pc - r_pc)^2 - v_pc) / (m_pc^2 + 1e-2)           (signed)
the error against the truth rather than against a noisy estimate of it (E[(x - r)^2] =
E[(x - t)^2] + Var(r) for a run x independent of r): without it every method's error has the
reference's noise as a floor. The MSE is unbiased; the relMSE divides by m, symmetric in r and
r2, so that r's noise cancels in expectation to second order. The bias-variance CSV gets
bias2_gather_net and bias2_exact_net (bias2 - mean_{p,c} v_pc) the same way.

Bias/variance (2 or more seeds S, per method and sample count; m = mean image over the seeds):
  variance = mean_{p,c} sum_s (x_s,pc - m_pc)^2 / (S - 1)   (per-run variance, unbiased)
  bias2    = mean_{p,c} (m_pc - r_pc)^2 - variance / S      (unbiased; may be slightly negative)
so that the expected MSE of one run against r is bias2 + variance.

Times (ms): prepare = G-buffer + DPRSM + voxel grid, once for all runs (not in the totals);
per run, each estimator stage as vplrender reports it (GPU timer queries for GPU stages,
steady_clock for CPU ones); build = all stages but 'estimate*'; total = build + estimate.

Exit status: 0 success, 1 bad input or failed output, 2 bad command line.
)";

namespace {

[[noreturn]] void bad(const std::string& m) { throw usage_error(m); }

std::vector<std::string> split_list(const std::string& s) {
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

}  // namespace

method parse_swept_method(const std::string& t) {
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

// Own flags here (CLI11); the rest, in their order, go to vplrender's parser (its validation,
// defaults and limits).
bool parse_sweep_options(const std::vector<std::string>& args, sweep_options& so) {
  CLI::App app;
  app.name(args.empty() ? std::string("speed_vs_error") : args[0]);
  app.set_help_flag();  // k_help is the help text
  app.allow_extras();
  bool help = false;
  std::optional<std::string> methods, samples, seeds, compensations, ref_dirs, ref_exact_dirs, ref_noise, references,
      repeats, dirs_per_sample;
  app.add_flag("-h,--help", help);
  app.add_option("--methods", methods);
  app.add_option("--samples", samples);
  app.add_option("--seeds", seeds);
  app.add_option("--dirs-per-sample", dirs_per_sample);
  app.add_option("--clamp-compensation", compensations);
  app.add_option("--ref-dirs", ref_dirs);
  app.add_option("--ref-exact-dirs", ref_exact_dirs);
  app.add_option("--ref-noise", ref_noise);
  app.add_option("--references", references);
  app.add_option("--replot", so.replot);
  app.add_option("--repeats", repeats);
  app.add_option("--cache-dir", so.cache_dir);
  app.add_option("--out", so.out);
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  if (argv.empty()) argv.push_back("speed_vs_error");
  try {
    app.parse(static_cast<int>(argv.size()), argv.data());
  } catch (const CLI::ParseError& e) {
    bad(explain_parse_error(e.what()));  // vplrender's words for CLI11's messages
  }
  if (help) return false;

  if (methods) {
    so.methods.clear();
    for (const std::string& t : split_list(*methods)) so.methods.push_back(parse_swept_method(t));
  }
  if (samples) {
    so.samples.clear();
    for (const std::string& t : split_list(*samples))
      so.samples.push_back(static_cast<int>(to_int("--samples", t, 1, limits::max_dirs)));
  }
  if (seeds) {
    so.seeds.clear();
    for (const std::string& t : split_list(*seeds))
      so.seeds.push_back(static_cast<std::uint32_t>(to_int("--seeds", t, 0, 4294967295LL)));
  }
  if (dirs_per_sample) {
    so.dirs_per_sample = static_cast<int>(to_int("--dirs-per-sample", *dirs_per_sample, 1, limits::max_dirs));
    const int largest = *std::max_element(so.samples.begin(), so.samples.end());
    if (static_cast<long long>(so.dirs_per_sample) * largest > limits::max_dirs)
      bad("--dirs-per-sample: " + std::to_string(so.dirs_per_sample) + " directions per sample at --samples " +
          std::to_string(largest) + " exceed " + std::to_string(limits::max_dirs) + " directions");
  }
  if (compensations) {
    so.compensations.clear();
    for (const std::string& t : split_list(*compensations)) {
      if (t != "off" && t != "on") bad("--clamp-compensation: unknown value '" + t + "' (off, on or off,on)");
      const clamp_compensation_choice c = t == "on" ? clamp_compensation_choice::on : clamp_compensation_choice::off;
      if (std::find(so.compensations.begin(), so.compensations.end(), c) == so.compensations.end())
        so.compensations.push_back(c);
    }
  }
  if (ref_dirs) so.ref_dirs = static_cast<int>(to_int("--ref-dirs", *ref_dirs, 1, limits::max_dirs));
  if (ref_exact_dirs) so.ref_exact_dirs = static_cast<int>(to_int("--ref-exact-dirs", *ref_exact_dirs, 1, limits::max_dirs));
  if (ref_noise) {
    if (*ref_noise != "on" && *ref_noise != "off") bad("--ref-noise: unknown value '" + *ref_noise + "' (on or off)");
    so.ref_noise = *ref_noise == "on";
  }
  if (references) {
    const std::string& v = *references;
    so.ref_vplsum = so.ref_gather = so.ref_exact = false;
    if (v == "all") so.ref_vplsum = so.ref_gather = so.ref_exact = true;
    else if (v == "both") so.ref_vplsum = so.ref_gather = true;
    else if (v != "none")
      for (const std::string& t : split_list(v)) {
        if (t == "vplsum") so.ref_vplsum = true;
        else if (t == "gather") so.ref_gather = true;
        else if (t == "exact") so.ref_exact = true;
        else bad("--references: unknown reference '" + t + "' (vplsum, gather, exact, all, both or none)");
      }
  }
  if (repeats) so.repeats = static_cast<int>(to_int("--repeats", *repeats, 1, 1000));

  std::vector<std::string> pass{"speed_vs_error"};
  for (const std::string& a : app.remaining()) {
    const std::string flag = a.substr(0, a.find('='));
    if (flag == "--method" || flag == "--vpls" || flag == "--seed" || flag == "--window")
      bad(flag + ": not allowed here (the sweep sets it; see --methods, --samples, --seeds)");
    pass.push_back(a);
  }
  if (so.methods.empty() || so.samples.empty() || so.seeds.empty()) bad("--methods, --samples, --seeds: empty list");
  parse_result r = parse_command_line(pass);
  if (r.what == parse_result::action::help) return false;
  so.base = r.opts;
  so.base.progress = progress_mode::never;
  // The exhaustive VPL sum follows the last listed setting (on for off,on): the estimand of the
  // runs it labels with the method's own name.
  if (!so.compensations.empty()) so.base.clamp_compensation = so.compensations.back();
  if (so.base.back == backend::gpu)
    for (method m : so.methods)
      if (!traits(m).gpu)
        bad(std::string("--methods ") + to_string(m) + ": runs on --backend cpu only for now (its GPU kernels are not written yet)");
  return true;
}

}  // namespace speed_vs_error
