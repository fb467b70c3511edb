// SPDX-License-Identifier: MIT
#pragma once
// Shared by parity_estimators_test.cpp and parity_builders_test.cpp (not a test program: only
// parity_*.cpp files become programs): the synthetic scene of tests/support/synthetic_scene.hpp
// in float, uploaded as SSBOs -- DPRSM (3 x vec4 per texel), voxel words, G-buffer / gather
// points (3 x vec4 each), and one parameter block -- plus the GLSL prelude that defines the
// pack's accessors over those buffers.
//
// Bindings used by the prelude (kernels put their output at 1, extra inputs at 9 and above):
//   2, 3, 4  DPRSM position / normal / albedo  (vec4)
//   5        parameter block  (struct scene_params below)
//   6        voxel words      (uint)
//   7        gather points    (vec4 position, normal, albedo per point; shading normal in .w)
//   8        G-buffer         (vec4 position, normal, albedo per pixel)
#include <parity_harness.hpp>
#include <synthetic_scene.hpp>

#include <vplkit/core/gather_point.hpp>
#include <vplkit/estimators/mis_estimator.hpp>
#include <vplkit/visibility/voxel_grid.hpp>
#include <vplkit/vpl/dprsm_view.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace vplkit::parity::est {

using v3f = vplkit::vec3<float>;

// std430 parameter block, mirrored in the prelude.
struct scene_params {
  float4 light_position, light_intensity, axis_x, axis_y, axis_z;
  float4 grid_min, grid_max;
  int4 grid_res;
  int4 ip;  // x: R, y..w: per-kernel integers
  float4 fp;  // per-kernel floats
  int4 ip2;   // more per-kernel integers
  float4 fp2; // more per-kernel floats
};

struct named_point {
  std::string name;
  vplkit::gather_point<float> gp;
};

// The scene, its DPRSM, its 32^3 voxel grid and a G-buffer, built once per process.
struct scene_fixture {
  vplkit_test::synthetic_scene<float> scene;
  int R = 0;
  vplkit_test::dprsm_data<float> dprsm;
  vplkit::voxel_grid<float> grid;
  vplkit_test::gbuffer_data<float> gbuffer;

  scene_fixture(int resolution, int voxels, int gw, int gh)
      : R(resolution), dprsm(scene.make_dprsm(resolution)), grid(scene.make_voxel_grid(voxels)),
        gbuffer(scene.make_gbuffer(gw, gh)) {}

  vplkit::dprsm_view<float> view() const { return dprsm.view(); }

  scene_params params() const {
    scene_params p{};
    const auto& L = dprsm.light;
    p.light_position = f4(L.position);
    p.light_intensity = f4(L.intensity);
    p.axis_x = f4(L.frame.axis_x);
    p.axis_y = f4(L.frame.axis_y);
    p.axis_z = f4(L.frame.axis_z);
    p.grid_min = f4(grid.bounds_min());
    p.grid_max = f4(grid.bounds_max());
    const vplkit::ivec3 r = grid.resolution();
    p.grid_res = {r.x, r.y, r.z, 0};
    p.ip = {R, 0, 0, 0};
    return p;
  }

  // DPRSM, voxel words and G-buffer (the parameter block and gather points come per call).
  std::vector<ssbo> inputs() const {
    std::vector<float4> pos, nor, alb;
    for (std::size_t i = 0; i < dprsm.position.size(); ++i) {
      pos.push_back(f4(dprsm.position[i]));
      nor.push_back(f4(dprsm.normal[i]));
      alb.push_back(f4(dprsm.albedo[i]));
    }
    std::vector<std::uint32_t> words = grid.words();
    if (words.empty()) words.push_back(0);
    return {input(2, pos), input(3, nor), input(4, alb), input(6, words),
            input(8, vplkit_test::surfels(gbuffer.position, gbuffer.normal, gbuffer.albedo))};
  }
};

// mis as_published near the normal (docs/glsl/estimators.md): the paper's p1 = cos sin / pi takes
// sin = sqrt(1 - cos^2), so a cosine that differs by dc between the two sides moves sin by
// cos dc / sin^2 relative, and a sample's value by p1 / (p1 + alpha) times that. sin is floored at
// 2^-11, the smallest sin a float cosine below 1 gives. The relative amplification of one sample.
inline double as_published_amplification(float cos2, float alpha, double dc) {
  const float sin2 = vplkit::mis_sin_from_cos(cos2);
  const double sn = std::max(double(sin2), std::ldexp(1.0, -11));
  const double p1 = double(vplkit::cosine_pdf_as_published(cos2, float(sn)));
  return p1 / (p1 + double(alpha)) * std::abs(double(cos2)) / (sn * sn) * dc;
}

inline std::vector<float4> pack_points(const std::vector<named_point>& pts) {
  std::vector<v3f> position, normal, albedo, shading;
  for (const auto& p : pts) {
    position.push_back(p.gp.position);
    normal.push_back(p.gp.normal);
    albedo.push_back(p.gp.albedo);
    shading.push_back(p.gp.shading_normal);
  }
  std::vector<float4> out = vplkit_test::surfels(position, normal, albedo, &shading);
  if (out.empty()) out.push_back({0, 0, 0, 0});
  return out;
}

// Accessors and helpers over the buffers above. Kernels include what they use after this.
inline const char* scene_prelude = R"(
#include "vplkit/core/gather_point.glsl"
#include "vplkit/visibility/visibility_callables.glsl"
#include "vplkit/vpl/dprsm_view.glsl"
layout(std430, binding = 2) readonly buffer Positions { vec4 dprsm_position[]; };
layout(std430, binding = 3) readonly buffer Normals { vec4 dprsm_normal[]; };
layout(std430, binding = 4) readonly buffer Albedos { vec4 dprsm_albedo[]; };
layout(std430, binding = 5) readonly buffer Params {
  vec4 light_position; vec4 light_intensity; vec4 axis_x; vec4 axis_y; vec4 axis_z;
  vec4 grid_min; vec4 grid_max; ivec4 grid_res; ivec4 ip; vec4 fp; ivec4 ip2; vec4 fp2;
};
layout(std430, binding = 6) readonly buffer Words { uint voxel_words[]; };
layout(std430, binding = 7) readonly buffer Points { vec4 points[]; };
layout(std430, binding = 8) readonly buffer GBuffer { vec4 gbuffer[]; };
vec3 vplkit_load_dprsm_position(int texel) { return dprsm_position[texel].xyz; }
vec3 vplkit_load_dprsm_normal(int texel) { return dprsm_normal[texel].xyz; }
vec3 vplkit_load_dprsm_albedo(int texel) { return dprsm_albedo[texel].xyz; }
uint vplkit_load_voxel_word(uint i) { return voxel_words[i]; }
vplkit_gather_point vplkit_load_gather_point(int pixel) {
  return vplkit_unpack_gather_point(gbuffer[3 * pixel], gbuffer[3 * pixel + 1], gbuffer[3 * pixel + 2]);
}
vplkit_dprsm_view load_view() {
  vplkit_light_frame frame = vplkit_light_frame(light_position.xyz, axis_x.xyz, axis_y.xyz, axis_z.xyz);
  return vplkit_dprsm_view(ip.x, vplkit_point_light(light_position.xyz, light_intensity.xyz, frame));
}
vplkit_voxel_grid load_grid() { return vplkit_voxel_grid(grid_min.xyz, grid_max.xyz, grid_res.xyz); }
vplkit_gather_point load_point(uint i) {
  return vplkit_unpack_gather_point(points[3u * i], points[3u * i + 1u], points[3u * i + 2u]);
}
)";

// A kernel over the fixture's scene: the prelude, then `source`; the parameter block `p`
// (binding 5), the gather points (7) and `extra` inputs (9 and up); the output (binding 1) and the
// per-item body as per_item() takes them.
inline kernel_call scene_kernel(const scene_fixture& f, const std::string& source, const scene_params& p,
                                const std::vector<named_point>& pts, std::vector<ssbo> extra,
                                const std::string& output_glsl, const std::string& body) {
  std::vector<ssbo> inputs = f.inputs();
  inputs.push_back(input(5, std::vector<scene_params>{p}));
  inputs.push_back(input(7, pack_points(pts)));
  for (auto& e : extra) inputs.push_back(std::move(e));
  return per_item(std::string(scene_prelude) + source, std::move(inputs), output_glsl, body);
}

}  // namespace vplkit::parity::est
