// SPDX-License-Identifier: MIT
#include "reference_cache.hpp"

#include "report_format.hpp"

#include "io/errors.hpp"
#include "io/exr_io.hpp"
#include "render/stage_timer.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

namespace speed_vs_error {

using namespace vplrender;
namespace fs = std::filesystem;

namespace {

std::uint64_t fnv1a(const std::string& s) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
  return h;
}

}  // namespace

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
  // Only when not the default, so the keys (and cached files) of earlier references stay what they were.
  if (kind == "vplsum" && o.dmin_fraction != 0.01) k += "|dmin=" + num(o.dmin_fraction);
  // Only when exact, so the keys (and cached files) of voxel references stay what they were.
  if (o.visibility == visibility_choice::exact && kind != "exact") k += "|visibility=exact";
  // Likewise the voxel march's contract, only when not the plane rule.
  if (o.visibility == visibility_choice::voxels && o.voxel_contract == voxel_contract_choice::exact && kind != "exact")
    k += "|voxel_contract=exact";
  // Gathering references shade known hits as their own surface and take the lit test: keys of the
  // older ones (the texel's normal, the shadow map always) do not match them.
  if (kind == "gather") k += std::string("|hits=own-surface|lit=") + to_string(o.lit_test);
  if (kind == "gather" || kind == "exact") k += "|dirs=" + std::to_string(dirs) + "|seed=" + std::to_string(seed);
  // The exact reference runs on --backend's estimator; "backend=gpu" entries written before it had a
  // GPU kernel hold CPU images: a key of their own.
  if (kind == "exact" && o.back == backend::gpu) k += "|exact_estimator=gpu";
  // Exact references place the hemisphere on the G-buffer's geometric normal and take a hit's side
  // from x; older ones took the normal of the triangle the camera ray met (at pixels on edges
  // another triangle's) and the side from the lifted ray origin (wrong at some junctions).
  if (kind == "exact") k += "|exact=gbuffer-normal,x-side";
  // Only with the clamp compensation (the reference adds it as the VPL methods do), so the keys of
  // clamped sums stay what they were.
  if (kind == "vplsum") {
    options r = o;
    r.meth = method::reference;
    const render_settings rs = make_render_settings(r, p.s);
    if (uses_clamp_compensation(rs)) k += "|clamp_compensation_dirs=" + std::to_string(clamp_compensation_dirs(rs));
  }
  // Only for patch VPLs, so the keys of point VPL sums stay what they were.
  if (kind == "vplsum" && o.vpl_mode == vpl_mode_choice::patch)
    k += "|vpl_mode=patch|strata=" + std::to_string(reference_patch_strata) + "|seed=" + std::to_string(seed);
  return k;
}

reference_image get_reference(const options& base, const prepared_scene& p, const frame_buffers& b,
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
  o.meth = kind == "gather" ? method::gather : kind == "exact" ? method::exact : method::reference;
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

}  // namespace speed_vs_error
