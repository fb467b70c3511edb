// SPDX-License-Identifier: MIT
// The DPRSM's rim (docs/math.md section 1, "The rim band"): the walls at the light's height are
// seen through the seam between the two paraboloids. Wherever an exact shadow ray (Embree) says a
// G-buffer point is lit, the DPRSM's shadow test must find its surface there too: a direction
// whose uv falls in the part of a rim texel square that lies inside the unit disk but whose centre
// lies outside (an invalid texel) was filed under that invalid texel and called unlit, a row of
// dark dots along the seam on the walls of the Cornell box at the light's height.
#include "renderer_direct_reference.hpp"
#include "renderer_gl_fixture.hpp"

#include <vplkit/vpl/direct_light.hpp>

#include <catch2/catch.hpp>

#include <glm/geometric.hpp>

#include <cmath>
#include <iostream>
#include <string>

using namespace vplrender;
using vplrender_test::gl_fixture;

namespace {

bool positive(vec3 c) { return c.x > 0.0f || c.y > 0.0f || c.z > 0.0f; }

struct seam_count {
  int lit_ref = 0;           // pixels the scene lights
  int dark = 0;              // of those, black in the DPRSM's direct light
  int seam_lit_ref = 0;      // pixels the scene lights within 4/R of the rim (in light-space z)
  int seam_dark = 0;         // of those, black in the DPRSM's direct light
  int seam_dark_invalid = 0; // ... because the lookup's texel is invalid
  int seam_dark_empty = 0;   // ... because it saw nothing
  int seam_dark_plane = 0;   // ... although it saw the pixel's own plane
  int seam_dark_other = 0;   // ... because it saw another surface (a silhouette seen from the light)
};

// The C++ direct light (the GLSL is parity-tested against it) against the scene's at every pixel.
seam_count count_dark(const gl_fixture& f) {
  const ray_scene rs(f.p.s);
  const gbuffer_data& g = f.b.gbuf;
  const vplkit::gbuffer_view<float> gv = g.view();
  const vplkit::dprsm_view<float> dv = f.b.dprsm.view();
  const float seam = 4.0f / float(dv.resolution);
  seam_count c;
  for (int p = 0; p < g.width * g.height; ++p) {
    const vplkit::gather_point<float> gp = gv.at(p);
    if (!vplkit::gather_point_valid(gp)) continue;
    if (!positive(vplrender_test::scene_direct_light(rs, f.p.s, dv.light, gp.position))) continue;
    const vec3 l = dv.light.frame.to_light(gp.position - dv.light.position);
    const bool at_seam = std::abs(l.z) <= seam * glm::length(l);
    const bool dark = !positive(vplkit::direct_light(gp, dv));
    ++c.lit_ref;
    c.dark += dark;
    if (!at_seam) continue;
    ++c.seam_lit_ref;
    if (!dark) continue;
    ++c.seam_dark;
    const int t = dv.texel_of_point(gp.position);
    if (!dv.texel_valid(t))
      ++c.seam_dark_invalid;
    else if (!positive(dv.albedo[t]))
      ++c.seam_dark_empty;
    else if (glm::dot(dv.normal[t], gp.normal) > 0.999f * glm::length(dv.normal[t]) * glm::length(gp.normal) &&
             std::abs(glm::dot(glm::normalize(gp.normal), dv.position[t] - gp.position)) < 1e-3f)
      ++c.seam_dark_plane;
    else
      ++c.seam_dark_other;
  }
  return c;
}

}  // namespace

TEST_CASE("DPRSM rim: the walls at the light's height are lit wherever an exact shadow ray says so") {
  for (const char* name : {"cornell", "open"})
    for (int R : {64, 512}) {
      const gl_fixture f = vplrender_test::make_gl_fixture(vplrender_test::small_options(name, 256, 256, R, 32));
      const seam_count c = count_dark(f);
      std::cout << name << ", DPRSM 2x" << R << "^2, 256x256: " << c.lit_ref << " pixels lit in the scene, "
                << c.dark << " black in direct light; within 4/R of the rim " << c.seam_lit_ref << " lit, " << c.seam_dark
                << " black (" << c.seam_dark_invalid << " through an invalid texel, " << c.seam_dark_empty
                << " through an empty one, " << c.seam_dark_plane << " through one showing the pixel's plane, "
                << c.seam_dark_other << " through one showing another surface)\n";
      INFO(name << " R " << R);
      REQUIRE(c.seam_lit_ref > 100);
      CHECK(c.seam_dark_invalid == 0);
      CHECK(c.seam_dark_empty == 0);
      CHECK(c.seam_dark_plane == 0);
      // What is left is a shadow map's silhouette texels (a face seen at grazing incidence whose
      // texel centres see the wall behind it; black along its whole height, not only at the seam).
      CHECK(c.seam_dark_other <= c.seam_lit_ref / 100);
    }
}

TEST_CASE("DPRSM rim: both backends' direct light on the Cornell box's seam row (R = 64)") {
  // The images of both backends (the GLSL lookup on the GPU), against the exact shadow ray.
  const gl_fixture f = vplrender_test::make_gl_fixture(vplrender_test::small_options("cornell", 128, 128, 64, 32));
  const ray_scene rs(f.p.s);
  const gbuffer_data& g = f.b.gbuf;
  const vplkit::gbuffer_view<float> gv = g.view();
  const vplkit::dprsm_view<float> dv = f.b.dprsm.view();
  const image_rgb cpu = vplrender_test::direct_image(f, false), gpu = vplrender_test::direct_image(f, true);
  int seam_lit = 0, dark_cpu = 0, dark_gpu = 0;
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const vplkit::gather_point<float> gp = gv.at(x, y);
      if (!vplkit::gather_point_valid(gp)) continue;
      const vec3 l = dv.light.frame.to_light(gp.position - dv.light.position);
      if (!(std::abs(l.z) <= 4.0f / 64.0f * glm::length(l))) continue;
      if (!positive(vplrender_test::scene_direct_light(rs, f.p.s, dv.light, gp.position))) continue;
      ++seam_lit;
      const float* c = cpu.at(x, y);
      const float* q = gpu.at(x, y);
      dark_cpu += !positive(vec3(c[0], c[1], c[2]));
      dark_gpu += !positive(vec3(q[0], q[1], q[2]));
    }
  std::cout << "cornell, DPRSM 2x64^2, 128x128: " << seam_lit << " pixels within 4/R of the rim lit in the scene; black "
            << "in direct light: cpu " << dark_cpu << ", gpu " << dark_gpu << "\n";
  REQUIRE(seam_lit > 100);
  CHECK(dark_cpu == 0);
  CHECK(dark_gpu == 0);
}
