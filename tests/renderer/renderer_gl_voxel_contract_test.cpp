// SPDX-License-Identifier: MIT
// --voxel-contract exact (CPU backend): the voxel march under exact visibility's contract (ends moved
// by exact's offset, every listed triangle counts, hits shaded with the interpolated shading normal,
// the lit test a ray through the grid) renders what --visibility exact (Embree) renders. Cornell
// with its corner normals bent into a smooth field, so that hits' shading normals matter, at 48x48:
// - the exhaustive VPL sum (visibility only, no sampling) and seeded gathering (the tracer, the hits'
//   shading and the lit test) are within 1e-5 relMSE of exact's images, with equal means to 1e-4;
// - the plane rule is farther from them (shown, so that the test can tell the two apart).
// The report names the contract (estimator.voxel_contract). Parsing: renderer_options_test.
#include "cli/render_options.hpp"
#include "cli/scene_setup.hpp"
#include "render/frame_buffers.hpp"
#include "render/pipeline.hpp"

#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include <glm/geometric.hpp>

#include <cmath>
#include <iostream>
#include <string>
#include <vector>

using namespace vplrender;

namespace {

struct image_error {
  double rel_mse = 0.0;     // mean over pixels of (a - b)^2 / mean(b)^2, luminance-free (RGB mean)
  double mean_ratio = 0.0;  // mean(a) / mean(b)
};

image_error compare(const image_rgb& a, const image_rgb& b) {
  const std::size_t n = a.rgb.size();
  double ma = 0.0, mb = 0.0, se = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    ma += a.rgb[i];
    mb += b.rgb[i];
    se += (double(a.rgb[i]) - double(b.rgb[i])) * (double(a.rgb[i]) - double(b.rgb[i]));
  }
  ma /= double(n);
  mb /= double(n);
  return image_error{se / double(n) / (mb * mb), ma / mb};
}

// Cornell's flat corner normals bent by a smooth field of the position (up to ~25 degrees), as a
// smoothed mesh's are: the shading normal then differs from the plane normal at every hit.
void bend_normals(scene& s) {
  for (triangle& t : s.triangles)
    for (std::size_t k = 0; k < 3; ++k) {
      const vec3 p = t.p[k];
      const vec3 bend(0.3f * std::sin(3.1f * p.y + 1.3f * p.z), 0.3f * std::cos(2.3f * p.x - 0.7f * p.z),
                      0.3f * std::sin(1.7f * p.x + 2.9f * p.y));
      t.n[k] = glm::normalize(t.n[k] + bend);
    }
}

}  // namespace

TEST_CASE("voxels under the exact contract render what exact visibility renders on the CPU backend") {
  pipeline_gl_context();
  options o;
  o.scene = "cornell";
  o.back = backend::cpu;
  o.width = 48;
  o.height = 48;
  o.dprsm = 16;
  o.voxels = 64;
  o.dirs = 64;
  o.progress = progress_mode::never;
  o.visibility = visibility_choice::exact;  // prepares the frame with exact rays too
  prepared_scene p = prepare_scene(o);
  bend_normals(p.s);
  stage_timer timer;
  nlohmann::json det;
  const frame_buffers b = prepare_buffers(o, p, timer, det);
  REQUIRE(b.corners);

  auto render = [&](method m, visibility_choice v, voxel_contract_choice c, lit_test_choice lit) {
    options ov = o;
    ov.meth = m;
    ov.visibility = v;
    ov.voxel_contract = c;
    ov.lit_test = lit;
    stage_timer t;
    nlohmann::json d;
    render_result r = run_estimator(ov, p, b, t, {}, d);
    if (v == visibility_choice::voxels) CHECK(d["estimator"]["voxel_contract"] == to_string(c));
    return r.image;
  };
  const auto shadow_ray = lit_test_choice::shadow_ray, shadow_map = lit_test_choice::shadow_map;
  const auto exact = voxel_contract_choice::exact, plane = voxel_contract_choice::plane_rule;
  for (const method m : {method::reference, method::gather}) {
    const image_rgb ref = render(m, visibility_choice::exact, plane, shadow_ray);
    const image_error contract = compare(render(m, visibility_choice::voxels, exact, shadow_ray), ref);
    const image_error rule = compare(render(m, visibility_choice::voxels, plane, shadow_map), ref);
    std::cout << "cornell (bent normals) 48x48, 64^3, " << to_string(m) << " against exact visibility: exact "
              << "contract relMSE " << contract.rel_mse << " mean ratio " << contract.mean_ratio
              << "; plane rule relMSE " << rule.rel_mse << " mean ratio " << rule.mean_ratio << "\n";
    INFO(to_string(m));
    CHECK(contract.rel_mse <= 1e-5);
    CHECK(std::abs(contract.mean_ratio - 1.0) <= 1e-4);
    CHECK(rule.rel_mse >= 10.0 * contract.rel_mse);
  }
}
