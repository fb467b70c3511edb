// SPDX-License-Identifier: MIT
#include "render/cpu/cpu_builders.hpp"

#include "render/cpu/cpu_frame.hpp"
#include "render/cpu/cpu_visibility.hpp"
#include "render/cpu/parallel.hpp"
#include "render/method_traits.hpp"

#include <vplkit/builders/flux_weights.hpp>
#include <vplkit/builders/gather_subset.hpp>
#include <vplkit/builders/gbg_weights.hpp>
#include <vplkit/builders/global_weights.hpp>
#include <vplkit/builders/local_weights.hpp>
#include <vplkit/builders/vpl_distribution.hpp>
#include <vplkit/visibility/visibility_callables.hpp>

#include <algorithm>
#include <vector>

namespace vplrender {

namespace {

using vplkit::gather_point;

std::vector<gather_point<float>> valid_points(const vplkit::gbuffer_view<float>& g, const std::vector<int>& pixels) {
  std::vector<gather_point<float>> pts;
  for (int p : pixels) {
    const gather_point<float> gp = g.at(p);
    if (vplkit::gather_point_valid(gp)) pts.push_back(gp);
  }
  return pts;
}

// The 2 R^2 texels in blocks of `block` over the workers: per-texel work that writes only its own
// texel, so the result does not depend on the worker count. Smaller blocks for costlier texels
// (global weights visit every subset point per texel), so that the workers finish together.
template <class F>
void for_each_texel(int n, int threads, F&& per_texel, int block = 16384) {
  parallel_items((n + block - 1) / block, threads, "", {}, [&](int b, int) {
    const int end = std::min(n, (b + 1) * block);
    for (int t = b * block; t < end; ++t) per_texel(t);
  });
}

// Per-texel global weights from a list of gather points, over the workers.
void global_weights(const vplkit::dprsm_view<float>& view, const std::vector<gather_point<float>>& points, float dmin,
                    float* out, int threads) {
  for_each_texel(
      view.texel_count(), threads,
      [&](int t) {
        out[t] = vplkit::global_weight_texel(view, t, points.data(), static_cast<int>(points.size()), dmin);
      },
      4096);
}

// vplkit::build_flux_weights of the frame's (already validated) view, over the workers: the same
// weights, flux_weight_texel per texel.
std::vector<float> flux_weights(const vplkit::dprsm_view<float>& view, int threads) {
  std::vector<float> w(static_cast<std::size_t>(view.texel_count()), 0.0f);
  for_each_texel(view.texel_count(), threads,
                 [&](int t) { w[static_cast<std::size_t>(t)] = vplkit::flux_weight_texel(view, t); });
  return w;
}

// vplkit::make_vpl_distribution(weights, view, eps) with the fallback's 0/1 weights (those of
// make_vpl_fallback: 1 on the texels that carry a VPL) made over the workers: the same mixture, bit
// for bit. A frame's fixed cost before its first sample: one vpl_at per texel, serial in the
// library's overload, was a third of the flux source's build (docs/results.md, "Presampled
// candidates").
vplkit::defensive_mixture<float> vpl_distribution(const std::vector<float>& weights,
                                                  const vplkit::dprsm_view<float>& view, float eps, int threads) {
  if (eps == 0.0f) return vplkit::make_vpl_distribution(weights.data(), weights.size(), view, {}, eps);
  std::vector<float> ones(static_cast<std::size_t>(view.texel_count()), 0.0f);
  for_each_texel(view.texel_count(), threads, [&](int t) {
    ones[static_cast<std::size_t>(t)] = vplkit::vpl_has_flux(view.vpl_at(t)) ? 1.0f : 0.0f;
  });
  return vplkit::make_vpl_distribution(weights.data(), weights.size(), view,
                                       vplkit::discrete_cdf<float>(ones.data(), ones.size()), eps);
}

}  // namespace

std::vector<float> build_gbg_weights_cpu(const frame_buffers& b, const render_settings& s, stage_timer& timer,
                                         const progress_fn& progress, nlohmann::json& det) {
  const cpu_frame f = open_cpu_frame(b, s);
  const vplkit::gbuffer_view<float>& g = f.g;
  const vplkit::dprsm_view<float>& view = f.view;
  const int threads = f.threads, W = f.W, H = f.H;
  cpu_tracer tracer = make_cpu_tracer(b, s.visibility, lit_test_choice::shadow_map, s.voxel_contract);
  tracer.shading_normals = false;  // as the GPU's GBG kernel (cpu_visibility.hpp)
  const std::size_t n = static_cast<std::size_t>(view.texel_count());
  vplkit::gbg_params<float> params;
  params.n_dirs = s.dirs;
  params.dmin = s.dmin;
  params.depth_tolerance = gathering_depth_tolerance(s, b.grid.occupancy().view());
  params.seed = builder_seed(s.seed, 2);
  params.accumulator = s.gbg_accumulator == gbg_accumulator_choice::paper ? vplkit::gbg_accumulator::paper
                                                                          : vplkit::gbg_accumulator::gathering;
  std::vector<float> raw(n, 0.0f), weights(n, 0.0f);
  vplkit::gbg_stats stats;
  {
    auto t = timer.scoped("gbg weights (cpu)");
    // Rows to workers one at a time, each worker accumulating into its own partial.
    std::vector<vplkit::gbg_partial> parts(static_cast<std::size_t>(threads));
    parallel_items(H, threads, "gbg weights", progress, [&](int y, int k) {
      vplkit::gbg_partial& part = parts[static_cast<std::size_t>(k)];
      if (part.acc.empty()) part.acc.assign(n, 0.0);
      vplkit::gbg_accumulate_pixels(g, y * W, (y + 1) * W, view, tracer, params, part.acc.data(), &part.stats);
    });
    std::vector<double> acc(n);
    vplkit::gbg_merge(parts, n, acc.data(), stats);
    vplkit::gbg_finish(acc.data(), n, stats.gather_points, s.dirs, raw.data());
  }
  {
    auto t = timer.scoped("gbg hole fill (cpu)");
    vplkit::gbg_count_and_fill(raw.data(), n, view, params.fill_holes, weights.data(), stats);
  }
  det["gbg"] = {{"gather_points", stats.gather_points}, {"rays", stats.rays},         {"hits", stats.hits},
                {"lit_hits", stats.lit_hits},           {"reached_texels", stats.reached_texels},
                {"holes", stats.holes},                 {"filled", stats.filled},     {"accumulator", to_string(s.gbg_accumulator)}};
  return weights;
}

cpu_distributions build_distributions_cpu(const frame_buffers& b, const render_settings& s, stage_timer& timer,
                                          const progress_fn& progress, nlohmann::json& det) {
  const cpu_frame f = open_cpu_frame(b, s);
  const vplkit::gbuffer_view<float>& g = f.g;
  const vplkit::dprsm_view<float>& view = f.view;
  const int threads = f.threads, W = f.W, H = f.H;
  const std::size_t n_texels = static_cast<std::size_t>(view.texel_count());
  cpu_distributions out;
  switch (distribution_builder(s)) {
    case builder_kind::none:
    case builder_kind::candidate_source:  // resolved to its builder by distribution_builder
      break;
    case builder_kind::flux: {
      std::vector<float> weights;
      {
        auto t = timer.scoped("flux weights (cpu)");
        weights = flux_weights(view, threads);
      }
      auto t = timer.scoped("cdf (cpu)");
      out.dists.push_back(vpl_distribution(weights, view, s.eps, threads));
      out.weights = std::move(weights);
      break;
    }
    case builder_kind::global: {
      std::vector<float> weights(n_texels, 0.0f);
      int used = 0;
      {
        auto t = timer.scoped("global weights (cpu)");
        const std::vector<int> subset = vplkit::stratified_gather_subset(g, vplkit::full_image_rect(g), s.global_subset,
                                                                         builder_seed(s.seed, 0));
        const std::vector<gather_point<float>> pts = valid_points(g, subset);
        used = static_cast<int>(pts.size());
        global_weights(view, pts, s.dmin, weights.data(), threads);
      }
      det["global_subset"] = used;
      auto t = timer.scoped("cdf (cpu)");
      out.dists.push_back(vpl_distribution(weights, view, s.eps, threads));
      out.weights = std::move(weights);
      break;
    }
    case builder_kind::local: {
      const vplkit::image_regions regions(W, H, s.regions_x, s.regions_y);
      const int N = regions.count();
      std::vector<float> flat(static_cast<std::size_t>(N) * n_texels, 0.0f);
      std::vector<int> used(static_cast<std::size_t>(N), 0);
      {
        auto t = timer.scoped("local weights (cpu)");
        const auto subsets = vplkit::local_gather_subsets(g, regions, s.local_subset, builder_seed(s.seed, 1));
        for (int i = 0; i < N; ++i) {
          const std::vector<gather_point<float>> pts = valid_points(g, subsets[static_cast<std::size_t>(i)]);
          used[static_cast<std::size_t>(i)] = static_cast<int>(pts.size());
          global_weights(view, pts, s.dmin, flat.data() + static_cast<std::size_t>(i) * n_texels, threads);
        }
      }
      det["local_subsets"] = used;
      {
        auto t = timer.scoped("cdf (cpu)");
        out.dists = vplkit::make_local_vpl_distributions(flat, N, view, s.eps);
      }
      out.weights = std::move(flat);
      // N_NG rounds of one VPL per region's CDF: vpls / N rounds (at least one), so a pixel gets
      // about --vpls samples whatever N is.
      out.local_rounds = std::max(1, s.vpls / N);
      if (s.meth == method::local) {
        det["local_rounds"] = out.local_rounds;
        det["local_combination"] = to_string(s.local_combination);
      }
      break;
    }
    case builder_kind::gbg: {
      std::vector<float> weights = build_gbg_weights_cpu(b, s, timer, progress, det);
      auto t = timer.scoped("cdf (cpu)");
      out.dists.push_back(vpl_distribution(weights, view, s.eps, threads));
      out.weights = std::move(weights);
      break;
    }
  }
  return out;
}

}  // namespace vplrender
