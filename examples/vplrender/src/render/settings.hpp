// SPDX-License-Identifier: MIT
#pragma once
// The render vocabulary that both backends and the pipeline share: the method and its switches,
// the numbers derived from the scene (dmin), the builders' seeds and the progress callback. The
// command line fills it (cli/render_options.hpp); nothing here knows about flags.
#include <vplkit/visibility/voxel_grid.hpp>
#include <vplkit/vpl/dprsm_patch.hpp>

#include <cstdint>
#include <functional>
#include <string>

namespace vplrender {

// The estimators of --method; each is described once, by its row in render/method_traits.cpp
// (name, estimator, builder, samples, backends). exact: one-bounce indirect light by cosine
// gathering against the scene's triangles with exact visibility and no VPLs
// (render/cpu/exact_estimator.hpp), the ground truth of the others. ris: resampled importance
// sampling of VPLs (vplkit/estimators/ris_estimator.hpp), candidates from the distribution of
// ris_source_choice, optionally with spatial reuse; both backends.
enum class method { reference, global, local, gbg, gather, mis, mis_as_published, exact, ris, ris_mis };
enum class backend { gpu, cpu };
// Departures from the paper that can be switched back: the local CDFs' combination, the GBG
// accumulator and the CDF search; and how a distribution is sampled (face selection, sampler).
enum class local_combination_choice { balance, average };
enum class gbg_accumulator_choice { gathering, paper };
enum class cdf_search_choice { guide, binary };
// joint: one CDF over both paraboloids' texels; roulette: the paper's Alg. 1 (choose the face by
// its share of the weight, then sample within it: vplkit::flat_face_roulette). Same pmf.
enum class face_selection_choice { joint, roulette };
// cdf: discrete CDF (inversion, keeps u's stratification); alias: Walker's alias table
// (vplkit::alias_table; O(1), same pmf, does not keep u's stratification); share_tree: the
// learned part of the defensive mixture drawn from vplkit::share_tree, one 24-bit number per
// level from a stream of its own (the draws do not move when the weights move by their last bits:
// docs/math.md, "Image parity at large DPRSMs"; global, gbg, local and mis). automatic (the
// default): share_tree for the methods that draw it with the joint face selection and the guided
// CDF search, else cdf (resolved_sampler; render/method_traits.hpp).
enum class sampler_choice { cdf, alias, share_tree, automatic };
// What V(x, y) and the gathering rays are decided against. voxels: the triangles listed by the
// voxel grid (triangle_voxel_visibility / triangle_voxel_tracer, docs/math.md section 7.2: no
// self-occlusion at junctions); paper_voxels: the paper's binary voxel test (voxel_visibility /
// voxel_tracer, section 7.1); exact: the scene's triangles (Embree on the CPU backend, the pack's
// BVH on the GPU backend).
enum class visibility_choice { voxels, paper_voxels, exact };
// How gathering (gather, mis, and the exhaustive gathering reference) decides that the light
// reaches a hit (docs/math.md section 4.1): shadow_map = the DPRSM's plane test (the paper's);
// shadow_ray = a ray to the light through the exact visibility (vplkit::with_light_visibility),
// which needs visibility_choice::exact and is its default there.
enum class lit_test_choice { shadow_map, shadow_ray };

// What --visibility voxels answers (docs/math.md 7.2, "The exact contract on the voxel grid"):
// plane_rule = the ends stay where they are and triangles whose planes pass within 0.01 voxel of an
// end are ignored, hits carry their triangle's plane normal; exact = --visibility exact's contract
// on the triangles the grid lists: ends moved off their surfaces by exact's offset, every listed
// triangle counts, hits carry their triangle's interpolated shading normal
// (vplkit::triangle_voxel_ends::offset and vplkit::triangle_corner_view). CPU backend only.
enum class voxel_contract_choice { plane_rule, exact };
// What a VPL is, for every method that uses VPLs (docs/math.md section 11): point = the paper's VPL
// at the texel centre (the VPL sum is the midpoint rule of the one-bounce integral); patch = a point
// jittered over the texel's patch (vplkit::vpl_mode::patch), so the VPL methods, gathering and MIS
// estimate the same continuous integral.
enum class vpl_mode_choice { point, patch };
// The GPU backend's split of long loops over dispatches (render/gpu/loop_budget.hpp): automatic =
// only where the driver leaves loops after 65535 iterations (llvmpipe, softpipe: GL_RENDERER);
// always = on every driver (the split path, tested anywhere); never = one dispatch per stage on
// every driver (on llvmpipe right only for work well below its budget: the tests compare the two).
enum class loop_budget_choice { automatic, always, never };

// Whether the VPL methods (reference, global, local, gbg, ris) add back what the distance clamp dmin
// removes (vplkit::estimate_clamp_compensation, docs/math.md, "The clamp's compensation"): on = clamped estimate +
// near-field gathering, converging to the unclamped integral; off = the clamped estimate alone.
enum class clamp_compensation_choice { off, on };
// Where the GPU backend computes the compensation (docs/renderer.md, "The clamp compensation's
// passes"; the same image either way): compacted = passes of its own before the estimate kernel,
// over the list of the pixels with another surface within dmin, in full SIMD groups; inline = in
// the estimate kernel, after the estimator's units, where a group runs the directions whenever one
// of its pixels needs them. The CPU backend has one form (a pass before the estimate's).
enum class clamp_compensation_pass_choice { compacted, inline_pass };
// How many directions of the compensation each gather point traces (clamp_compensation_dirs;
// docs/results/clamp_compensation.md, "Directions per pixel" measured the rule):
// automatic = the default rule; fixed = `value` directions whatever the VPL count;
// per_vpls = one per `value` VPL samples, rounded up. Any rule gives the same expectation: the
// term is an average of its directions (docs/math.md, "The clamp's compensation").
struct clamp_compensation_dirs_choice {
  enum class rule { automatic, fixed, per_vpls };
  rule kind = rule::automatic;
  int value = 0;
  bool operator==(const clamp_compensation_dirs_choice& o) const { return kind == o.kind && value == o.value; }
};
// Where --method ris draws its candidates: a builder's defensive mixture (global; local: the
// pixel's own region's; gbg) or the flux CDF (light-power sampling, view-independent); tiles: per
// image tile a CDF over blocks of texels times the flux within each block (render/cpu/
// tiled_candidates.hpp; --method ris-mis on the CPU backend).
enum class ris_source_choice { global, local, gbg, flux, tiles };

const char* to_string(method m);
const char* to_string(backend b);
const char* to_string(local_combination_choice c);
const char* to_string(gbg_accumulator_choice a);
const char* to_string(cdf_search_choice s);
const char* to_string(face_selection_choice f);
const char* to_string(sampler_choice s);
const char* to_string(visibility_choice v);
const char* to_string(vpl_mode_choice v);
const char* to_string(lit_test_choice l);
const char* to_string(voxel_contract_choice e);
const char* to_string(loop_budget_choice l);

const char* to_string(clamp_compensation_choice c);
const char* to_string(clamp_compensation_pass_choice c);
std::string to_string(const clamp_compensation_dirs_choice& c);  // "auto", "N" or "1:K"
const char* to_string(ris_source_choice r);

// The methods that sample a distribution over the VPLs (traits(m).builder is not none: global,
// local, gbg, mis, mis-as-published, ris): they have builders and CDFs; reference, gather and exact
// have none.
bool has_distribution(method m);

// The methods whose samples are VPLs (traits(m).uses_vpls: every one but gather and exact):
// --vpl-mode applies to them.
bool uses_vpls(method m);

// The choices the command line sets one to one (cli/options.hpp's `options` has them as they
// are, with these defaults), and the estimator reads as they are: held once, here, by both.
// The comments name the paper's setting where a default departs from it.
struct render_choices {
  method meth = method::mis;
  int vpls = 64;              // VPL samples per gather point
  int dirs = 16;              // gathering directions per gather point (gbg NBDIR, gather, mis)
  int regions_x = 2, regions_y = 2;  // local CDF: the image regions as a grid
  local_combination_choice local_combination = local_combination_choice::balance;  // paper: average
  gbg_accumulator_choice gbg_accumulator = gbg_accumulator_choice::gathering;       // paper: paper
  cdf_search_choice cdf_search = cdf_search_choice::guide;                          // same indices either way
  face_selection_choice face_selection = face_selection_choice::joint;              // paper: roulette
  sampler_choice sampler = sampler_choice::automatic;
  // The command line's default: exact for the GPU backend, voxels for the CPU backend (--paper: paper_voxels).
  visibility_choice visibility = visibility_choice::voxels;
  lit_test_choice lit_test = lit_test_choice::shadow_map;  // the command line's default: shadow-ray with exact
  voxel_contract_choice voxel_contract = voxel_contract_choice::plane_rule;  // --visibility voxels only
  vpl_mode_choice vpl_mode = vpl_mode_choice::patch;       // paper: point (the midpoint rule)
  clamp_compensation_pass_choice clamp_compensation_pass = clamp_compensation_pass_choice::compacted;
  clamp_compensation_dirs_choice clamp_compensation_dirs_rule;  // automatic
  std::uint32_t seed = 1;
  bool direct = false;        // add direct lighting (default: one-bounce indirect only)
};

// Everything an estimator run needs besides the buffers (docs/renderer.md): the command line's
// choices, and what is derived from them and the scene or set only by programs and tests.
struct render_settings : render_choices {
  float eps = 0.05f;
  clamp_compensation_choice clamp_compensation = clamp_compensation_choice::off;
  float dmin = 0.0f;          // VPL distance clamp (world units)
  float scene_diagonal = 0.0f;  // of the scene's box (world units): the gathering depth tolerance
  int global_subset = 256;    // |S| of the global CDF
  int local_subset = 256;     // |S_i| per region of the local CDFs
  int threads = 0;            // CPU backend: 0 = std::thread::hardware_concurrency()
  // GPU backend: where long loops are split over dispatches, and (> 0) at most this many units
  // (samples, rounds, directions, texels) per dispatch whatever the budget allows (tests).
  loop_budget_choice loop_budget = loop_budget_choice::automatic;
  int max_units_per_pass = 0;
  // GPU backend, patch VPLs: read the DPRSM's plane records (render/gpu/gpu_dprsm_planes.hpp), or
  // (false: tests, measurements) compute each from the texel's three surfel vectors per sample.
  // The same images either way.
  bool dprsm_planes = true;
  // --method ris: candidates per sample (M), their source, spatial-reuse neighbours (K, 0 = off).
  int ris_candidates = 32;
  ris_source_choice ris_source = ris_source_choice::flux;
  int ris_spatial = 0;
  // --method ris-mis: entries of the presampled candidate pool (per candidate distribution; 0 =
  // each candidate drawn from the distribution itself). vplkit/estimators/ris_candidate_pool.hpp.
  int ris_pool = 0;
  // --candidate-source tiles: the image tiles (tiles_x * tiles_y), gather points per tile, and the
  // side of the texel blocks.
  int tiles_x = 8, tiles_y = 8;
  int tile_points = 8;
  int tile_block = 8;
};

// Seed of builder stage k (0: global subset, 1: local subsets, 2: GBG rays): a hash of the seed
// that differs from the per-pixel estimator streams (make_counter_rng(seed, pixel)).
std::uint32_t builder_seed(std::uint32_t seed, std::uint32_t stage);

// Seed of the presampled RIS candidate pool (--candidate-pool): entry i is drawn from the stream
// (ris_pool_seed(seed), i), apart from the builders' and the pixels' streams.
std::uint32_t ris_pool_seed(std::uint32_t seed);

// The reference's strata per texel side with --vpl-mode patch: m = 1, one jittered point per texel
// (vplkit::exhaustive_vpl_patch_sum), the point reference's cost; its noise is measured in
// docs/results.md.
constexpr int reference_patch_strata = 1;

vplkit::vpl_mode library_vpl_mode(vpl_mode_choice v);

// Does the method divide by the clamp max(d^2, dmin^2)? reference, global, local, gbg and ris
// (its target and its shading use the clamped contribution); mis, gather and exact have no clamp.
bool method_has_clamp(method m);

// Is the clamp compensation added to this run's estimate? On, a clamp (dmin > 0), and a method
// whose VPLs are clamped (method_has_clamp).
bool uses_clamp_compensation(const render_settings& s);

// Its directions per gather point: reference_compensation_dirs for the reference (a converged
// estimand, whatever the rule), else s.clamp_compensation_dirs_rule: fixed N, one per K VPL
// samples rounded up, or automatic = one per clamp_compensation_vpls_per_dir VPL samples, at least
// one. 16, not the earlier 4: the term's noise is small next to the VPLs' at a given sample count,
// and the fewer directions cost 4 times less; at equal time 1:16 beats 1:4, 1:64 and one
// direction on sponza, cornell and open (docs/results/clamp_compensation.md, "Directions per pixel").
constexpr int reference_compensation_dirs = 256;
constexpr int clamp_compensation_vpls_per_dir = 16;
int clamp_compensation_dirs(const render_settings& s);

// Depth tolerance of the gathering look-ups (gather, mis; GBG rays): the error of a hit's position,
// to which dprsm_lookup adds its own slack (a fraction of the texel's footprint). voxels and
// exact: 0, their hits lie on the triangles. paper_voxels, whose tracer's hits lie up to a voxel
// diagonal off the surface: 2 voxel diagonals of `grid`.
float gathering_depth_tolerance(const render_settings& s, const vplkit::voxel_grid_view<float>& grid);

// Progress callback: (label, done, total); called from the calling thread only.
using progress_fn = std::function<void(const std::string& label, std::uint64_t done, std::uint64_t total)>;

}  // namespace vplrender
