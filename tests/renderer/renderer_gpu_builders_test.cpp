// SPDX-License-Identifier: MIT
// The GPU backend's builders and CDFs against the C++ ones on the same G-buffer and DPRSM:
//  - global and local (2 x 2 regions) weights from build_brsm_weights_gpu (gather_subset.comp +
//    global_weights.comp) against vplkit::build_global_weights / build_local_weights on the CPU
//    builder's subsets (stratified_gather_subset / local_gather_subsets, same seeds);
//  - the CDFs of build_mixtures_gpu (cdf_build.comp, double accumulation) against
//    vplkit::discrete_cdf<float> built from the SAME weights (read back), and the mixture scalars
//    against vplkit::make_vpl_distribution's.
#include "renderer_gl_fixture.hpp"

#include "cli/render_options.hpp"
#include "cli/scene_setup.hpp"
#include "raster/gl_raster.hpp"
#include "raster/tessellate.hpp"
#include "raster/voxels.hpp"
#include "render/cpu/cpu_backend.hpp"
#include "render/cpu/cpu_builders.hpp"
#include "render/gpu/gpu_backend.hpp"
#include "render/gpu/gpu_builders.hpp"
#include "render/gpu/gpu_cdf.hpp"
#include "scene/builtin_scenes.hpp"

#include <vplkit/builders/gather_subset.hpp>
#include <vplkit/builders/global_weights.hpp>
#include <vplkit/builders/local_weights.hpp>
#include <vplkit/builders/vpl_distribution.hpp>
#include <vplkit/core/float_bits.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iostream>

using namespace vplrender;

namespace {

using fixture = vplrender_test::gl_fixture;

// 64x48 pixels, DPRSM 2 x dprsm^2, 32^3 voxels, the default VPL and direction counts.
fixture make_fixture(const char* scene_name, int dprsm = 16) {
  vplrender::options o = vplrender_test::small_options(scene_name, 64, 48, dprsm, 32);
  o.vpls = vplrender::options{}.vpls;
  o.dirs = vplrender::options{}.dirs;
  return vplrender_test::make_gl_fixture(o);
}

long long ulp_distance(float a, float b) {  // both >= 0
  return std::llabs(static_cast<long long>(vplkit::float_bits(a)) - static_cast<long long>(vplkit::float_bits(b)));
}

// Per texel: both sides evaluate luminance(vpl_contribution) in float (the GPU's length / sqrt /
// division a few ulps off, FMA contraction: <= 8 ulps per term, parity_vpl_test) and add the |S|
// terms in float in the same order, then multiply by 1 / |S|. Perturbed inputs can flip each of the
// |S| - 1 roundings of the running sum by at most one half-ulp of the running sum (<= the final
// sum, positive terms) per side, so |gpu - cpu| <= (8 + |S|) 2^-24 w (+ 1e-30 for zeros).
double weight_bound(double w, int subset_size) { return (8.0 + subset_size) * std::ldexp(1.0, -24) * w + 1e-30; }

struct weight_stats {
  int outside = 0, nonzero = 0, zero_mismatch = 0;
  double worst_rel = 0.0, worst_ratio = 0.0;
};

void compare_weights(const std::vector<float>& gpu, const float* cpu, std::size_t n, int subset_size, weight_stats& s) {
  for (std::size_t t = 0; t < n; ++t) {
    const double a = cpu[t], b = gpu[t];
    REQUIRE(std::isfinite(b));
    if ((a == 0.0) != (b == 0.0)) ++s.zero_mismatch;
    if (a != 0.0) ++s.nonzero;
    const double diff = std::abs(a - b), bound = weight_bound(std::max(a, b), subset_size);
    if (diff > bound) ++s.outside;
    s.worst_ratio = std::max(s.worst_ratio, diff / bound);
    if (a > 0.0) s.worst_rel = std::max(s.worst_rel, diff / a);
  }
}

// The C++ guide definition on a stored cdf: guide[j] = largest i in [0, n - 1] with cdf[i] <= j / m
// (computed exactly as ceil(cdf[i] m) <= j, m a power of two).
std::vector<std::uint32_t> guide_of(const float* cdf, std::size_t n, std::size_t m) {
  std::vector<std::uint32_t> g(m + 1, 0u);
  std::size_t i = 0;
  for (std::size_t j = 0; j <= m; ++j) {
    while (i + 1 < n && std::ceil(double(cdf[i + 1]) * double(m)) <= double(j)) ++i;
    g[j] = static_cast<std::uint32_t>(i);
  }
  return g;
}

struct cdf_stats {
  long long differing = 0, values = 0;
  long long worst_ulps = 0;
  int guide_mismatch = 0, total_mismatch = 0;
};

// Distribution k of `gm` (whose GPU arrays `data` holds) against discrete_cdf built from `w`.
void compare_cdf(const gpu_mixtures& gm, const std::vector<std::uint32_t>& data, std::size_t k, const float* w,
                 cdf_stats& s) {
  const std::size_t n = gm.n, m = gm.m;
  const vplkit::discrete_cdf<float> ref(w, n);
  REQUIRE(ref.size() == n);
  REQUIRE(ref.guide_size() == m);
  std::vector<float> cdf(n + 1);
  std::memcpy(cdf.data(), data.data() + gm.cdf_offset[k], (n + 1) * 4);
  const std::uint32_t* guide = data.data() + gm.guide_offset[k];
  bool same = true;
  for (std::size_t i = 0; i <= n; ++i) {
    const long long u = ulp_distance(cdf[i], ref.cdf()[i]);
    if (u != 0) {
      ++s.differing;
      same = false;
    }
    s.worst_ulps = std::max(s.worst_ulps, u);
    ++s.values;
  }
  // Guide: exactly the C++ definition on the stored cdf (so equal to the C++ guide where the cdfs
  // are equal).
  const std::vector<std::uint32_t> expect = same ? std::vector<std::uint32_t>(ref.guide().begin(), ref.guide().end())
                                                 : guide_of(cdf.data(), n, m);
  for (std::size_t j = 0; j <= m; ++j)
    if (guide[j] != expect[j]) ++s.guide_mismatch;
  if (ulp_distance(gm.totals[k], ref.total()) > 1) ++s.total_mismatch;
}

}  // namespace

TEST_CASE("GPU global and local weights equal the CPU builders' within the float-sum bound") {
  for (const char* scene_name : {"cornell", "open"}) {
    fixture f = make_fixture(scene_name);
    render_settings es = make_render_settings(f.o, f.p.s);
    const auto g = f.b.gbuf.view();
    const auto view = f.b.dprsm.view();
    const std::size_t n = static_cast<std::size_t>(view.texel_count());
    stage_timer timer;
    // Global.
    {
      const std::vector<int> subset =
          vplkit::stratified_gather_subset(g, vplkit::full_image_rect(g), es.global_subset, builder_seed(es.seed, 0));
      const std::vector<float> cpu = vplkit::build_global_weights(g, subset, view, es.dmin);
      const gpu_weights gw = build_brsm_weights_gpu(f.b, es, false, timer);
      REQUIRE(gw.regions == 1);
      REQUIRE(gw.weights.size_bytes() == 2 * n * 4);
      CHECK(gw.used.front() == static_cast<int>(subset.size()));  // every stratum's pick is valid
      const std::vector<float> gpu = gw.weights.read<float>(n);
      weight_stats s;
      compare_weights(gpu, cpu.data(), n, gw.used.front(), s);
      std::cout << scene_name << " global weights (|S| = " << gw.used.front() << "): " << s.nonzero
                << " non-zero texels, worst relative " << s.worst_rel << ", worst |gpu - cpu| / bound "
                << s.worst_ratio << "\n";
      CHECK(s.nonzero > 0);
      CHECK(s.zero_mismatch == 0);
      CHECK(s.outside == 0);
    }
    // Local, 2 x 2 regions.
    {
      const vplkit::image_regions regions(g.width, g.height, es.regions_x, es.regions_y);
      const int N = regions.count();
      const auto subsets = vplkit::local_gather_subsets(g, regions, es.local_subset, builder_seed(es.seed, 1));
      std::vector<float> cpu(static_cast<std::size_t>(N) * n);
      std::vector<int> used(static_cast<std::size_t>(N));
      vplkit::build_local_weights(g, regions, subsets, view, es.dmin, cpu.data(), cpu.size(), used.data());
      const gpu_weights gw = build_brsm_weights_gpu(f.b, es, true, timer);
      REQUIRE(gw.regions == N);
      CHECK(gw.used == used);
      const std::vector<float> gpu = gw.weights.read<float>(static_cast<std::size_t>(N) * n);
      weight_stats s;
      for (int i = 0; i < N; ++i) {
        const std::vector<float> part(gpu.begin() + static_cast<long>(i * n), gpu.begin() + static_cast<long>((i + 1) * n));
        compare_weights(part, cpu.data() + static_cast<std::size_t>(i) * n, n, used[static_cast<std::size_t>(i)], s);
      }
      std::cout << scene_name << " local weights (" << N << " regions, |S_i| = " << used[0] << " ..): " << s.nonzero
                << " non-zero texels, worst relative " << s.worst_rel << ", worst |gpu - cpu| / bound "
                << s.worst_ratio << "\n";
      CHECK(s.nonzero > 0);
      CHECK(s.zero_mismatch == 0);
      CHECK(s.outside == 0);
    }
  }
}

TEST_CASE("GPU-built CDFs equal vplkit::discrete_cdf of the same weights within 1 ulp") {
  // docs/glsl/distribution.md: every cdf_build.comp value is the C++ value or a float neighbour,
  // differing only near a rounding tie of the exact quotient; the guide is exactly the C++
  // definition on the stored cdf; totals within 1 ulp (measured: bit-equal). DPRSM 2 x 64 x 64:
  // 8192 weights, 8 blocks of cdf_build.comp (the cross-block scan and prefix max run).
  for (const char* scene_name : {"cornell", "open"}) {
    fixture f = make_fixture(scene_name, 64);
    render_settings es = make_render_settings(f.o, f.p.s);
    const auto view = f.b.dprsm.view();
    const std::size_t n = static_cast<std::size_t>(view.texel_count());
    const vplkit::gl::buffer& dprsm = f.b.gpu->dprsm;
    for (bool local : {false, true}) {
      stage_timer timer;
      nlohmann::json det;
      const gpu_weights gw = build_brsm_weights_gpu(f.b, es, local, timer);
      const int D = gw.regions;
      const std::vector<float> w = gw.weights.read<float>(static_cast<std::size_t>(D) * n);
      for (float eps : {es.eps, 0.0f}) {
        const gpu_mixtures gm = build_mixtures_gpu(gw.weights, D, dprsm, view, eps, timer, det);
        REQUIRE(gm.count == D);
        REQUIRE(gm.n == n);
        const std::vector<std::uint32_t> data = gm.data.read<std::uint32_t>();
        cdf_stats s;
        for (int d = 0; d < D; ++d) compare_cdf(gm, data, static_cast<std::size_t>(d), w.data() + d * n, s);
        // The fallback: make_vpl_fallback's CDF (uniform over the texels carrying a VPL).
        const vplkit::discrete_cdf<float> fb = vplkit::make_vpl_fallback(view);
        if (eps > 0.0f) {
          std::vector<float> ones(n);
          for (std::size_t t = 0; t < n; ++t) ones[t] = vplkit::vpl_has_flux(view.vpl_at(static_cast<int>(t))) ? 1.0f : 0.0f;
          compare_cdf(gm, data, static_cast<std::size_t>(D), ones.data(), s);
        }
        // The mixture scalars and records equal make_vpl_distribution's.
        const std::vector<std::uint32_t> meta = gm.meta.read<std::uint32_t>();
        for (int d = 0; d < D; ++d) {
          const std::vector<float> wd(w.begin() + static_cast<long>(d * n), w.begin() + static_cast<long>((d + 1) * n));
          const vplkit::defensive_mixture<float> ref = vplkit::make_vpl_distribution(wd, view, eps);
          const std::uint32_t* rec = meta.data() + 12 * d;
          CHECK(rec[1] == ref.learned().size());
          CHECK(rec[2] == ref.learned().guide_size());
          CHECK(ulp_distance(gm.totals[static_cast<std::size_t>(d)], ref.learned().total()) <= 1);
          CHECK(rec[5] == ref.fallback().size());
          CHECK(rec[6] == ref.fallback().guide_size());
          CHECK(rec[7] == vplkit::float_bits(ref.fallback().total()));
          CHECK(rec[8] == vplkit::float_bits(ref.effective_eps()));
          CHECK(rec[9] == vplkit::float_bits(ref.fallback_scale()));
          CHECK(rec[10] == vplkit::float_bits(ref.learned_scale()));
        }
        if (eps > 0.0f) CHECK(gm.totals.back() == fb.total());
        std::cout << scene_name << (local ? " local" : " global") << " eps " << eps << ": " << s.differing << " of "
                  << s.values << " cdf values differ (worst " << s.worst_ulps << " ulp), guide mismatches "
                  << s.guide_mismatch << ", totals off by > 1 ulp " << s.total_mismatch << "\n";
        CHECK(s.worst_ulps <= 1);
        CHECK(s.guide_mismatch == 0);
        CHECK(s.total_mismatch == 0);
        CHECK(det["cdf"]["backend"] == "gpu");
      }
    }
  }
}

TEST_CASE("GPU distributions: builder facts use the CPU builder's keys, and both builders take the subset sizes") {
  fixture f = make_fixture("cornell");
  // Not the defaults (256): --global-subset and --local-subset reach both backends' builders.
  f.o.global_subset = 7;
  f.o.local_subset = 5;
  for (method m : {method::global, method::local, method::gbg}) {
    f.o.meth = m;
    render_settings es = make_render_settings(f.o, f.p.s);
    es.threads = 2;
    stage_timer tc, tg;
    nlohmann::json dc, dg;
    const cpu_distributions c = build_distributions_cpu(f.b, es, tc, {}, dc);
    const gpu_mixtures gm = build_distributions_gpu(f.b, es, tg, dg);
    CHECK(gm.count == static_cast<int>(c.dists.size()));
    CHECK(gm.local_rounds == c.local_rounds);
    for (auto it = dc.begin(); it != dc.end(); ++it) {
      INFO(to_string(m) << " key " << it.key());
      CHECK(dg.contains(it.key()));
    }
    if (m == method::global) {
      CHECK(dc["global_subset"] == 7);
      CHECK(dg["global_subset"] == dc["global_subset"]);
    }
    if (m == method::local) {
      CHECK(dc["local_subsets"] == nlohmann::json::array({5, 5, 5, 5}));
      CHECK(dg["local_subsets"] == dc["local_subsets"]);
      CHECK(dg["local_combination"] == dc["local_combination"]);
    }
    CHECK(dg["builders"] == "gpu");
  }
}
