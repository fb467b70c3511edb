// CPU/GPU parity of vplrender's estimators: the same G-buffer, DPRSM and voxel grid rendered by the
// C++ templates (render_cpu) and by the compute shader of the GLSL pack (render_gpu), every method,
// both built-in scenes, 24x16 pixels, DPRSM 2x16x16, 32^3 voxels.
//
// The bound. Both sides run the T = float arithmetic on the same inputs with the same random bits
// (make_counter_rng(seed, pixel), exact on both sides) and the same CDF arrays (built once on the
// CPU, sampled bit for bit by the pack). What may differ: the GPU contracts a * b + c into FMAs
// outside `precise` code, its sqrt/div/sin/cos are not required to round correctly (a few ulp on
// llvmpipe), and the reference sums in compensated float where the C++ sums in double. Over the
// at most a few dozen terms of a pixel this stays well below 1e-5 relative (measured worst, printed
// below). A pixel can also differ by a whole sample when a last-ulp difference flips a decision: a
// sampled CDF index at a bin edge, a DDA step at a voxel-boundary tie, a cosine or depth test at
// its threshold. Such pixels are rare; we require >= 99% of the pixels within the bound and every
// pixel finite and non-negative on both sides.
#include "builtin_scenes.hpp"
#include "cpu_backend.hpp"
#include "gl_raster.hpp"
#include "gpu_backend.hpp"
#include "pipeline.hpp"
#include "scene_setup.hpp"
#include "tessellate.hpp"
#include "voxels.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>

using namespace vplrender;

namespace {

// Per channel: |gpu - cpu| <= rel * max(|cpu|, |gpu|) + abs_floor, abs_floor = 1e-6 of the CPU
// image's mean (values at the level of float noise around zero count as equal).
constexpr double rel_bound = 1e-5;  // measured worst 7.9e-7 (open, mis-as-published): ~13x margin
constexpr double required_fraction = 0.99;

struct parity {
  double within = 0.0;      // fraction of pixels within the bound
  double worst_rel = 0.0;   // worst relative difference among pixels within the bound
  double worst_any = 0.0;   // worst relative difference overall
  int worst_x = -1, worst_y = -1;
};

parity compare(const image_rgb& c, const image_rgb& g) {
  double mean = 0.0;
  for (float v : c.rgb) mean += v;
  mean /= std::max<std::size_t>(1, c.rgb.size());
  const double floor_abs = 1e-6 * mean;
  parity r;
  int ok = 0;
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      bool inside = true;
      double worst = 0.0;
      for (int k = 0; k < 3; ++k) {
        const double a = c.at(x, y)[k], b = g.at(x, y)[k];
        REQUIRE(std::isfinite(a));
        REQUIRE(std::isfinite(b));
        REQUIRE(a >= 0.0);
        REQUIRE(b >= 0.0);
        const double d = std::abs(a - b), m = std::max(std::abs(a), std::abs(b));
        if (d > rel_bound * m + floor_abs) inside = false;
        if (m > 0.0) worst = std::max(worst, d / m);
      }
      if (inside) {
        ++ok;
        r.worst_rel = std::max(r.worst_rel, worst);
      }
      if (worst > r.worst_any) {
        r.worst_any = worst;
        r.worst_x = x;
        r.worst_y = y;
      }
    }
  r.within = static_cast<double>(ok) / static_cast<double>(c.width * c.height);
  return r;
}

void run_scene(const std::string& scene_name) {
  pipeline_gl_context();
  options o;
  o.scene = scene_name;
  o.width = 24;
  o.height = 16;
  o.dprsm = 16;
  o.voxels = 32;
  o.vpls = 8;
  o.dirs = 8;
  o.progress = progress_mode::never;
  const prepared_scene p = prepare_scene(o);
  gl_rasterizer raster(p.s);
  const gbuffer_data g = raster.render_gbuffer(p.s.cam, o.width, o.height);
  tessellation_params tp;
  tp.max_angle = tessellation_angle_for_resolution(o.dprsm);
  const dprsm_data d = raster.render_dprsm(dprsm_light(p.s), o.dprsm, tp);
  const vplkit::voxel_grid<float> grid = voxelize_cpu(p.s, o.voxels);
  for (method m : {method::reference, method::global, method::local, method::gbg, method::gather, method::mis,
                   method::mis_as_published}) {
    if (!gpu_estimator_available(m)) continue;
    o.meth = m;
    estimator_settings es = make_estimator_settings(o, p.s);
    es.threads = 2;
    stage_timer tc, tg;
    const image_rgb c = render_cpu(g, d, grid.view(), es, tc).image;
    const image_rgb gi = render_gpu(g, d, grid.view(), es, tg).image;
    const parity r = compare(c, gi);
    std::cout << scene_name << " " << to_string(m) << ": " << 100.0 * r.within << "% of pixels within "
              << rel_bound << " relative; worst inside " << r.worst_rel << ", worst overall " << r.worst_any
              << " at pixel (" << r.worst_x << ", " << r.worst_y << ")\n";
    INFO(scene_name << " " << to_string(m) << ": worst pixel (" << r.worst_x << ", " << r.worst_y << ") rel "
                    << r.worst_any);
    CHECK(r.within >= required_fraction);
  }
}

}  // namespace

TEST_CASE("GPU estimators match the CPU backend on the cornell scene") { run_scene("cornell"); }

TEST_CASE("GPU estimators match the CPU backend on the open scene") { run_scene("open"); }

TEST_CASE("the pass split keeps short loops in one pass and splits long ones") {
  // The cornell/open cases above already run the reference in two passes (512 texels at 32^3
  // voxels), so the per-pixel state carried between passes is covered by the parity itself.
  estimator_settings es;
  es.meth = method::gbg;
  es.vpls = 64;
  CHECK(gpu_pass_count(es, 16, vplkit::ivec3(32), 1) == 1);
  es.meth = method::reference;
  CHECK(gpu_pass_count(es, 16, vplkit::ivec3(32), 1) == 2);
  CHECK(gpu_pass_count(es, 512, vplkit::ivec3(128), 1) > 1000);
  es.meth = method::mis;
  es.vpls = 800;
  es.dirs = 800;
  CHECK(gpu_pass_count(es, 512, vplkit::ivec3(128), 1) > 1);
}
