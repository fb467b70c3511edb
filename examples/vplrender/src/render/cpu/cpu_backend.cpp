#include "render/cpu/cpu_backend.hpp"

#include <vplkit/builders/gather_subset.hpp>
#include <vplkit/builders/gbg_weights.hpp>
#include <vplkit/builders/global_weights.hpp>
#include <vplkit/builders/local_weights.hpp>
#include <vplkit/builders/vpl_distribution.hpp>
#include <vplkit/estimators/gathering_estimator.hpp>
#include <vplkit/estimators/local_estimator.hpp>
#include <vplkit/estimators/mis_estimator.hpp>
#include <vplkit/estimators/vpl_sampling_estimator.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/sampling/rng.hpp>
#include <vplkit/visibility/visibility_callables.hpp>
#include <vplkit/vpl/direct_light.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace vplrender {

estimator_settings make_estimator_settings(const options& o, const scene& s) {
  estimator_settings e;
  e.meth = o.meth;
  e.vpls = o.vpls;
  e.dirs = o.dirs;
  e.regions_x = o.regions_x;
  e.regions_y = o.regions_y;
  e.eps = static_cast<float>(o.eps);
  e.local_combination = o.local_combination;
  e.gbg_accumulator = o.gbg_accumulator;
  e.cdf_search = o.cdf_search;
  e.seed = o.seed;
  e.direct = o.direct;
  // The VPL clamp of docs/math.md section 2: 1% of the scene diagonal (a documented, tunable bias;
  // the reference uses the same value, so the CDF methods converge to it exactly).
  e.dmin = 0.01f * bounds(s).diagonal();
  return e;
}

std::uint32_t builder_seed(std::uint32_t seed, std::uint32_t stage) {
  return vplkit::rng_key(seed, 0xB0000000u + stage);
}

namespace {

using vplkit::gather_point;
using vec3f = glm::vec3;

int thread_count(int requested) {
  if (requested > 0) return requested;
  const unsigned h = std::thread::hardware_concurrency();
  return h > 0 ? static_cast<int>(h) : 1;
}

// Runs work(item, thread) for item in [0, n) on `threads` workers, handing out items one at a
// time (items are rows or blocks: coarse enough). The calling thread reports progress every
// 50 ms. The first exception of any worker is rethrown after all have stopped.
template <class Work>
void parallel_items(int n, int threads, const std::string& label, const progress_fn& progress, Work&& work) {
  std::atomic<int> next{0}, done{0};
  std::atomic<bool> failed{false};
  std::exception_ptr error;
  std::mutex error_mutex;
  std::vector<std::thread> pool;
  const int t = std::max(1, std::min(threads, n));
  for (int k = 0; k < t; ++k)
    pool.emplace_back([&, k] {
      for (;;) {
        const int i = next.fetch_add(1);
        if (i >= n || failed.load()) break;
        try {
          work(i, k);
        } catch (...) {
          std::lock_guard<std::mutex> lock(error_mutex);
          if (!error) error = std::current_exception();
          failed = true;
        }
        done.fetch_add(1);
      }
    });
  if (progress) {
    while (done.load() < n && !failed.load()) {
      progress(label, static_cast<std::uint64_t>(done.load()), static_cast<std::uint64_t>(n));
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  }
  for (std::thread& th : pool) th.join();
  if (error) std::rethrow_exception(error);
  if (progress) progress(label, static_cast<std::uint64_t>(n), static_cast<std::uint64_t>(n));
}

// Per-texel global weights from a list of gather points, parallel over texel blocks.
void global_weights(const vplkit::dprsm_view<float>& view, const std::vector<gather_point<float>>& points, float dmin,
                    float* out, int threads) {
  const int n = view.texel_count();
  const int block = 4096;
  const int blocks = (n + block - 1) / block;
  parallel_items(blocks, threads, "", {}, [&](int b, int) {
    const int end = std::min(n, (b + 1) * block);
    for (int t = b * block; t < end; ++t)
      out[t] = vplkit::global_weight_texel(view, t, points.data(), static_cast<int>(points.size()), dmin);
  });
}

// --cdf-search binary: the estimators' Distribution interface over a defensive mixture, drawing by
// plain binary search (the same index and pmf as the guided sample(), at another cost).
struct binary_searched_mixture {
  const vplkit::defensive_mixture<float>* m = nullptr;
  vplkit::discrete_sample<float> sample(float u) const noexcept { return m->sample_binary_search(u); }
  float pmf(std::size_t i) const noexcept { return m->pmf(i); }
};

std::vector<gather_point<float>> valid_points(const vplkit::gbuffer_view<float>& g, const std::vector<int>& pixels) {
  std::vector<gather_point<float>> pts;
  for (int p : pixels) {
    const gather_point<float> gp = g.at(p);
    if (vplkit::gather_point_valid(gp)) pts.push_back(gp);
  }
  return pts;
}

}  // namespace

int estimator_threads(int requested) { return thread_count(requested); }

float gathering_depth_tolerance(const vplkit::voxel_grid_view<float>& grid) {
  // The tracer's own error (one voxel diagonal, voxel_tracer_depth_tolerance) doubled for the
  // texel's depth spread on tilted surfaces.
  return 2.0f * vplkit::voxel_tracer_depth_tolerance(grid);
}

cpu_distributions build_distributions_cpu(const gbuffer_data& gb, const dprsm_data& dd,
                                          const vplkit::voxel_grid_view<float>& grid, const estimator_settings& es,
                                          stage_timer& timer, const progress_fn& progress, nlohmann::json& det) {
  const vplkit::gbuffer_view<float> g = gb.view();
  const vplkit::dprsm_view<float> view = dd.view();
  g.validate();
  view.validate();
  const int threads = thread_count(es.threads);
  const int W = g.width, H = g.height;
  const vplkit::voxel_tracer<float> tracer{grid};
  const float depth_tol = gathering_depth_tolerance(grid);
  const std::size_t n_texels = static_cast<std::size_t>(view.texel_count());
  cpu_distributions out;
  // GBG weights -> defensive distribution (used by gbg, mis, mis-as-published).
  auto build_gbg = [&]() {
    std::vector<float> raw(n_texels, 0.0f), weights(n_texels, 0.0f);
    vplkit::gbg_stats stats;
    {
      auto t = timer.scoped("gbg weights (cpu)");
      vplkit::gbg_params<float> params;
      params.n_dirs = es.dirs;
      params.dmin = es.dmin;
      params.depth_tolerance = depth_tol;
      params.seed = builder_seed(es.seed, 2);
      params.accumulator = es.gbg_accumulator == gbg_accumulator_choice::paper ? vplkit::gbg_accumulator::paper
                                                                               : vplkit::gbg_accumulator::gathering;
      std::vector<std::vector<double>> acc(static_cast<std::size_t>(threads));
      std::vector<vplkit::gbg_stats> per(static_cast<std::size_t>(threads));
      std::vector<int> counts(static_cast<std::size_t>(threads), 0);
      parallel_items(H, threads, "gbg weights", progress, [&](int y, int k) {
        std::vector<double>& a = acc[static_cast<std::size_t>(k)];
        if (a.empty()) a.assign(n_texels, 0.0);
        for (int x = 0; x < W; ++x) {
          const int p = y * W + x;
          const gather_point<float> gp = g.at(p);
          if (!vplkit::gather_point_valid(gp)) continue;
          ++counts[static_cast<std::size_t>(k)];
          vplkit::gbg_accumulate_gather_point(gp, p, view, tracer, params, a.data(), &per[static_cast<std::size_t>(k)]);
        }
      });
      std::vector<double> total(n_texels, 0.0);
      for (std::size_t k = 0; k < acc.size(); ++k) {
        if (!acc[k].empty())
          for (std::size_t i = 0; i < n_texels; ++i) total[i] += acc[k][i];
        stats.gather_points += counts[k];
        stats.rays += per[k].rays;
        stats.hits += per[k].hits;
        stats.lit_hits += per[k].lit_hits;
      }
      vplkit::gbg_finish(total.data(), n_texels, stats.gather_points, es.dirs, raw.data());
    }
    {
      auto t = timer.scoped("gbg hole fill (cpu)");
      for (std::size_t i = 0; i < n_texels; ++i) {
        if (raw[i] != 0.0f) ++stats.reached_texels;
        else if (vplkit::vpl_has_flux(view.vpl_at(static_cast<int>(i)))) ++stats.holes;
      }
      stats.filled = vplkit::gbg_fill_holes(raw.data(), weights.data(), view);
    }
    det["gbg"] = {{"gather_points", stats.gather_points}, {"rays", stats.rays},         {"hits", stats.hits},
                  {"lit_hits", stats.lit_hits},           {"reached_texels", stats.reached_texels},
                  {"holes", stats.holes},                 {"filled", stats.filled},     {"accumulator", to_string(es.gbg_accumulator)}};
    auto t = timer.scoped("cdf (cpu)");
    return vplkit::make_vpl_distribution(weights, view, es.eps);
  };

  switch (es.meth) {
    case method::reference:
    case method::gather:
      break;
    case method::global: {
      std::vector<float> weights(n_texels, 0.0f);
      int used = 0;
      {
        auto t = timer.scoped("global weights (cpu)");
        const std::vector<int> subset = vplkit::stratified_gather_subset(g, vplkit::full_image_rect(g), es.global_subset,
                                                                         builder_seed(es.seed, 0));
        const std::vector<gather_point<float>> pts = valid_points(g, subset);
        used = static_cast<int>(pts.size());
        global_weights(view, pts, es.dmin, weights.data(), threads);
      }
      det["global_subset"] = used;
      auto t = timer.scoped("cdf (cpu)");
      out.dists.push_back(vplkit::make_vpl_distribution(weights, view, es.eps));
      break;
    }
    case method::local: {
      const vplkit::image_regions regions(W, H, es.regions_x, es.regions_y);
      const int N = regions.count();
      std::vector<float> flat(static_cast<std::size_t>(N) * n_texels, 0.0f);
      std::vector<int> used(static_cast<std::size_t>(N), 0);
      {
        auto t = timer.scoped("local weights (cpu)");
        const auto subsets = vplkit::local_gather_subsets(g, regions, es.local_subset, builder_seed(es.seed, 1));
        for (int i = 0; i < N; ++i) {
          const std::vector<gather_point<float>> pts = valid_points(g, subsets[static_cast<std::size_t>(i)]);
          used[static_cast<std::size_t>(i)] = static_cast<int>(pts.size());
          global_weights(view, pts, es.dmin, flat.data() + static_cast<std::size_t>(i) * n_texels, threads);
        }
      }
      det["local_subsets"] = used;
      {
        auto t = timer.scoped("cdf (cpu)");
        out.dists = vplkit::make_local_vpl_distributions(flat, N, view, es.eps);
      }
      // N_NG rounds of one VPL per region's CDF: vpls / N rounds (at least one), so a pixel gets
      // about --vpls samples whatever N is.
      out.local_rounds = std::max(1, es.vpls / N);
      det["local_rounds"] = out.local_rounds;
      det["local_combination"] = to_string(es.local_combination);
      break;
    }
    case method::gbg:
    case method::mis:
    case method::mis_as_published:
      out.dists.push_back(build_gbg());
      break;
  }
  return out;
}

cpu_render_result render_cpu(const gbuffer_data& gb, const dprsm_data& dd, const vplkit::voxel_grid_view<float>& grid,
                             const estimator_settings& es, stage_timer& timer, const progress_fn& progress) {
  const vplkit::gbuffer_view<float> g = gb.view();
  const vplkit::dprsm_view<float> view = dd.view();
  g.validate();
  view.validate();
  const int threads = thread_count(es.threads);
  const int W = g.width, H = g.height;
  cpu_render_result result;
  result.image = image_rgb(W, H);
  nlohmann::json& det = result.details;
  det["threads"] = threads;
  det["dmin"] = es.dmin;

  const vplkit::voxel_visibility<float> visibility{grid};
  const vplkit::voxel_tracer<float> tracer{grid};
  const float depth_tol = gathering_depth_tolerance(grid);
  det["depth_tolerance"] = depth_tol;
  det["cdf_search"] = to_string(es.cdf_search);
  const cpu_distributions built = build_distributions_cpu(gb, dd, grid, es, timer, progress, det);
  const bool binary = es.cdf_search == cdf_search_choice::binary;
  std::vector<binary_searched_mixture> binary_dists;
  for (const auto& m : built.dists) binary_dists.push_back({&m});

  // Per-pixel loop shared by every method: est(gp, rng) -> vec3.
  auto render_pixels = [&](auto&& est) {
    auto t = timer.scoped("estimate (cpu)");
    parallel_items(H, threads, "render", progress, [&](int y, int) {
      for (int x = 0; x < W; ++x) {
        const int p = y * W + x;
        const gather_point<float> gp = g.at(p);
        vec3f c(0.0f);
        if (vplkit::gather_point_valid(gp)) {
          vplkit::counter_rng rng = vplkit::make_counter_rng(es.seed, static_cast<std::uint32_t>(p));
          c = est(gp, rng);
          if (es.direct) c += vplkit::direct_light(gp, view);
          c = vplkit::estimator_finite_or_zero(glm::max(c, vec3f(0.0f)));
        }
        float* o = result.image.at(x, y);
        o[0] = c.x;
        o[1] = c.y;
        o[2] = c.z;
      }
    });
  };

  switch (es.meth) {
    case method::reference: {
      render_pixels([&](const gather_point<float>& gp, vplkit::counter_rng&) {
        return vplkit::exhaustive_vpl_sum(gp, view, visibility, es.dmin);
      });
      break;
    }
    case method::global:
    case method::gbg: {
      const auto& dist = built.dists.front();
      if (binary)
        render_pixels([&](const gather_point<float>& gp, vplkit::counter_rng& rng) {
          return vplkit::estimate_vpl_sampling(gp, view, binary_dists.front(), rng, es.vpls, visibility, es.dmin);
        });
      else
        render_pixels([&](const gather_point<float>& gp, vplkit::counter_rng& rng) {
          return vplkit::estimate_vpl_sampling(gp, view, dist, rng, es.vpls, visibility, es.dmin);
        });
      break;
    }
    case method::local: {
      const int N = static_cast<int>(built.dists.size());
      const vplkit::local_combination comb = es.local_combination == local_combination_choice::average
                                                 ? vplkit::local_combination::average
                                                 : vplkit::local_combination::balance;
      if (binary)
        render_pixels([&](const gather_point<float>& gp, vplkit::counter_rng& rng) {
          return vplkit::estimate_local(gp, view, binary_dists.data(), N, rng, built.local_rounds, visibility, es.dmin,
                                        comb);
        });
      else
        render_pixels([&](const gather_point<float>& gp, vplkit::counter_rng& rng) {
          return vplkit::estimate_local(gp, view, built.dists.data(), N, rng, built.local_rounds, visibility, es.dmin,
                                        comb);
        });
      break;
    }
    case method::gather: {
      render_pixels([&](const gather_point<float>& gp, vplkit::counter_rng& rng) {
        return vplkit::estimate_gathering(gp, view, rng, es.dirs, tracer, depth_tol);
      });
      break;
    }
    case method::mis:
    case method::mis_as_published: {
      const auto& dist = built.dists.front();
      const vplkit::mis_mode mode =
          es.meth == method::mis ? vplkit::mis_mode::solid_angle : vplkit::mis_mode::as_published;
      if (binary)
        render_pixels([&](const gather_point<float>& gp, vplkit::counter_rng& rng) {
          return vplkit::estimate_mis(gp, view, binary_dists.front(), rng, es.dirs, es.vpls, tracer, visibility,
                                      depth_tol, mode);
        });
      else
        render_pixels([&](const gather_point<float>& gp, vplkit::counter_rng& rng) {
          return vplkit::estimate_mis(gp, view, dist, rng, es.dirs, es.vpls, tracer, visibility, depth_tol, mode);
        });
      break;
    }
  }
  return result;
}

}  // namespace vplrender
