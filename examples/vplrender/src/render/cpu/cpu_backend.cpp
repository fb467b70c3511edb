// SPDX-License-Identifier: MIT
#include "render/cpu/cpu_backend.hpp"

#include "render/cpu/cpu_builders.hpp"
#include "render/cpu/cpu_frame.hpp"
#include "render/cpu/cpu_visibility.hpp"
#include "render/cpu/exact_estimator.hpp"
#include "render/cpu/parallel.hpp"
#include "render/method_traits.hpp"
#include "render/cpu/ris_render.hpp"
#include "render/cpu/thread_cpu_time.hpp"
#include "render/cpu/tiled_candidates.hpp"
#include "render/mixture_components.hpp"
#include "render/share_tree_mixture.hpp"

#include <vplkit/estimators/clamp_compensation.hpp>
#include <vplkit/estimators/gathering_estimator.hpp>
#include <vplkit/estimators/local_estimator.hpp>
#include <vplkit/estimators/mis_estimator.hpp>
#include <vplkit/estimators/vpl_sampling_estimator.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/sampling/rng.hpp>
#include <vplkit/visibility/visibility_callables.hpp>
#include <vplkit/vpl/direct_light.hpp>
#include <vplkit/vpl/dprsm_plane.hpp>

#include <glm/common.hpp>
#include <algorithm>

#include <memory>
#include <utility>
#include <vector>

namespace vplrender {

namespace {

// --candidate-source tiles: the frame's texel blocks (on the flux build's weights) and one
// distribution per tile of s.tiles_x x s.tiles_y from s.tile_points stratified gather points each
// (stream builder_seed(seed, 3)), timed as the stage "tiles (cpu)". The distributions point at the
// blocks, which therefore live on the heap: moving this struct keeps their address.
struct tiled_candidates {
  std::unique_ptr<const tile_blocks> blocks;
  std::vector<tiled_distribution> dists;
};

tiled_candidates build_tiled_candidates(const cpu_frame& f, const render_settings& s, const cpu_distributions& built,
                                        stage_timer& timer, nlohmann::json& det) {
  if (built.dists.size() != 1) throw vplkit::invalid_input("--candidate-source tiles: needs the flux build's mixture");
  tiled_candidates out;
  std::vector<int> used;
  {
    auto t = timer.scoped("tiles (cpu)");
    out.blocks = std::make_unique<const tile_blocks>(vplkit::make_tile_blocks(f.view, s.tile_block));
    const vplkit::image_regions tiles(f.W, f.H, s.tiles_x, s.tiles_y);
    const std::vector<std::vector<int>> subsets =
        vplkit::local_gather_subsets(f.g, tiles, s.tile_points, builder_seed(s.seed, 3));
    std::vector<std::vector<vplkit::gather_point<float>>> points(subsets.size());
    for (std::size_t i = 0; i < subsets.size(); ++i) {
      for (const int p : subsets[i])
        if (vplkit::gather_point_valid(f.g.at(p))) points[i].push_back(f.g.at(p));
      used.push_back(static_cast<int>(points[i].size()));
    }
    out.dists = make_tiled_distributions(*out.blocks, points, s.dmin, built.dists[0].fallback(), s.eps, f.threads);
  }
  det["tiles"] = {{"tiles", static_cast<int>(out.dists.size())},
                  {"grid", {s.tiles_x, s.tiles_y}},
                  {"points", used},
                  {"block", out.blocks->grid.block},
                  {"blocks", out.blocks->count()},
                  {"empty", std::count_if(out.dists.begin(), out.dists.end(),
                                          [](const tiled_distribution& d) { return d.block_cdf().empty(); })}};
  return out;
}

using vplkit::gather_point;
using vec3f = glm::vec3;

// --cdf-search binary: the estimators' Distribution interface over a defensive mixture, drawing by
// plain binary search (the same index and pmf as the guided sample(), at another cost).
struct binary_searched_mixture {
  const vplkit::defensive_mixture<float>* m = nullptr;
  vplkit::discrete_sample<float> sample(float u) const noexcept { return m->sample_binary_search(u); }
  float pmf(std::size_t i) const noexcept { return m->pmf(i); }
};

// Calls body(dists) with the distributions the estimators sample: the mixtures themselves; for
// --cdf-search binary, adaptors that search them by plain binary search; for --sampler alias or
// --face-selection roulette, the mixtures sampled through those components.
template <class Body>
void with_distributions(const cpu_distributions& built, const frame_buffers& b, const render_settings& s,
                        stage_timer& timer, Body&& body) {
  if (mixture_components::wanted(s) && !built.dists.empty()) {
    mixture_components c;
    {
      auto t = timer.scoped("sampler tables (cpu)");
      c = build_mixture_components(built.weights.data(), static_cast<int>(built.dists.size()), b.dprsm.view(), s);
    }
    if (s.sampler == sampler_choice::alias) body(component_mixtures(built.dists, std::move(c.alias)).data());
    else body(component_mixtures(built.dists, c.flat).data());
  } else if (s.cdf_search == cdf_search_choice::binary) {
    std::vector<binary_searched_mixture> binary;
    for (const auto& m : built.dists) binary.push_back({&m});
    body(binary.data());
  } else {
    body(built.dists.data());
  }
}

// vplkit::build_dprsm_planes over the worker threads (rows of R texels, both faces).
std::vector<vplkit::dprsm_plane<float>> build_dprsm_planes_cpu(const vplkit::dprsm_view<float>& view, int threads) {
  view.validate();
  std::vector<vplkit::dprsm_plane<float>> out(static_cast<std::size_t>(view.texel_count()));
  const int R = view.resolution, rows = view.texel_count() / R;
  parallel_items(rows, threads, "", {}, [&](int row, int) {
    for (int t = row * R; t < (row + 1) * R; ++t)
      out[static_cast<std::size_t>(t)] = vplkit::dprsm_plane_of(view.light.position, view.texel_valid(t),
                                                                view.position[t], view.normal[t], view.albedo[t]);
  });
  return out;
}

}  // namespace

render_result render_cpu(const frame_buffers& b, const render_settings& given, stage_timer& timer,
                         const progress_fn& progress) {
  render_settings s = given;
  s.sampler = resolved_sampler(given);
  cpu_frame f = open_cpu_frame(b, s);
  const method_traits& mt = traits(s.meth);
  if (mt.estimator == estimator_kind::ris && mt.variant != 1 && s.ris_source == ris_source_choice::tiles)
    throw vplkit::invalid_input("--method ris --candidate-source tiles: tiles is for --method ris-mis");
  // Patch VPLs read four plane records per point (their texel's and the hidden test's three
  // neighbours'): built once per frame, as the GPU backend builds them (vplkit::dprsm_view::planes;
  // the same values as computing them per point, so the same image).
  std::vector<vplkit::dprsm_plane<float>> planes;
  if (mt.uses_vpls && s.vpl_mode == vpl_mode_choice::patch) {
    auto tp = timer.scoped("dprsm planes (cpu)");
    planes = build_dprsm_planes_cpu(f.view, f.threads);
    f.view.planes = planes.data();
  }
  const vplkit::gbuffer_view<float>& g = f.g;
  const vplkit::dprsm_view<float>& view = f.view;
  const int threads = f.threads, W = f.W, H = f.H;
  render_result result;
  result.image = image_rgb(W, H);
  nlohmann::json& det = result.details;
  det["threads"] = threads;
  det["dmin"] = s.dmin;

  const cpu_visibility visibility = make_cpu_visibility(b, s.visibility, s.voxel_contract);
  const cpu_tracer tracer = make_cpu_tracer(b, s.visibility, s.lit_test, s.voxel_contract);
  det["visibility"] = to_string(mt.exact_rays ? visibility_choice::exact : s.visibility);
  if (!mt.exact_rays && s.visibility == visibility_choice::voxels) det["voxel_contract"] = to_string(s.voxel_contract);
  const float depth_tol = gathering_depth_tolerance(s, b.grid.occupancy().view());
  det["depth_tolerance"] = depth_tol;
  if (mt.gathers)
    det["lit_test"] = to_string(tracer.answers_light_visibility() ? lit_test_choice::shadow_ray : lit_test_choice::shadow_map);
  det["cdf_search"] = to_string(s.cdf_search);
  const cpu_distributions built = build_distributions_cpu(b, s, timer, progress, det);

  // Patch VPLs take the gathering look-up's depth window in every method, so that the VPL methods,
  // gathering and MIS estimate one integral (docs/math.md section 11, "Rejections").
  const vplkit::vpl_mode vmode = library_vpl_mode(s.vpl_mode);
  // What the VPL clamp removed (docs/math.md, "The clamp's compensation"), from a stream of its own: the clamped
  // estimate stays what it is without it.
  const bool compensate = uses_clamp_compensation(s);
  const int compensation_dirs = clamp_compensation_dirs(s);
  if (compensate) det["clamp_compensation_dirs"] = compensation_dirs;

  // The compensation of every pixel, a pass of its own before the estimate (timed as a stage of the
  // estimate, as the GPU backend's passes): its stream derives from the pixel's own (the key only),
  // so the estimate keeps every sample it had, and the pixel's value is estimate + term as before.
  // Most pixels trace nothing (no other surface within dmin: the tracer's near-surface test).
  std::vector<vec3f> compensation_terms;
  if (compensate) {
    auto t = timer.scoped(clamp_compensation_stage_cpu);
    compensation_terms.assign(static_cast<std::size_t>(W) * static_cast<std::size_t>(H), vec3f(0.0f));
    std::vector<double> cpu_s(static_cast<std::size_t>(std::max(1, threads)), 0.0);  // per worker
    parallel_items(H, threads, "clamp compensation", progress, [&](int y, int k) {
      const double t0 = thread_cpu_seconds();
      for (int p = y * W; p < (y + 1) * W; ++p) {
        const gather_point<float> gp = g.at(p);
        if (!vplkit::gather_point_valid(gp)) continue;
        vplkit::counter_rng compensation_rng =
            vplkit::clamp_compensation_stream(vplkit::make_counter_rng(s.seed, static_cast<std::uint32_t>(p)));
        compensation_terms[static_cast<std::size_t>(p)] = vplkit::estimate_clamp_compensation(
            gp, view, compensation_rng, compensation_dirs, tracer, s.dmin, depth_tol, vmode);
      }
      cpu_s[static_cast<std::size_t>(k)] += thread_cpu_seconds() - t0;
    });
    double total = 0.0;
    for (double c : cpu_s) total += c;
    // Its CPU time (all workers): what docs/results/clamp_compensation.md's costs divide.
    det["clamp_compensation_cpu_ms"] = 1e3 * total;
  }
  const auto compensation = [&](const gather_point<float>&, int p) {
    return compensate ? compensation_terms[static_cast<std::size_t>(p)] : vec3f(0.0f);
  };

  // Per-pixel loop shared by every method: est(gp, rng) -> vec3.
  auto render_pixels = [&](auto&& est) {
    auto t = timer.scoped("estimate (cpu)");
    std::vector<double> cpu_s(static_cast<std::size_t>(std::max(1, threads)), 0.0);  // per worker
    parallel_items(H, threads, "render", progress, [&](int y, int k) {
      const double t0 = thread_cpu_seconds();
      for (int x = 0; x < W; ++x) {
        const int p = y * W + x;
        const gather_point<float> gp = g.at(p);
        vec3f c(0.0f);
        if (vplkit::gather_point_valid(gp)) {
          vplkit::counter_rng rng = vplkit::make_counter_rng(s.seed, static_cast<std::uint32_t>(p));
          c = est(gp, rng) + compensation(gp, p);
          if (s.direct) c += vplkit::direct_light(gp, view);
          c = vplkit::estimator_finite_or_zero(glm::max(c, vec3f(0.0f)));
        }
        float* o = result.image.at(x, y);
        o[0] = c.x;
        o[1] = c.y;
        o[2] = c.z;
      }
      cpu_s[static_cast<std::size_t>(k)] += thread_cpu_seconds() - t0;
    });
    double total = 0.0;
    for (double c : cpu_s) total += c;
    det["estimate_cpu_ms"] = 1e3 * total;  // the clamp compensation's cost is measured against it
  };

  det["face_selection"] = to_string(s.face_selection);
  det["sampler"] = to_string(s.sampler);
  if (mt.uses_vpls) det["vpl_mode"] = to_string(s.vpl_mode);
  if (mt.estimator == estimator_kind::reference && vmode == vplkit::vpl_mode::patch)
    det["reference_strata"] = reference_patch_strata;
  if (s.sampler == sampler_choice::share_tree) {
    // --sampler share-tree (render/share_tree_mixture.hpp): the VPL-sampling, local and mis estimators
    // over mixtures whose learned part is a share tree drawn from the pixel's tree stream (local:
    // every region's draws from the one stream, in the estimator's draw order; mis: its VPL draws,
    // the gathering hits evaluate the tree's pmf).
    if (!draws_share_tree(mt.estimator))
      throw vplkit::invalid_input(std::string("--sampler share-tree: not supported with --method ") + mt.name +
                                  " (only global, gbg, local and mis)");
    std::vector<share_tree_mixture> trees;
    {
      auto t = timer.scoped("sampler tables (cpu)");
      trees = build_share_tree_mixtures(built.weights, built.dists);
    }
    if (mt.estimator == estimator_kind::mis) {
      const vplkit::mis_mode mode = mt.variant == 1 ? vplkit::mis_mode::as_published : vplkit::mis_mode::solid_angle;
      render_pixels([&](const gather_point<float>& gp, vplkit::counter_rng& rng) {
        vplkit::counter_rng stream = share_tree_stream(rng);
        return vplkit::estimate_mis(gp, view, share_tree_mixture_draw{&trees[0], &stream}, rng, s.dirs, s.vpls, tracer,
                                    visibility, depth_tol, mode, vmode);
      });
      return result;
    }
    if (mt.estimator == estimator_kind::local) {
      const vplkit::local_combination comb = s.local_combination == local_combination_choice::average
                                                 ? vplkit::local_combination::average
                                                 : vplkit::local_combination::balance;
      render_pixels([&](const gather_point<float>& gp, vplkit::counter_rng& rng) {
        vplkit::counter_rng stream = share_tree_stream(rng);
        std::vector<share_tree_mixture_draw> draws(trees.size());
        for (std::size_t d = 0; d < trees.size(); ++d) draws[d] = share_tree_mixture_draw{&trees[d], &stream};
        return vplkit::estimate_local(gp, view, draws.data(), static_cast<int>(draws.size()), rng, built.local_rounds,
                                      visibility, s.dmin, comb, vmode, depth_tol);
      });
      return result;
    }
    render_pixels([&](const gather_point<float>& gp, vplkit::counter_rng& rng) {
      vplkit::counter_rng stream = share_tree_stream(rng);
      return vplkit::estimate_vpl_sampling(gp, view, share_tree_mixture_draw{&trees[0], &stream}, rng, s.vpls,
                                           visibility, s.dmin, vmode, depth_tol);
    });
    return result;
  }
  with_distributions(built, b, s, timer, [&](const auto* dists) {
    switch (mt.estimator) {
      case estimator_kind::reference:
        if (vmode == vplkit::vpl_mode::patch)
          render_pixels([&](const gather_point<float>& gp, vplkit::counter_rng& rng) {
            return vplkit::exhaustive_vpl_patch_sum(gp, view, rng, reference_patch_strata, visibility, s.dmin,
                                                    depth_tol);
          });
        else
          render_pixels([&](const gather_point<float>& gp, vplkit::counter_rng&) {
            return vplkit::exhaustive_vpl_sum(gp, view, visibility, s.dmin);
          });
        break;
      case estimator_kind::vpl_sampling:
        render_pixels([&](const gather_point<float>& gp, vplkit::counter_rng& rng) {
          return vplkit::estimate_vpl_sampling(gp, view, dists[0], rng, s.vpls, visibility, s.dmin, vmode,
                                                depth_tol);
        });
        break;
      case estimator_kind::local: {
        const int N = static_cast<int>(built.dists.size());
        const vplkit::local_combination comb = s.local_combination == local_combination_choice::average
                                                   ? vplkit::local_combination::average
                                                   : vplkit::local_combination::balance;
        render_pixels([&](const gather_point<float>& gp, vplkit::counter_rng& rng) {
          return vplkit::estimate_local(gp, view, dists, N, rng, built.local_rounds, visibility, s.dmin, comb,
                                        vmode, depth_tol);
        });
        break;
      }
      case estimator_kind::gather:
        render_pixels([&](const gather_point<float>& gp, vplkit::counter_rng& rng) {
          return vplkit::estimate_gathering(gp, view, rng, s.dirs, tracer, depth_tol);
        });
        break;
      case estimator_kind::mis: {
        const vplkit::mis_mode mode = mt.variant == 1 ? vplkit::mis_mode::as_published : vplkit::mis_mode::solid_angle;
        render_pixels([&](const gather_point<float>& gp, vplkit::counter_rng& rng) {
          return vplkit::estimate_mis(gp, view, dists[0], rng, s.dirs, s.vpls, tracer, visibility, depth_tol, mode,
                                      vmode);
        });
        break;
      }
      case estimator_kind::ris:
        if (mt.variant == 1) {
          if (s.ris_source == ris_source_choice::tiles) {
            const tiled_candidates tiles = build_tiled_candidates(f, s, built, timer, det);
            render_ris_mis_cpu(f, s, tiles.dists.data(), static_cast<int>(tiles.dists.size()), tracer, visibility,
                               depth_tol, vmode, result.image.rgb.data(), timer, progress, det);
            break;
          }
          render_ris_mis_cpu(f, s, dists, static_cast<int>(built.dists.size()), tracer, visibility, depth_tol, vmode,
                             result.image.rgb.data(), timer, progress, det);
          break;
        }
        render_ris_cpu(f, s, dists, static_cast<int>(built.dists.size()), visibility, depth_tol, vmode, compensation,
                       result.image.rgb.data(), timer, progress, det);
        break;
      case estimator_kind::exact: {
        const ray_scene& rs = frame_ray_scene(b, "--method exact");
        render_pixels([&](const gather_point<float>& gp, vplkit::counter_rng& rng) {
          return estimate_exact(rs, view.light, gp, rng, s.dirs);
        });
        break;
      }
    }
  });
  return result;
}

}  // namespace vplrender
