// SPDX-License-Identifier: MIT
#include "cli/options.hpp"

#include "io/errors.hpp"
#include "render/method_traits.hpp"
#include "scene/scene.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>

namespace vplrender {

const char* to_string(progress_mode p) {
  return p == progress_mode::always ? "always" : p == progress_mode::never ? "never" : "auto";
}

namespace {

std::string replace_extension(const std::string& out, const char* ext) { return out.substr(0, out.size() - 4) + ext; }

struct raw_values {
  std::string scene, meth, back, size, vpls, seed, out, regions, global_subset, local_subset, dirs, eps, dmin, voxels, dprsm, cam, light, exposure, progress, frames,
      window_script, local_combination, gbg_accumulator, cdf_search,
      face_selection, sampler, visibility, vpl_mode, lit_test, voxel_contract, clamp_compensation, clamp_compensation_pass, clamp_compensation_dirs, candidates, candidate_source, spatial, candidate_pool, tiles, tile_points, tile_block;
  bool paper = false, direct = false, window = false;
};

// Word-wraps at `width` columns; CLI11 indents continuation lines to the description column.
std::string wrap(const std::string& text, std::size_t width = 62) {
  std::string out, line;
  std::size_t i = 0;
  while (i < text.size()) {
    const std::size_t j = std::min(text.find(' ', i), text.size());
    const std::string word = text.substr(i, j - i);
    if (!line.empty() && line.size() + 1 + word.size() > width) {
      out += line + "\n";
      line.clear();
    }
    line += (line.empty() ? "" : " ") + word;
    i = j + 1;
  }
  return out + line;
}

// --method's help: one clause per row of render/method_traits.cpp.
std::string method_help() {
  std::string clauses;
  for (const method_traits& t : all_method_traits())
    clauses += (clauses.empty() ? "" : "; ") + std::string(t.name) + " = " + t.help;
  return "Estimator (default " + std::string(to_string(options().meth)) + "): " + clauses + ".";
}

void build_app(CLI::App& app, raw_values& v) {
  app.description(wrap(
      "vplrender: one-bounce diffuse global illumination with virtual point lights stored in a dual "
      "paraboloid reflective shadow map, selected by inverse transform sampling (vplkit example).", 96));
  app.get_formatter()->column_width(34);
  const auto d = [](const char* text) { return wrap(text); };
  app.add_option("--scene", v.scene, d("Scene: the built-in 'cornell' (closed box, default) or 'open', or an OBJ file "
                                     "(with its MTL and textures). Use ./cornell for a file of that name."))
      ->type_name("cornell|open|FILE.obj");
  app.add_option("--method", v.meth, wrap(method_help()))->type_name(method_names());
  app.add_option("--backend", v.back, d("gpu (default) or cpu. Both rasterise the G-buffer and the DPRSM on OpenGL "
                                      "(headless). gpu: everything after that runs as compute shaders from the GLSL "
                                      "pack: voxelisation, the builders' weights (global, local, GBG with its hole "
                                      "fill), the CDFs, the estimator of every method and the direct light. cpu: the "
                                      "C++ templates on all cores (voxelisation, builders, CDFs, estimators)."))
      ->type_name("gpu|cpu");
  app.add_option("--size", v.size, d("Image size (default 512x512; each side 1..16384, at most 2^26 pixels)."))
      ->type_name("WxH");
  app.add_option("--vpls", v.vpls, d("VPL samples per gather point (default 64; 1..1048576)."))->type_name("N");
  app.add_option("--seed", v.seed, d("Random seed (default 1; 0..4294967295)."))->type_name("N");
  app.add_option("--out", v.out, d("Output OpenEXR file (default vplrender.exr); the PNG preview and the JSON "
                                 "report are written beside it with .png and .json."))
      ->type_name("FILE.exr");
  app.add_option("--regions", v.regions, d("Image regions of the local CDF method (default 4 = 2x2; 1..1024; "
                                         "laid out as the most nearly square grid)."))
      ->type_name("N");
  app.add_option("--global-subset", v.global_subset,
                 d("Gather points whose mean unshadowed contribution weighs each texel of the global CDF (|S|, "
                   "default 256; 1..65536; stratified over the image): its build costs |S| contributions per "
                   "texel. For --method global and --candidate-source global."))
      ->type_name("N");
  app.add_option("--local-subset", v.local_subset,
                 d("The same per image region for the local CDFs (|S_i|, default 256; 1..65536, at most 2^22 "
                   "with --regions in all): --regions x N contributions per texel. For --method local and "
                   "--candidate-source local."))
      ->type_name("N");
  app.add_option("--dirs", v.dirs, d("Cosine-distributed gathering directions per gather point for gbg, gather, "
                                   "mis and ris-mis (default 16; 1..65536)."))
      ->type_name("N");
  app.add_option("--eps", v.eps, d("Defensive mixing weight: p = (1-eps) p_cdf + eps p_uniform (default 0.05; "
                                 "0..1; 0 reproduces the paper)."))
      ->type_name("X");
  app.add_option("--dmin", v.dmin, d("VPL distance clamp as a fraction of the scene's diagonal (default 0.01; "
                                   "0..1; 0 = no clamp): every VPL contribution, and the exhaustive reference, "
                                   "uses max(distance, dmin) in 1/d^2 (docs/math.md section 2): a bias that "
                                   "bounds the VPL strategy's variance near surfaces."))
      ->type_name("X");
  app.add_option("--local-combination", v.local_combination,
                 d("How --method local combines its N region CDFs (default balance): balance = each sample "
                   "divided by the sum of the N pmfs (the mixture; unbiased wherever any CDF covers the VPL); "
                   "average = each sample divided by N times the pmf of the CDF that drew it (the paper's; "
                   "unbiased only where every CDF covers the VPL, more noise at region borders)."))
      ->type_name("balance|average");
  app.add_option("--gbg-accumulator", v.gbg_accumulator,
                 d("Value each lit GBG ray adds to its texel's weight, for gbg, mis and mis-as-published (default "
                   "gathering): gathering = luminance of the gathering estimator's value rho_x L_o(y); paper = "
                   "luminance of the VPL's contribution to the gather point (eq. 5, clamped at dmin)."))
      ->type_name("gathering|paper");
  app.add_option("--cdf-search", v.cdf_search,
                 d("How every CDF sample is searched (default guide): guide = guide table (cutpoint method) then "
                   "at most a short binary search; binary = plain binary search over the whole CDF. Both return "
                   "the same index for every u, so the image is identical: this measures the search's cost."))
      ->type_name("guide|binary");
  app.add_option("--face-selection", v.face_selection,
                 d("How a VPL distribution chooses between the two paraboloids (default joint): joint = one CDF "
                   "over both faces' texels; roulette = the paper's Alg. 1, the face by its share of the weight, "
                   "then the texel within it. Same pmf; a sample may land on another texel for the same u."))
      ->type_name("joint|roulette");
  app.add_option("--sampler", v.sampler,
                 d("How a VPL distribution turns u into a texel (default auto: share-tree for global, gbg, local, "
                   "mis and mis-as-published with --face-selection joint and --cdf-search guide, else cdf): cdf = "
                   "inversion of the discrete "
                   "CDF (keeps the stratification of u); alias = Walker's alias table, O(1) (same pmf, does not "
                   "keep u's stratification; one u per draw, so at large DPRSMs its thresholds are coarse: "
                   "docs/results/notes/2026-11-21-paper-analogues.md 4.6). alias needs --face-selection joint and --cdf-search guide. "
                   "share-tree = the learned part drawn by descending a binary tree of quantised shares, one 24-bit "
                   "number per level from a stream of its own (same pmf up to 2^-24 per level; the CPU and GPU "
                   "images agree at large DPRSMs, where the flat CDF turns the backends' last-bit weight "
                   "differences into other draws: docs/math.md, \"Image parity at large DPRSMs\"). share-tree "
                   "needs --method global, gbg, local, mis or mis-as-published, --face-selection joint and --cdf-search guide."))
      ->type_name("auto|cdf|alias|share-tree");
  app.add_option("--visibility", v.visibility,
                 d("What visibility and the gathering rays are decided against, for every method (default "
                   "exact with --backend gpu, voxels with --backend cpu; --paper: paper-voxels): voxels = the "
                   "triangles listed by the voxel grid (--voxels; no self-occlusion where surfaces meet); "
                   "paper-voxels = the paper's binary voxel test and voxel "
                   "tracer (dark seams at junctions); exact = the scene's triangles, through Embree on the CPU "
                   "backend and the GLSL pack's BVH (built on the host, uploaded once per frame) on the GPU backend. "
                   "--method exact always uses exact rays."))
      ->type_name("voxels|paper-voxels|exact");
  app.add_option("--lit-test", v.lit_test,
                 d("How gathering (gather, mis) decides that the light reaches a hit (default shadow-ray with "
                   "--visibility exact, else shadow-map): shadow-map = the DPRSM's test against its texel's "
                   "plane (the paper's); shadow-ray = a ray from the hit to the light, through the exact "
                   "visibility (needs --visibility exact). docs/math.md section 4.1."))
      ->type_name("shadow-map|shadow-ray");
  app.add_option("--voxel-contract", v.voxel_contract,
                 d("What --visibility voxels answers (default plane-rule): plane-rule = segment ends left "
                   "where they are, triangles whose planes pass within 0.01 voxel of an end ignored, hits "
                   "shaded with their triangle's plane normal; exact = --visibility exact's contract on the "
                   "triangles the grid lists (ends moved by exact's offset, every triangle counts, hits "
                   "shaded with the interpolated shading normal). CPU backend only. docs/math.md section 7.2."));
  app.add_option("--vpl-mode", v.vpl_mode,
                 d("What a VPL is, for every method that uses VPLs (reference, global, local, gbg, mis, "
                   "mis-as-published, ris, ris-mis; default patch): patch = a point drawn uniformly over its texel's patch "
                   "with that point's own solid angle, so every method estimates the same continuous one-bounce "
                   "integral as gather and exact; point = the paper's VPL at the texel centre, whose VPL sum is "
                   "a midpoint rule of it (docs/math.md section 11). --paper selects point."))
      ->type_name("point|patch");
  app.add_option("--clamp-compensation", v.clamp_compensation,
                 d("Add back what the VPL clamp --dmin removes, for reference, global, local, gbg and ris (default on; "
                   "both backends): a short gathering ray per 16 VPL samples (--clamp-compensation-dirs) adds the near field the clamp weighs down, so the "
                   "estimate converges to the unclamped integral without its fireflies (docs/math.md, \"The clamp's compensation\"). "
                   "off = the clamped estimate, a documented bias near surfaces."))
      ->type_name("off|on");
  app.add_option("--clamp-compensation-pass", v.clamp_compensation_pass,
                 d("GPU backend: where the clamp compensation is computed, the same image either way (docs/renderer.md, "
                   "\"The clamp compensation's passes\"): compacted (default) = passes of its own over the list of the "
                   "pixels with another surface within dmin, in full SIMD groups; inline = in the estimate kernel, whose "
                   "SIMD groups run it whenever one of their pixels needs it."))
      ->type_name("compacted|inline");
  app.add_option("--clamp-compensation-dirs", v.clamp_compensation_dirs,
                 d("Directions of the clamp compensation per pixel, for global, local, gbg and ris (not reference, "
                   "which takes 256): auto (default, the measured rule of docs/results/clamp_compensation.md), N = N "
                   " whatever --vpls, 1:K = one per K VPL samples rounded up. Any choice estimates the "
                   "same; fewer directions cost less and add more of the term's own noise."))
      ->type_name("auto|N|1:K");
  app.add_option("--candidates", v.candidates,
                 d("--method ris and ris-mis: candidate VPLs per sample (default 32; 1..65536), each weighed by its "
                   "unshadowed contribution (ris-mis: its MIS-weighted contribution against --dirs gathering, the "
                   "weights counting each sample as max(1, M/2) VPL samples); --vpls samples per pixel, one "
                   "visibility query each."))
      ->type_name("M");
  app.add_option("--candidate-source", v.candidate_source,
                 d("--method ris and ris-mis: the distribution the candidates are drawn from (default flux): flux (each VPL by its "
                   "flux: light-power sampling, no view, nothing to build), or what global, local (the CDF of the "
                   "pixel's region) and gbg build, with --eps (docs/results.md, RIS, compares them); tiles "
                   "(--method ris-mis): per image tile (--tiles) a CDF over blocks of texels "
                   "(--tile-block), each block weighed by its mean unshadowed contribution to --tile-points "
                   "of the tile's gather points, times the flux within the block, with --eps."))
      ->type_name("global|local|gbg|flux|tiles");
  app.add_option("--tiles", v.tiles,
                 d("--candidate-source tiles: image tiles, each with its own candidate distribution and pool "
                   "(default 64; 1..1024; the most nearly square grid, which must fit the image)."))
      ->type_name("N");
  app.add_option("--tile-points", v.tile_points,
                 d("--candidate-source tiles: gather points per tile that weigh its texel blocks (default 8; "
                   "1..65536, stratified over the tile)."))
      ->type_name("N");
  app.add_option("--tile-block", v.tile_block,
                 d("--candidate-source tiles: side of the texel blocks, in texels of one paraboloid face "
                   "(default 8; 1..64). Within a block the candidates follow the flux."))
      ->type_name("B");
  app.add_option("--spatial", v.spatial,
                 d("--method ris and ris-mis: neighbours whose reservoirs each pixel reuses, unbiased (default 0 = "
                   "off; 0..16; docs/math.md section 13; ris-mis: over its MIS-weighted target)."))
      ->type_name("K");
  app.add_option("--candidate-pool", v.candidate_pool,
                 d("--method ris-mis: draw the candidates from a pool of P VPLs presampled once per frame from "
                   "--candidate-source (default 16384, 1 MiB; 0 = off: each candidate its own draw; 0..4194304; per region "
                   "with local). The same estimate, unbiased (docs/math.md, \"Presampled candidates\"); a candidate costs "
                   "a read of one 64-byte record instead of a CDF search and a patch construction."))
      ->type_name("P");
  app.add_option("--voxels", v.voxels, d("Voxel grid resolution per axis for visibility (default 128; 4..1024)."))
      ->type_name("N");
  app.add_option("--dprsm", v.dprsm, d("Paraboloid map resolution per face (default 512, i.e. 2x512x512; 8..4096)."))
      ->type_name("N");
  app.add_option("--camera", v.cam, d("Camera: eye, target, up vector and vertical field of view in degrees (0..180), "
                                    "10 comma-separated numbers. Default: the built-in scene's camera, or for an "
                                    "OBJ one that frames its bounding box from +Z."))
      ->type_name("EX,EY,EZ,TX,TY,TZ,UX,UY,UZ,FOV");
  app.add_option("--light", v.light, d("Point light position, optionally followed by its RGB intensity in W/sr (3 or "
                                     "6 comma-separated numbers). Default: the built-in scene's light, or for an OBJ "
                                     "one placed automatically (see docs/renderer.md)."))
      ->type_name("X,Y,Z[,R,G,B]");
  app.add_flag("--paper", v.paper, d("The paper's parameters: --size 512x512 --dprsm 512 --voxels 128 --vpls 800 "
                                   "--regions 4 --dirs 800 --vpl-mode point --visibility paper-voxels. Flags given explicitly win."));
  app.add_flag("--direct", v.direct, d("Add direct lighting (default: one-bounce indirect only, as in the paper)."));
  app.add_flag("--window", v.window, d("Also show the result in an interactive window (GPU backend; needs a display). "
                                     "Keys: 1-7 reference/global/local/gbg/gather/mis/mis-as-published, 8 exact "
                                     "(when started with --method exact or --visibility exact), M next "
                                     "method, + / - double / halve --vpls (and --dirs for gbg, gather, mis, exact), "
                                     "Esc or Q close. Each change re-renders; the title shows method, samples and "
                                     "the last render time."));
  app.add_option("--frames", v.frames,
                 d("With --window: close after N frames (default 0: when closed by the user; 1..1000000). Without "
                   "--window: render N frames headless in one process (1..10000) with the light moving once around "
                   "a horizontal circle through its position (radius 0.05 of the scene's diagonal; frame 0 is the "
                   "scene's light), after one untimed warm-up frame; the JSON report gets \"frames\" (count, "
                   "median_ms, per-stage medians). Only the last frame's image is written."))
      ->type_name("N");
  app.add_option("--window-script", v.window_script,
                 d("With --window: key actions injected one per frame from the second frame on, comma-separated "
                   "(1-9, m, +, -, q); for tests."))
      ->type_name("K1,K2,...");
  app.add_option("--exposure", v.exposure, d("Exposure multiplier for the PNG preview only (default 1; > 0)."))
      ->type_name("X");
  app.add_option("--progress", v.progress, d("Progress bar on stderr for runs longer than a second: auto (only when "
                                           "stderr is a terminal, default), always, never."))
      ->type_name("auto|always|never");
  app.footer(wrap(
      "Outputs: FILE.exr (linear HDR, float RGB), FILE.png (Reinhard on luminance, sRGB), FILE.json (parameters, GL "
      "renderer, per-stage times). Each is written to a temporary file and renamed.", 96) + "\n" +
             wrap("Exit status: 0 success, 1 bad input or failed output, 2 bad command line, 3 not implemented in this "
                  "build.", 96));
}

[[noreturn]] void bad(const std::string& flag, const std::string& msg) { throw usage_error(flag + ": " + msg); }

long long parse_integer(const std::string& flag, const std::string& text, long long lo, long long hi) {
  const bool digits = !text.empty() && text.size() <= 19 &&
                      std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
  if (!digits)
    bad(flag, "expected a whole number in " + std::to_string(lo) + ".." + std::to_string(hi) + ", got '" + text + "'");
  errno = 0;
  const long long v = std::strtoll(text.c_str(), nullptr, 10);
  if (errno == ERANGE || v < lo || v > hi)
    bad(flag, "value " + text + " is outside " + std::to_string(lo) + ".." + std::to_string(hi));
  return v;
}

// --clamp-compensation-dirs: auto, N (1..max_dirs) or 1:K (K in 1..max_vpls).
clamp_compensation_dirs_choice parse_clamp_compensation_dirs(const std::string& text) {
  const char* flag = "--clamp-compensation-dirs";
  clamp_compensation_dirs_choice c;
  if (text == "auto") return c;
  if (text.rfind("1:", 0) == 0) {
    c.kind = clamp_compensation_dirs_choice::rule::per_vpls;
    c.value = static_cast<int>(parse_integer(flag, text.substr(2), 1, limits::max_vpls));
    return c;
  }
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos)
    bad(flag, "expected auto, a number of directions N or 1:K (one per K VPL samples), got '" + text + "'");
  c.kind = clamp_compensation_dirs_choice::rule::fixed;
  c.value = static_cast<int>(parse_integer(flag, text, 1, limits::max_dirs));
  return c;
}

double parse_real(const std::string& flag, const std::string& text) {
  // strtod, but not "nan"/"inf"/hex: only plain decimal numbers.
  const bool charset = !text.empty() && std::all_of(text.begin(), text.end(), [](char c) {
    return (c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+' || c == 'e' || c == 'E';
  });
  char* end = nullptr;
  const double v = charset ? std::strtod(text.c_str(), &end) : 0.0;
  if (!charset || end != text.c_str() + text.size()) bad(flag, "'" + text + "' is not a number");
  if (!std::isfinite(v) || std::abs(v) > static_cast<double>(std::numeric_limits<float>::max()))
    bad(flag, "'" + text + "' is out of range");
  return v;
}

std::vector<double> parse_list(const std::string& flag, const std::string& text) {
  std::vector<double> out;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = text.find(',', start);
    std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    item.erase(0, item.find_first_not_of(' '));
    item.erase(item.find_last_not_of(' ') + 1);
    out.push_back(parse_real(flag, item));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

template <class E>
E parse_choice(const std::string& flag, const std::string& text, std::initializer_list<std::pair<const char*, E>> choices) {
  std::string list;
  for (const auto& [name, value] : choices) {
    if (text == name) return value;
    list += list.empty() ? name : std::string("|") + name;
  }
  bad(flag, "unknown value '" + text + "' (expected " + list + ")");
}

void parse_size(const std::string& text, int& w, int& h) {
  const std::size_t x = text.find_first_of("xX");
  if (x == std::string::npos) bad("--size", "expected WxH, e.g. 512x512, got '" + text + "'");
  w = static_cast<int>(parse_integer("--size", text.substr(0, x), 1, limits::max_side));
  h = static_cast<int>(parse_integer("--size", text.substr(x + 1), 1, limits::max_side));
  if (static_cast<long long>(w) * h > limits::max_pixels)
    bad("--size", text + " has more than 2^26 pixels");
}

// CLI11's messages, made to lead with the flag and to say plainly what went wrong.
}  // namespace

std::string explain_parse_error(const std::string& message) {
  const std::string& m = message;
  const std::string at_most = ": At Most 1 required but received ";
  if (const std::size_t p = m.find(at_most); p != std::string::npos) return m.substr(0, p) + ": given more than once";
  // CLI11: "--vpls: 1 required N missing" for a flag at the end of the line without its value.
  if (m.rfind("--", 0) == 0 && m.find(" required ") != std::string::npos && m.size() > 8 &&
      m.compare(m.size() - 8, 8, " missing") == 0)
    return m.substr(0, m.find(':')) + ": needs a value";
  const std::string not_expected = "not expected: ";
  if (const std::size_t p = m.find(not_expected); p != std::string::npos) {
    const std::string what = m.substr(p + not_expected.size());
    return (what.rfind("-", 0) == 0 ? "unknown option: " : "unexpected argument: ") + what + " (see --help)";
  }
  return m;
}

std::string options::png_path() const { return replace_extension(out, ".png"); }
std::string options::json_path() const { return replace_extension(out, ".json"); }

void region_grid(int n, int& x, int& y) {
  y = 1;
  for (int d = 1; static_cast<long long>(d) * d <= n; ++d)
    if (n % d == 0) y = d;
  x = n / y;
}

std::string help_text(const std::string& program) {
  CLI::App app;
  raw_values v;
  build_app(app, v);
  app.name(program);
  return app.help();
}

parse_result parse_command_line(const std::vector<std::string>& args) {
  CLI::App app;
  raw_values v;
  build_app(app, v);
  parse_result r;
  app.name(args.empty() ? std::string("vplrender") : args[0]);
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  if (argv.empty()) argv.push_back("vplrender");
  try {
    app.parse(static_cast<int>(argv.size()), argv.data());
  } catch (const CLI::CallForHelp&) {
    r.what = parse_result::action::help;
    r.help = app.help();
    return r;
  } catch (const CLI::ParseError& e) {
    throw usage_error(explain_parse_error(e.what()));
  }
  const auto given = [&](const char* flag) { return app.count(flag) > 0; };

  options& o = r.opts;
  if (given("--scene")) {
    if (v.scene.empty()) bad("--scene", "empty scene name");
    o.scene = v.scene;
  }
  if (given("--method")) {
    const std::optional<method> m = method_from_name(v.meth);
    if (!m) bad("--method", "unknown value '" + v.meth + "' (expected " + method_names() + ")");
    o.meth = *m;
  }
  if (given("--backend")) o.back = parse_choice<backend>("--backend", v.back, {{"gpu", backend::gpu}, {"cpu", backend::cpu}});
  if (given("--progress"))
    o.progress = parse_choice<progress_mode>("--progress", v.progress,
                                             {{"auto", progress_mode::automatic}, {"always", progress_mode::always},
                                              {"never", progress_mode::never}});
  if (given("--local-combination"))
    o.local_combination = parse_choice<local_combination_choice>(
        "--local-combination", v.local_combination,
        {{"balance", local_combination_choice::balance}, {"average", local_combination_choice::average}});
  if (given("--gbg-accumulator"))
    o.gbg_accumulator = parse_choice<gbg_accumulator_choice>(
        "--gbg-accumulator", v.gbg_accumulator,
        {{"gathering", gbg_accumulator_choice::gathering}, {"paper", gbg_accumulator_choice::paper}});
  if (given("--cdf-search"))
    o.cdf_search = parse_choice<cdf_search_choice>("--cdf-search", v.cdf_search,
                                                   {{"guide", cdf_search_choice::guide},
                                                    {"binary", cdf_search_choice::binary}});
  if (given("--face-selection"))
    o.face_selection = parse_choice<face_selection_choice>(
        "--face-selection", v.face_selection,
        {{"joint", face_selection_choice::joint}, {"roulette", face_selection_choice::roulette}});
  if (given("--sampler"))
    o.sampler = parse_choice<sampler_choice>("--sampler", v.sampler,
                                             {{"auto", sampler_choice::automatic},
                                              {"cdf", sampler_choice::cdf},
                                              {"alias", sampler_choice::alias},
                                              {"share-tree", sampler_choice::share_tree}});
  // The library's face roulette samples discrete CDFs, and --cdf-search only concerns the joint CDF.
  if (o.sampler == sampler_choice::alias && o.face_selection == face_selection_choice::roulette)
    throw usage_error("--sampler alias: needs --face-selection joint (the face roulette samples discrete CDFs)");
  if (o.sampler == sampler_choice::share_tree) {
    if (o.face_selection == face_selection_choice::roulette)
      throw usage_error("--sampler share-tree: needs --face-selection joint (the face roulette samples discrete CDFs)");
    // The tree draws from a stream of its own, one position per VPL draw: the estimators whose draws
    // the stream follows (render/method_traits.hpp, draws_share_tree).
    if (!draws_share_tree(traits(o.meth).estimator))
      throw usage_error(std::string("--sampler share-tree: not supported with --method ") + to_string(o.meth) +
                        " (only global, gbg, local, mis and mis-as-published; use --sampler cdf)");
  }
  if (o.cdf_search == cdf_search_choice::binary &&
      ((o.sampler != sampler_choice::cdf && o.sampler != sampler_choice::automatic) ||
       o.face_selection != face_selection_choice::joint))
    throw usage_error("--cdf-search binary: needs --sampler cdf and --face-selection joint");
  o.paper = v.paper;
  // The GPU backend's default is exact visibility: on the GPU the pack's BVH costs less than the
  // voxel march it was to approximate (docs/results/visibility_gpu.md).
  if (o.back == backend::gpu) o.visibility = visibility_choice::exact;
  if (o.paper) o.visibility = visibility_choice::paper_voxels;
  if (given("--visibility"))
    o.visibility = parse_choice<visibility_choice>("--visibility", v.visibility,
                                                   {{"voxels", visibility_choice::voxels},
                                                    {"paper-voxels", visibility_choice::paper_voxels},
                                                    {"exact", visibility_choice::exact}});
  if (given("--voxel-contract")) {
    o.voxel_contract = parse_choice<voxel_contract_choice>("--voxel-contract", v.voxel_contract,
                                                           {{"plane-rule", voxel_contract_choice::plane_rule},
                                                            {"exact", voxel_contract_choice::exact}});
    if (o.voxel_contract == voxel_contract_choice::exact && o.back == backend::gpu)
      throw usage_error("--voxel-contract exact: the GPU backend's voxel march has the plane rule only; use --backend "
                        "cpu, or --visibility exact");
    if (o.visibility != visibility_choice::voxels)
      throw usage_error("--voxel-contract: needs --visibility voxels (it chooses what the voxel march answers)");
  }
  // Rays that answer as exact ones do: the BVH's or Embree's, or the voxel march under the exact contract.
  const bool exact_answers = o.visibility == visibility_choice::exact ||
                             (o.visibility == visibility_choice::voxels && o.voxel_contract == voxel_contract_choice::exact);
  o.lit_test = exact_answers ? lit_test_choice::shadow_ray : lit_test_choice::shadow_map;
  if (given("--lit-test"))
    o.lit_test = parse_choice<lit_test_choice>("--lit-test", v.lit_test,
                                               {{"shadow-map", lit_test_choice::shadow_map},
                                                {"shadow-ray", lit_test_choice::shadow_ray}});
  if (o.lit_test == lit_test_choice::shadow_ray && !exact_answers)
    throw usage_error("--lit-test shadow-ray: needs --visibility exact, or --visibility voxels with --voxel-contract "
                      "exact (the shadow ray is an exact ray)");
  if (o.paper) {
    o.width = o.height = 512;
    o.dprsm = 512;
    o.voxels = 128;
    o.vpls = 800;
    o.regions = 4;
    o.dirs = 800;
    o.vpl_mode = vpl_mode_choice::point;
  }
  if (given("--vpl-mode"))
    o.vpl_mode = parse_choice<vpl_mode_choice>("--vpl-mode", v.vpl_mode,
                                               {{"point", vpl_mode_choice::point}, {"patch", vpl_mode_choice::patch}});
  if (given("--clamp-compensation")) {
    o.clamp_compensation = parse_choice<clamp_compensation_choice>(
        "--clamp-compensation", v.clamp_compensation,
        {{"off", clamp_compensation_choice::off}, {"on", clamp_compensation_choice::on}});
  }
  if (given("--clamp-compensation-pass"))
    o.clamp_compensation_pass = parse_choice<clamp_compensation_pass_choice>(
        "--clamp-compensation-pass", v.clamp_compensation_pass,
        {{"compacted", clamp_compensation_pass_choice::compacted}, {"inline", clamp_compensation_pass_choice::inline_pass}});
  if (given("--clamp-compensation-dirs")) o.clamp_compensation_dirs_rule = parse_clamp_compensation_dirs(v.clamp_compensation_dirs);
  if (given("--candidates"))
    o.candidates = static_cast<int>(parse_integer("--candidates", v.candidates, 1, limits::max_candidates));
  if (given("--candidate-source"))
    o.candidate_source = parse_choice<ris_source_choice>("--candidate-source", v.candidate_source,
                                                         {{"global", ris_source_choice::global},
                                                          {"local", ris_source_choice::local},
                                                          {"gbg", ris_source_choice::gbg},
                                                          {"flux", ris_source_choice::flux},
                                                          {"tiles", ris_source_choice::tiles}});
  if (given("--tiles")) o.tiles = static_cast<int>(parse_integer("--tiles", v.tiles, 1, limits::max_tiles));
  if (given("--tile-points"))
    o.tile_points = static_cast<int>(parse_integer("--tile-points", v.tile_points, 1, limits::max_subset));
  if (given("--tile-block"))
    o.tile_block = static_cast<int>(parse_integer("--tile-block", v.tile_block, 1, limits::max_tile_block));
  if (given("--spatial")) o.spatial = static_cast<int>(parse_integer("--spatial", v.spatial, 0, limits::max_spatial));
  if (given("--candidate-pool"))
    o.candidate_pool =
        static_cast<int>(parse_integer("--candidate-pool", v.candidate_pool, 0, limits::max_candidate_pool));
  if (!traits(o.meth).gpu && o.back == backend::gpu)
    bad(std::string("--method ") + to_string(o.meth),
        "runs on --backend cpu only for now (its GPU kernels are not written yet); add --backend cpu");
  if (given("--size")) parse_size(v.size, o.width, o.height);
  if (given("--vpls")) o.vpls = static_cast<int>(parse_integer("--vpls", v.vpls, 1, limits::max_vpls));
  if (given("--seed")) o.seed = static_cast<std::uint32_t>(parse_integer("--seed", v.seed, 0, 4294967295LL));
  if (given("--regions")) o.regions = static_cast<int>(parse_integer("--regions", v.regions, 1, limits::max_regions));
  if (given("--global-subset"))
    o.global_subset = static_cast<int>(parse_integer("--global-subset", v.global_subset, 1, limits::max_subset));
  if (given("--local-subset"))
    o.local_subset = static_cast<int>(parse_integer("--local-subset", v.local_subset, 1, limits::max_subset));
  if (given("--dirs")) o.dirs = static_cast<int>(parse_integer("--dirs", v.dirs, 1, limits::max_dirs));
  if (given("--voxels"))
    o.voxels = static_cast<int>(parse_integer("--voxels", v.voxels, limits::min_voxels, limits::max_voxels));
  if (given("--dprsm"))
    o.dprsm = static_cast<int>(parse_integer("--dprsm", v.dprsm, limits::min_dprsm, limits::max_dprsm));
  if (given("--dmin")) {
    o.dmin_fraction = parse_real("--dmin", v.dmin);
    if (!(o.dmin_fraction >= 0.0 && o.dmin_fraction <= 1.0)) bad("--dmin", "value " + v.dmin + " is outside 0..1");
  }
  if (given("--eps")) {
    o.eps = parse_real("--eps", v.eps);
    if (!(o.eps >= 0.0 && o.eps <= 1.0)) bad("--eps", "value " + v.eps + " is outside 0..1");
  }
  if (given("--exposure")) {
    const double e = parse_real("--exposure", v.exposure);
    if (!(e > 0.0 && e <= limits::max_exposure)) bad("--exposure", "value " + v.exposure + " must be in (0, 1e6]");
    o.exposure = static_cast<float>(e);
  }
  if (given("--out")) {
    o.out = v.out;
    std::string lower = o.out;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    const std::size_t slash = o.out.find_last_of('/');
    const std::string base = slash == std::string::npos ? o.out : o.out.substr(slash + 1);
    if (lower.size() < 4 || lower.compare(lower.size() - 4, 4, ".exr") != 0 || base.size() <= 4)
      bad("--out", "'" + o.out + "' must be a file name ending in .exr");
  }
  if (given("--camera")) {
    const std::vector<double> c = parse_list("--camera", v.cam);
    if (c.size() != 10) bad("--camera", "expected 10 comma-separated numbers (eye, target, up, fov), got " + std::to_string(c.size()));
    camera cam;
    cam.eye = glm::vec3(glm::dvec3(c[0], c[1], c[2]));
    cam.target = glm::vec3(glm::dvec3(c[3], c[4], c[5]));
    cam.up = glm::vec3(glm::dvec3(c[6], c[7], c[8]));
    cam.vfov_deg = static_cast<float>(c[9]);
    try {
      validate_camera(cam, "--camera");
    } catch (const input_error& e) {
      throw usage_error(e.what());
    }
    o.cam = camera_option{cam.eye, cam.target, cam.up, cam.vfov_deg};
  }
  if (given("--light")) {
    const std::vector<double> l = parse_list("--light", v.light);
    if (l.size() != 3 && l.size() != 6)
      bad("--light", "expected 3 (position) or 6 (position, intensity) comma-separated numbers, got " + std::to_string(l.size()));
    light_option lo;
    lo.position = glm::vec3(glm::dvec3(l[0], l[1], l[2]));
    if (l.size() == 6) {
      if (l[3] < 0.0 || l[4] < 0.0 || l[5] < 0.0) bad("--light", "intensity must be >= 0 in every channel");
      lo.intensity = glm::vec3(glm::dvec3(l[3], l[4], l[5]));
    }
    o.light = lo;
  }
  o.direct = v.direct;
  o.window = v.window;
  if (given("--frames"))
    o.frames = static_cast<int>(parse_integer("--frames", v.frames, 1, o.window ? limits::max_window_frames : limits::max_frames));
  if (given("--window-script")) {
    if (!o.window) bad("--window-script", "needs --window");
    std::size_t i = 0;
    while (i <= v.window_script.size()) {
      const std::size_t j = std::min(v.window_script.find(',', i), v.window_script.size());
      std::string k = v.window_script.substr(i, j - i);
      if (k.size() == 1 && k[0] >= 'A' && k[0] <= 'Z') k[0] = static_cast<char>(k[0] - 'A' + 'a');
      static const char* const allowed[] = {"0", "1", "2", "3", "4", "5", "6", "7", "8", "9", "m", "+", "-", "p", "q"};
      if (std::find(std::begin(allowed), std::end(allowed), k) == std::end(allowed))
        bad("--window-script", "unknown key action '" + k + "' (expected 0-9, m, +, -, p, q)");
      o.window_script.push_back(k);
      i = j + 1;
    }
  }

  region_grid(o.regions, o.regions_x, o.regions_y);
  if (o.regions_x > o.width || o.regions_y > o.height)
    bad("--regions", std::to_string(o.regions) + " regions (" + std::to_string(o.regions_x) + "x" +
                         std::to_string(o.regions_y) + ") do not fit a " + std::to_string(o.width) + "x" +
                         std::to_string(o.height) + " image");
  if (o.candidate_source == ris_source_choice::tiles) {
    // Methods without candidates ignore the source, as they ignore every other one.
    if (o.meth == method::ris)
      bad("--candidate-source", "tiles is for --method ris-mis (ris takes global, local, gbg or flux)");
    int tx = 0, ty = 0;
    region_grid(o.tiles, tx, ty);
    if (tx > o.width || ty > o.height)
      bad("--tiles", std::to_string(o.tiles) + " tiles (" + std::to_string(tx) + "x" + std::to_string(ty) +
                         ") do not fit a " + std::to_string(o.width) + "x" + std::to_string(o.height) + " image");
    if (static_cast<long long>(o.tiles) * o.tile_points > limits::max_subset_points)
      bad("--tile-points", std::to_string(o.tile_points) + " gather points in each of " + std::to_string(o.tiles) +
                               " tiles exceed " + std::to_string(limits::max_subset_points) + " in all");
    // A pool per tile: 2048 entries each unless --candidate-pool says otherwise.
    if (!given("--candidate-pool")) o.candidate_pool = 2048;
  }
  if (static_cast<long long>(o.regions) * o.local_subset > limits::max_subset_points)
    bad("--local-subset", std::to_string(o.local_subset) + " gather points in each of " + std::to_string(o.regions) +
                              " regions exceed " + std::to_string(limits::max_subset_points) + " in all");
  if (o.window && o.back != backend::gpu) bad("--window", "needs --backend gpu");
  return r;
}

}  // namespace vplrender
