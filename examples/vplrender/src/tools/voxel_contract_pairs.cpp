// SPDX-License-Identifier: MIT
// voxel_contract_pairs: how often the triangle voxel march disagrees with exact visibility (Embree),
// under each of its contracts (docs/math.md 7.2, "Where the end rule and the offset differ").
// Takes vplrender's scene flags (--scene --camera --light --size --dprsm --voxels; CPU backend),
// pairs every gather point with every N-th DPRSM texel that sees a surface (--every N, default 4),
// keeps the pairs that face each other (the receiver's geometric and shading cosines, the texel's
// cosine all positive), and prints, for the plane rule and for the exact contract, the pairs whose
// answer differs from Embree's, their share of the weight cos cos / max(r^2, 1e-4), and the relMSE
// of the per-pixel weighted sums against Embree's.
//   voxel_contract_pairs [--every N] VPLRENDER_FLAGS...
#include "cli/options.hpp"
#include "cli/render_options.hpp"
#include "cli/scene_setup.hpp"
#include "io/errors.hpp"
#include "render/cpu/cpu_visibility.hpp"
#include "render/cpu/ray_scene.hpp"
#include "render/frame_buffers.hpp"
#include "render/pipeline.hpp"

#include <vplkit/visibility/triangle_voxel_query.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

using namespace vplrender;

namespace {

struct tally {
  long differ = 0;
  double weight = 0.0;
  std::vector<double> sums;
};

int run(std::vector<std::string> args) {
  int every = 4;
  for (std::size_t i = 0; i + 1 < args.size(); ++i)
    if (args[i] == "--every") {
      every = std::stoi(args[i + 1]);
      if (every < 1) throw usage_error("--every: must be at least 1");
      args.erase(args.begin() + std::ptrdiff_t(i), args.begin() + std::ptrdiff_t(i) + 2);
      break;
    }
  args.insert(args.begin(), "voxel_contract_pairs");
  args.insert(args.end(), {"--backend", "cpu", "--visibility", "exact"});  // the frame's exact rays
  const parse_result pr = parse_command_line(args);
  if (pr.what != parse_result::action::run) {
    std::printf("%s", pr.help.c_str());
    return 0;
  }
  const options& o = pr.opts;
  const prepared_scene p = prepare_scene(o);
  stage_timer timer;
  nlohmann::json det;
  const frame_buffers b = prepare_buffers(o, p, timer, det);
  const ray_scene& rays = frame_ray_scene(b, "voxel_contract_pairs");
  const auto grid = b.grid.view();
  const float offset = rays.surface_offset();
  const std::size_t pixels = b.gbuf.position.size(), texels = b.dprsm.position.size();
  tally rule, contract;
  rule.sums.assign(pixels, 0.0);
  contract.sums.assign(pixels, 0.0);
  std::vector<double> exact_sums(pixels, 0.0);
  long pairs = 0;
  double total = 0.0;
  for (std::size_t i = 0; i < pixels; ++i) {
    const vec3 x = b.gbuf.position[i];
    vec3 nx = b.gbuf.normal[i];
    if (!(glm::dot(nx, nx) > 0.0f)) continue;
    nx = glm::normalize(nx);
    vec3 ns = b.gbuf.shading_normal.empty() ? nx : b.gbuf.shading_normal[i];
    ns = glm::dot(ns, ns) > 0.0f ? glm::normalize(ns) : nx;
    for (std::size_t t = 0; t < texels; t += std::size_t(every)) {
      const vec3 ny_raw = b.dprsm.normal[t];
      if (b.dprsm.albedo[t] == vec3(0.0f) || !(glm::dot(ny_raw, ny_raw) > 0.0f)) continue;
      const vec3 y = b.dprsm.position[t], ny = glm::normalize(ny_raw);
      const vec3 d = y - x;
      const float r2 = glm::dot(d, d);
      if (!(r2 > 0.0f)) continue;
      const vec3 w = d / std::sqrt(r2);
      const float cx = glm::dot(ns, w), cy = -glm::dot(ny, w);
      if (!(cx > 0.0f) || !(cy > 0.0f) || !(glm::dot(nx, w) > 0.0f)) continue;
      const double weight = double(cx) * double(cy) / double(std::max(r2, 1e-4f));
      const bool e = rays.visible(x, nx, y, ny);
      const bool r = vplkit::triangle_voxel_visible(grid, x, y);
      const bool c = vplkit::triangle_voxel_visible_offset(grid, x, nx, y, ny, offset);
      ++pairs;
      total += weight;
      if (e) exact_sums[i] += weight;
      for (auto [v, tl] : {std::pair<bool, tally*>{r, &rule}, std::pair<bool, tally*>{c, &contract}}) {
        if (v) tl->sums[i] += weight;
        if (v != e) {
          ++tl->differ;
          tl->weight += weight;
        }
      }
    }
  }
  double mean = 0.0;
  for (double s : exact_sums) mean += s;
  mean /= double(pixels);
  std::printf("%ld pairs (%zu gather points, every %d-th texel), Embree's offset %g\n", pairs, pixels, every, double(offset));
  for (auto [name, tl] : {std::pair<const char*, tally*>{"plane rule", &rule}, std::pair<const char*, tally*>{"exact contract", &contract}}) {
    double se = 0.0;
    for (std::size_t i = 0; i < pixels; ++i) se += (tl->sums[i] - exact_sums[i]) * (tl->sums[i] - exact_sums[i]);
    std::printf("%-15s differs from Embree on %ld pairs (%.4f %%), %.4f %% of the weight; per-pixel sums relMSE %.3e\n",
                name, tl->differ, 100.0 * double(tl->differ) / double(std::max(1L, pairs)), 100.0 * tl->weight / total,
                se / double(pixels) / (mean * mean));
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(std::vector<std::string>(argv + 1, argv + argc));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "voxel_contract_pairs: %s\n", e.what());
    return 1;
  }
}
