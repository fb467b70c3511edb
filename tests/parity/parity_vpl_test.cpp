// SPDX-License-Identifier: MIT
// CPU/GPU parity of glsl/vplkit/vpl/*.glsl with include/vplkit/vpl/*.hpp (T = float): luminance,
// the VPL model (flux, geometry term, contribution, cos(alpha), patch area, reflected radiance),
// the DPRSM view (vpl_at over a synthetic DPRSM uploaded as vec4 SSBOs, texel_of_direction /
// texel_of_point) and dprsm_lookup. Random configurations with fixed seeds plus the hard cases of
// docs/math.md section 10 (d2 -> 0, coincident points, back-facing, unnormalised and zero normals,
// dmin = 0).
//
// Measured on llvmpipe (Mesa 22.3.6): + - * / and sqrt are correctly rounded there, but the
// compiler contracts some a*b + c (dot products) into FMAs and turns 1/sqrt(x) and x/sqrt(y) into
// an rsqrt (<= 1 ulp). Results built from dot products of unit vectors (cosines) therefore differ
// by a few ulp of 1 in absolute terms; the bounds below are stated relative to the size each
// quantity would have with both cosines equal to 1, which is what an absolute cosine error scales
// with.
#include <parity_harness.hpp>

#include <gpu_model_float.hpp>
#include <gpu_precision.hpp>

#include <vplkit/paraboloid/paraboloid.hpp>
#include <vplkit/paraboloid/texel_grid.hpp>
#include <vplkit/vpl/direct_light.hpp>
#include <vplkit/vpl/dprsm_lookup.hpp>
#include <vplkit/vpl/dprsm_raycast.hpp>
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/luminance.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iostream>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

using namespace vplkit::parity;
using vplkit::ivec2;
using vplkit::vec2;
using vplkit::vec3;
using vplkit_test::flt_eps;
using vplkit_test::flt_min;
using vplkit_test::pi;
using vplkit_test::random_source;

namespace {

// compare_floats_abs on values divided by a per-element scale (computed in double), for
// quantities whose error is an absolute error of a cosine times that scale. scale 0 leaves the
// value as it is (then both sides must give 0 for the comparison to pass).
comparison compare_scaled(const std::vector<float>& gpu, const std::vector<float>& cpu,
                          const std::vector<double>& scale, const float_bound& bound, const describe_fn& describe,
                          const std::string& what) {
  std::vector<float> g;
  std::vector<double> c;
  for (std::size_t i = 0; i < gpu.size(); ++i) g.push_back(scale[i] > 0 ? float(double(gpu[i]) / scale[i]) : gpu[i]);
  for (std::size_t i = 0; i < cpu.size(); ++i) c.push_back(scale[i] > 0 ? double(cpu[i]) / scale[i] : double(cpu[i]));
  return compare_floats_abs(g, c, bound, describe, what);
}

// compare_scaled on each colour channel, named "<what> <channel> / (<scale>)": the cosine bound
// of a radiance divided by its value with the cosines taken as 1.
void check_scaled_channels(const channels<float>& gpu, const channels<float>& cpu, const channels<double>& scale,
                           const float_bound& bound, const describe_fn& describe, const std::string& what,
                           const std::string& scale_text) {
  for (int ch = 0; ch < 3; ++ch) {
    VPLKIT_CHECK_PARITY(compare_scaled(gpu.c[ch], cpu.c[ch], scale.c[ch], bound, describe,
                                       what + " " + channel_name(ch) + " / (" + scale_text + ")"));
  }
}

// n cases drawn in turn by draw(rnd, i, c) from one stream, labelled "random i".
template <class Case, class Draw>
std::vector<Case> random_cases(std::uint64_t seed, int n, Draw draw) {
  random_source rnd(seed);
  std::vector<Case> cases;
  for (int i = 0; i < n; ++i) {
    Case c;
    draw(rnd, i, c);
    c.label = "random " + std::to_string(i);
    cases.push_back(c);
  }
  return cases;
}

// Cosines are dot products of vectors normalised by unit_or_zero on each side (division, sqrt,
// dot: each a few ulp, FMA-contracted or not), so cos1 cos2 differs by a few ulp of 1 in ABSOLUTE
// terms; relative to a small cosine (grazing) that is large (measured rel 2e-4 at cos1 cos2 =
// 4e-5), so a relative bound would be meaningless. The comparisons therefore divide G (and the
// radiances) by their value with both cosines equal to 1, 1 / (pi max(d2^2, dmin^2, floor)),
// computed in double: what is compared is cos1 cos2 in [0, 1] as each side sees it (the distance
// part adds ~1 ulp relatively). Measured worst: 5.6e-7 (two cosines), 4.1e-7 (one cosine).
// Bound: abs 2e-6 (17 ulp of 1), room for GPU sqrt/division at the GLSL limits. A back-facing
// decision flipped by rounding (0 on one side, ~1e-7 on the other) passes; a wrong cosine, clamp
// or constant (an O(1) difference) does not.
const auto cosine_bound = within_abs(2e-6);

}  // namespace

TEST_CASE("luminance and vpl_flux: 10^5 random inputs") {
  random_source rnd(11);
  const std::size_t n = 100000;
  std::vector<float4> in;
  std::vector<vec3<float>> rgb, albedo, intensity;
  std::vector<float> omega;
  for (std::size_t i = 0; i < n; ++i) {
    const double scale = std::pow(10.0, rnd.uniform(-20, 20));
    rgb.push_back(rnd.colour(0, 1) * float(scale));
    albedo.push_back(rnd.colour(0, 1));
    intensity.push_back(rnd.colour(0, 1000));
    omega.push_back(float(rnd.uniform(0, 0.05)));
  }
  for (vec3<float> c : {vec3<float>(0), vec3<float>(1), vec3<float>(1, 0, 0), vec3<float>(0, 1, 0),
                        vec3<float>(0, 0, 1), vec3<float>(1e30f), vec3<float>(flt_min)}) {
    rgb.push_back(c);
    albedo.push_back(vec3<float>(0));
    intensity.push_back(c);
    omega.push_back(0.0f);
  }
  for (std::size_t i = 0; i < rgb.size(); ++i) {
    in.push_back(f4(rgb[i], omega[i]));
    in.push_back(f4(albedo[i]));
    in.push_back(f4(intensity[i]));
  }
  const auto gpu = run_compute<float4>(per_item(R"(
#include "vplkit/vpl/luminance.glsl"
#include "vplkit/vpl/vpl.glsl"
)",
                                                {input(0, in, "vec4 q")}, "vec4 result", R"(
  result[i] = vec4(vplkit_vpl_flux(q[3u * i + 1u].xyz, q[3u * i + 2u].xyz, q[3u * i].w),
                   vplkit_luminance(q[3u * i].xyz));)"),
                                       rgb.size());
  std::vector<float4> cpu;
  for (std::size_t i = 0; i < rgb.size(); ++i)
    cpu.push_back(f4(vplkit::vpl_flux(albedo[i], intensity[i], omega[i]), vplkit::luminance(rgb[i])));
  auto describe = [&](std::size_t i) {
    return "rgb " + show3(rgb[i]) + " albedo " + show3(albedo[i]) + " I " + show3(intensity[i]) +
           " omega " + show(omega[i]);
  };
  // luminance: three products and two sums of non-negative terms (no cancellation); FMA
  // contraction changes it by an ulp or so. Bound 4 ulps, or 3 FLT_MIN absolute: each of the
  // three products may be a denormal that one side flushes (spec::flushed_product_abs).
  VPLKIT_CHECK_PARITY(compare_field_abs(gpu, cpu, [](const float4& v) { return v.w; },
                                        within_ulps(4) | within_abs(3 * vplkit_test::spec::flushed_product_abs),
                                        describe, "luminance"));
  // flux: two correctly rounded products per channel: bit-identical unless a compiler
  // reassociates; bound 2 ulps.
  for (int ch = 0; ch < 3; ++ch) {
    VPLKIT_CHECK_PARITY(compare_field_abs(gpu, cpu, [ch](const float4& v) { return v[ch]; }, within_ulps(2),
                                          describe, std::string("vpl_flux ") + channel_name(ch)));
  }
}

namespace {

struct geometry_case {
  vec3<float> x, n_x, rho_x, y, n_y, flux;
  float dmin;
  std::string label;
};

using W = vplkit_test::gpu_float;
vec3<W> to_w(const vec3<float>& v) { return vec3<W>(W(v.x), W(v.y), W(v.z)); }

// Geometry term and contribution of each case on both sides; compares G and each channel of L
// scaled by their size with both cosines 1 (cosine_bound), and checks that nothing is NaN/Inf.
void check_geometry(const std::vector<geometry_case>& cases, const std::string& what) {
  std::vector<float4> in;
  for (const auto& c : cases) {
    in.push_back(f4(c.x, c.dmin));
    in.push_back(f4(c.n_x));
    in.push_back(f4(c.rho_x));
    in.push_back(f4(c.y));
    in.push_back(f4(c.n_y));
    in.push_back(f4(c.flux));
  }
  const auto gpu = run_compute<float4>(per_item(R"(#include "vplkit/vpl/vpl.glsl")", {input(0, in, "vec4 q")},
                                                "vec4 result", R"(
  uint k = 6u * i;
  vec3 x = q[k].xyz;
  float dmin = q[k].w;
  vplkit_vpl v = vplkit_vpl(q[k + 3u].xyz, q[k + 4u].xyz, q[k + 5u].xyz);
  float g = vplkit_vpl_geometry_term(x, q[k + 1u].xyz, v.position, v.normal, dmin);
  result[i] = vec4(vplkit_vpl_contribution(x, q[k + 1u].xyz, q[k + 2u].xyz, v, dmin), g);)"),
                                       cases.size());
  series<float> g_term;
  std::vector<double> sg;
  channels<float> gl, cl;
  channels<double> sl;
  std::size_t zero_mismatch = 0, positive = 0;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const auto& c = cases[i];
    const float g = vplkit::vpl_geometry_term(c.x, c.n_x, c.y, c.n_y, c.dmin);
    const vec3<float> L =
        vplkit::vpl_contribution(c.x, c.n_x, c.rho_x, vplkit::vpl<float>{c.y, c.n_y, c.flux}, c.dmin);
    for (int k = 0; k < 4; ++k) REQUIRE(std::isfinite(gpu[i][k]));
    REQUIRE(gpu[i].w >= 0.0f);
    if ((g > 0) != (gpu[i].w > 0)) ++zero_mismatch;
    if (g > 0) ++positive;
    const vec3<double> w = vec3<double>(c.y) - vec3<double>(c.x);
    const double d2sq = std::max({glm::dot(w, w), double(c.dmin) * double(c.dmin),
                                  double(vplkit::vpl_distance_sq_floor<float>())});
    const double scale_g = 1.0 / (pi * d2sq);
    g_term.add(gpu[i].w, g);
    sg.push_back(scale_g);
    gl.push(gpu[i]);
    cl.push(L);
    sl.push(vec3<double>(c.rho_x) * vec3<double>(c.flux) / pi * scale_g);
  }
  auto describe = [&](std::size_t i) {
    const auto& c = cases[i];
    return c.label + ": x " + show3(c.x) + " n_x " + show3(c.n_x) + " y " + show3(c.y) + " n_y " +
           show3(c.n_y) + " dmin " + show(c.dmin) + " (cpu G " +
           show(vplkit::vpl_geometry_term(c.x, c.n_x, c.y, c.n_y, c.dmin)) + ")";
  };
  std::cout << "  " << what << ": " << positive << " of " << cases.size()
            << " with G > 0 on the CPU; zero/non-zero decisions that differ: " << zero_mismatch
            << " (allowed only within the cosine bound)\n";
  VPLKIT_CHECK_PARITY(compare_scaled(g_term.gpu, g_term.cpu, sg, cosine_bound, describe,
                                     what + ": G * pi max(d2^2, dmin^2, floor)"));
  check_scaled_channels(gl, cl, sl, cosine_bound, describe, what + ": contribution", "rho flux / pi^2 d2^2");
  // The same bounds for the GPU model (gpu_model_float.hpp): every division and square root of
  // the C++ at the specification's extremes and at random within them.
  std::uint64_t seed = 11;
  for (const auto deviation : vplkit_test::gpu_model_deviations) {
    const vplkit_test::gpu_model_scope model(deviation, seed++);
    std::vector<float> mg;
    channels<float> ml;
    for (const auto& c : cases) {
      const W dmin = c.dmin;
      mg.push_back(float(vplkit::vpl_geometry_term(to_w(c.x), to_w(c.n_x), to_w(c.y), to_w(c.n_y), dmin)));
      const vec3<W> L = vplkit::vpl_contribution(to_w(c.x), to_w(c.n_x), to_w(c.rho_x),
                                                 vplkit::vpl<W>{to_w(c.y), to_w(c.n_y), to_w(c.flux)}, dmin);
      ml.push(vec3<float>(float(L.x), float(L.y), float(L.z)));
    }
    const std::string m = what + ", GPU model (" + vplkit_test::to_string(deviation) + ")";
    VPLKIT_CHECK_PARITY(compare_scaled(mg, g_term.cpu, sg, cosine_bound, describe, m + ": G * pi max(d2^2, ...)"));
    check_scaled_channels(ml, cl, sl, cosine_bound, describe, m + ": contribution", "rho flux / pi^2 d2^2");
  }
}

}  // namespace

TEST_CASE("vpl_geometry_term and vpl_contribution: 10^5 random configurations") {
  const std::vector<geometry_case> cases =
      random_cases<geometry_case>(22, 100000, [](random_source& rnd, int i, geometry_case& c) {
      c.x = rnd.in_box(5);
      c.y = rnd.in_box(5);
      const vec3<float> to_y = glm::normalize(c.y - c.x);
      // half of the cases face each other (most give G > 0), half random (mostly back-facing)
      if (i % 2 == 0) {
        c.n_x = glm::normalize(to_y + rnd.sphere_direction() * 0.9f);
        c.n_y = glm::normalize(-to_y + rnd.sphere_direction() * 0.9f);
      } else {
        c.n_x = rnd.sphere_direction();
        c.n_y = rnd.sphere_direction();
      }
      // unnormalised normals of any scale, some zero
      c.n_x *= float(std::pow(10.0, rnd.uniform(-20, 20)));
      c.n_y *= float(std::pow(10.0, rnd.uniform(-20, 20)));
      if (i % 50 == 7) c.n_x = vec3<float>(0);
      if (i % 50 == 13) c.n_y = vec3<float>(0);
      c.rho_x = rnd.colour(0, 1);
      c.flux = rnd.colour(0, 10);
      c.dmin = i % 3 == 0 ? 0.0f : float(rnd.uniform(0, 0.5));
      });
  check_geometry(cases, "geometry (random)");
}

TEST_CASE("vpl_geometry_term and vpl_contribution: hard cases") {
  std::vector<geometry_case> cases;
  const vec3<float> rho(0.5f, 0.25f, 1.0f), flux(2.0f, 3.0f, 4.0f);
  auto add = [&](vec3<float> x, vec3<float> n_x, vec3<float> y, vec3<float> n_y, float dmin,
                 const std::string& label) {
    cases.push_back({x, n_x, rho, y, n_y, flux, dmin, label});
  };
  // d2 -> 0: a VPL on a wall (normal -x) slides toward x on the floor (normal +z) along the corner
  // direction, d from 1 down to 1e-30, at two scales of x, with dmin = 0 and 0.1.
  for (float sx : {0.0f, 1000.0f}) {
    for (float dmin : {0.0f, 0.1f}) {
      for (double e = 0; e >= -30; e -= 0.25) {
        const float d = float(std::pow(10.0, e));
        const vec3<float> x(sx, sx, 0);
        add(x, vec3<float>(0, 0, 1), x + vec3<float>(d, 0, d), vec3<float>(-1, 0, 0), dmin,
            "d2 -> 0, d = " + show(d));
      }
    }
  }
  // coincident points (x == y, and separations at and around the coincidence tolerance, which both
  // sides compute with the same exact operations), dmin = 0 and 0.5
  for (float s : {1.0f, 1000.0f, 1e-3f}) {
    const vec3<float> x(s, -s, 0.5f * s);
    const float tol = vplkit::vpl_coincidence_tolerance(x, x);
    for (float off : {0.0f, tol * 0.5f, tol, tol * 1.5f, tol * 4.0f, tol * 64.0f}) {
      for (float dmin : {0.0f, 0.5f}) {
        add(x, vec3<float>(0, 0, 1), x + vec3<float>(off, 0, off), vec3<float>(-1, 0, -1), dmin,
            "coincident, offset " + show(off));
      }
    }
  }
  // back-facing: VPL facing away, VPL behind x, edge-on (exact zero dot), in x's tangent plane,
  // back to back
  const vec3<float> o(0, 0, 0);
  for (float dmin : {0.0f, 0.5f}) {
    add(o, vec3<float>(0, 0, 1), vec3<float>(0, 0, 1), vec3<float>(0, 0, 1), dmin, "VPL faces away");
    add(o, vec3<float>(0, 0, 1), vec3<float>(0, 0, -1), vec3<float>(0, 0, 1), dmin, "VPL behind x");
    add(o, vec3<float>(0, 0, 1), vec3<float>(0, 1, 1), vec3<float>(1, 0, 0), dmin, "VPL edge-on");
    add(o, vec3<float>(0, 0, 1), vec3<float>(1, 1, 0), vec3<float>(-1, -1, 0), dmin,
        "VPL in x's tangent plane");
    add(o, vec3<float>(0, 0, -1), vec3<float>(0, 0, 1), vec3<float>(0, 0, 1), dmin, "back to back");
    add(o, vec3<float>(0, 0, 1), vec3<float>(0, 0, 1), vec3<float>(0, 0, -1), dmin, "facing (G > 0)");
  }
  // unnormalised normals from 4 FLT_MIN to 1e30 (denormal normals are a CPU-only guarantee), and
  // zero normals
  for (float s : {4.0f * flt_min, 1e-30f, 1e-10f, 1.0f, 1e10f, 1e30f}) {
    add(o, vec3<float>(0.3f, 0.1f, 1.0f) * s, vec3<float>(0.5f, 0.2f, 1.0f),
        vec3<float>(-0.2f, 0.1f, -1.0f) * s, 0.0f, "normal scale " + show(s));
  }
  add(o, vec3<float>(0), vec3<float>(0.5f, 0.2f, 1.0f), vec3<float>(0, 0, -1), 0.0f, "zero n_x");
  add(o, vec3<float>(0, 0, 1), vec3<float>(0.5f, 0.2f, 1.0f), vec3<float>(0), 0.0f, "zero n_y");
  // huge separations (dot(w, w) overflows to Inf: G = 0)
  add(vec3<float>(-1e30f, 0, 0), vec3<float>(1, 0, 0), vec3<float>(1e30f, 0, 0),
      vec3<float>(-1, 0, 0), 0.0f, "huge separation");
  check_geometry(cases, "geometry (hard cases)");
}

namespace {

struct light_case {
  vec3<float> c, y, n_y, intensity, rho_y;
  float omega, d1, cos_in;
  std::string label;
};

void check_light_cases(const std::vector<light_case>& cases, const std::string& what) {
  std::vector<float4> in;
  for (const auto& c : cases) {
    in.push_back(f4(c.c, c.omega));
    in.push_back(f4(c.y, c.d1));
    in.push_back(f4(c.n_y, c.cos_in));
    in.push_back(f4(c.intensity));
    in.push_back(f4(c.rho_y));
  }
  // Two outputs: radiance and cos(alpha), patch area.
  kernel_call call = per_item(R"(#include "vplkit/vpl/vpl.glsl")", {input(0, in, "vec4 q")}, "vec4 radiance_cos", R"(
  uint k = 5u * i;
  vec3 c = q[k].xyz, y = q[k + 1u].xyz, n = q[k + 2u].xyz;
  radiance_cos[i] = vec4(vplkit_reflected_radiance(c, q[k + 3u].xyz, y, n, q[k + 4u].xyz),
                         vplkit_vpl_cos_alpha(c, y, n));
  area[i] = vplkit_vpl_patch_area(q[k].w, q[k + 1u].w, q[k + 2u].w);)");
  call.more_outputs = {output_of<float>(2, "float area")};
  const kernel_outputs out = run_kernel(call, cases.size(), sizeof(float4));
  const auto gpu = out.get<float4>(1);
  const auto gpu_area = out.get<float>(2);
  series<float> cos_alpha, area;
  channels<float> gl, cl;
  channels<double> sl;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const auto& c = cases[i];
    const vec3<float> L = vplkit::reflected_radiance(c.c, c.intensity, c.y, c.n_y, c.rho_y);
    cos_alpha.add(gpu[i].w, vplkit::vpl_cos_alpha(c.c, c.y, c.n_y));
    area.add(gpu_area[i], vplkit::vpl_patch_area(c.omega, c.d1, c.cos_in));
    for (int k = 0; k < 3; ++k) REQUIRE(std::isfinite(gpu[i][k]));
    REQUIRE(std::isfinite(gpu_area[i]));
    const vec3<double> w = vec3<double>(c.c) - vec3<double>(c.y);
    const double d1sq = std::max(glm::dot(w, w), double(vplkit::vpl_distance_sq_floor<float>()));
    gl.push(gpu[i]);
    cl.push(L);
    sl.push(vec3<double>(c.rho_y) * vec3<double>(c.intensity) / (pi * d1sq));
  }
  auto describe = [&](std::size_t i) {
    const auto& c = cases[i];
    return c.label + ": c " + show3(c.c) + " y " + show3(c.y) + " n_y " + show3(c.n_y) +
           " omega " + show(c.omega) + " d1 " + show(c.d1) + " cos " + show(c.cos_in);
  };
  // cos(alpha): a dot product of two unit_or_zero vectors, clamped at 0: a few ulp of 1 in
  // absolute terms (measured 3.0e-7). Bound 8 ulps or 1e-6 abs (8.4 ulp of 1).
  VPLKIT_CHECK_PARITY(compare_floats_abs(cos_alpha, within_ulps(8) | within_abs(1e-6), describe,
                                         what + ": vpl_cos_alpha"));
  // patch area: ((omega / c) d1) d1 with the same c on both sides (the floor decision compares the
  // same float): one division and two products, bit-identical on llvmpipe; a GPU division
  // (spec::div_ulps) against the C++ one (0.5), and each side's two products (0.5 each): 5 ulps,
  // + 1 because an error of n ulps of one binade reads as up to 2n ulps just below a power of two;
  // or 2 FLT_MIN absolute (a result near FLT_MIN flushed on one side).
  const auto area_bound = within_ulps(vplkit_test::spec::div_ulps + 0.5 + 4 * vplkit_test::spec::add_mul_ulps + 1) |
                          within_abs(2 * vplkit_test::spec::flushed_product_abs);
  VPLKIT_CHECK_PARITY(compare_floats_abs(area, area_bound, describe, what + ": vpl_patch_area"));
  // reflected radiance scaled by rho I / (pi d1^2): the cosine's absolute error (cosine_bound).
  check_scaled_channels(gl, cl, sl, cosine_bound, describe, what + ": reflected_radiance", "rho I / pi d1^2");
  // The same bounds for the GPU model (gpu_model_float.hpp).
  std::uint64_t seed = 21;
  for (const auto deviation : vplkit_test::gpu_model_deviations) {
    const vplkit_test::gpu_model_scope model(deviation, seed++);
    std::vector<float> mc, ma;
    channels<float> ml;
    for (const auto& c : cases) {
      const vec3<W> L = vplkit::reflected_radiance(to_w(c.c), to_w(c.intensity), to_w(c.y), to_w(c.n_y), to_w(c.rho_y));
      ml.push(vec3<float>(float(L.x), float(L.y), float(L.z)));
      mc.push_back(float(vplkit::vpl_cos_alpha(to_w(c.c), to_w(c.y), to_w(c.n_y))));
      ma.push_back(float(vplkit::vpl_patch_area(W(c.omega), W(c.d1), W(c.cos_in))));
    }
    const std::string m = what + ", GPU model (" + vplkit_test::to_string(deviation) + ")";
    VPLKIT_CHECK_PARITY(compare_floats_abs(mc, cos_alpha.cpu, within_ulps(8) | within_abs(1e-6), describe,
                                           m + ": vpl_cos_alpha"));
    VPLKIT_CHECK_PARITY(compare_floats_abs(ma, area.cpu, area_bound, describe, m + ": vpl_patch_area"));
    check_scaled_channels(ml, cl, sl, cosine_bound, describe, m + ": reflected_radiance", "rho I / pi d1^2");
  }
}

}  // namespace

TEST_CASE("vpl_cos_alpha, vpl_patch_area, reflected_radiance: random and hard cases") {
  std::vector<light_case> cases =
      random_cases<light_case>(33, 100000, [](random_source& rnd, int i, light_case& c) {
      c.c = rnd.in_box(3);
      c.y = rnd.in_box(5);
      const vec3<float> to_c = glm::normalize(c.c - c.y);
      c.n_y = (i % 2 == 0 ? glm::normalize(to_c + rnd.sphere_direction() * 0.9f) : rnd.sphere_direction()) *
              float(std::pow(10.0, rnd.uniform(-20, 20)));
      if (i % 50 == 3) c.n_y = vec3<float>(0);
      c.intensity = rnd.colour(0, 100);
      c.rho_y = rnd.colour(0, 1);
      c.omega = float(rnd.uniform(0, 0.05));
      c.d1 = float(rnd.uniform(0, 20));
      // cos in [-0.2, 1], a fifth of them around the 1e-6 floor
      c.cos_in = i % 5 == 0 ? float(rnd.uniform(0, 2e-6)) : float(rnd.uniform(-0.2, 1.0));
      });
  const vec3<float> I(10, 20, 30), rho(0.5f, 0.25f, 1.0f);
  // light on the surface point (coincident), and approaching it: d1 from 1 to 1e-30
  for (float s : {0.0f, 1.0f, 1000.0f}) {
    const vec3<float> y(s, s, 0);
    cases.push_back({y, y, vec3<float>(0, 0, 1), I, rho, 0.01f, 0.0f, 0.5f, "light on y"});
    for (double e = 0; e >= -30; e -= 0.5) {
      const float d = float(std::pow(10.0, e));
      cases.push_back({y + vec3<float>(0.3f * d, 0, d), y, vec3<float>(0, 0, 1), I, rho, 0.01f, d,
                       0.9f, "d1 = " + show(d)});
    }
  }
  // back-facing (light behind the surface), edge-on (exact zero dot), zero normal
  cases.push_back({vec3<float>(0, 0, -1), vec3<float>(0), vec3<float>(0, 0, 1), I, rho, 0.01f, 1.0f,
                   -1.0f, "light behind"});
  cases.push_back({vec3<float>(1, 0, 0), vec3<float>(0), vec3<float>(0, 0, 1), I, rho, 0.01f, 1.0f,
                   0.0f, "light edge-on"});
  cases.push_back({vec3<float>(0, 0, 1), vec3<float>(0), vec3<float>(0), I, rho, 0.01f, 1.0f, -0.0f,
                   "zero normal"});
  // patch area at grazing incidence: cos = 0, -0, -1, tiny, exactly the floor and beside it
  for (float cs : {0.0f, -0.0f, -1.0f, 1e-30f, 4.0f * flt_min, 1e-6f, std::nextafter(1e-6f, 1.0f),
                   std::nextafter(1e-6f, 0.0f), 1.0f}) {
    cases.push_back({vec3<float>(0, 0, 1), vec3<float>(0), vec3<float>(0, 0, 1), I, rho, 0.02f, 7.0f,
                     cs, "grazing cos " + show(cs)});
  }
  check_light_cases(cases, "light cases");
}

// ---- DPRSM view ----------------------------------------------------------------------------

namespace {

// A small analytic scene: floor z = 0, a wall x = 3 facing the light (normal given unnormalised,
// (-5, 0, 0)), a wall y = -2 whose normal points away from the light (its texels carry no flux),
// and half a ceiling z = 4 (x < 0, normal (0, 0, -1e-3)); elsewhere the sky (empty texels).
struct plane {
  int axis;              // 0, 1, 2: the plane is coordinate[axis] = at
  float at;
  vec3<float> lo, hi;    // bounds of the hit point
  vec3<float> normal;    // reported normal
  vec3<float> albedo;
};

const std::vector<plane>& scene_planes() {
  static const std::vector<plane> planes = {
      {2, 0.0f, vec3<float>(-6, -6, -1), vec3<float>(6, 6, 1), vec3<float>(0, 0, 1),
       vec3<float>(0.8f, 0.5f, 0.3f)},
      {0, 3.0f, vec3<float>(2, -6, 0), vec3<float>(4, 6, 4), vec3<float>(-5, 0, 0),
       vec3<float>(0.2f, 0.7f, 0.4f)},
      {1, -2.0f, vec3<float>(-6, -3, 0), vec3<float>(3, -1, 4), vec3<float>(0, -1, 0),
       vec3<float>(0.5f, 0.5f, 0.5f)},
      {2, 4.0f, vec3<float>(-6, -6, 3), vec3<float>(0, 6, 5), vec3<float>(0, 0, -1e-3f),
       vec3<float>(0.3f, 0.3f, 0.9f)},
  };
  return planes;
}

std::optional<vplkit::dprsm_hit<float>> trace_scene(vec3<float> o, vec3<float> d) {
  std::optional<vplkit::dprsm_hit<float>> best;
  float best_t = std::numeric_limits<float>::infinity();
  for (const plane& p : scene_planes()) {
    if (d[p.axis] == 0.0f) continue;
    const float t = (p.at - o[p.axis]) / d[p.axis];
    if (!(t > 1e-4f) || !(t < best_t)) continue;
    vec3<float> h = o + t * d;
    h[p.axis] = p.at;
    bool inside = true;
    for (int k = 0; k < 3; ++k) inside = inside && h[k] >= p.lo[k] && h[k] <= p.hi[k];
    if (!inside) continue;
    best_t = t;
    best = vplkit::dprsm_hit<float>{h, p.normal, p.albedo};
  }
  return best;
}

struct dprsm_data {
  vplkit::point_light<float> light;
  int R = 0;
  std::vector<vec3<float>> P, N, A;
  vplkit::dprsm_view<float> view;
};

// Light 0: an off-centre light with a tilted front axis (non-trivial frame), R = 32, plus
// hand-made texels: one at the light's own position (coincident: flux 0), one whose normal is
// exactly perpendicular to the light direction (cos alpha = 0 exactly: flux 0), one with a zero
// normal. Light 1: front axis +z (identity axes), odd R = 33.
dprsm_data make_dprsm(int which) {
  dprsm_data d;
  if (which == 0) {
    d.light = vplkit::make_point_light(vec3<float>(0.3f, 0.2f, 1.5f), vec3<float>(10, 20, 30),
                                       vec3<float>(0.2f, -0.3f, -1.0f));
    d.R = 32;
  } else {
    d.light = vplkit::make_point_light(vec3<float>(-1.0f, 1.0f, 2.0f), vec3<float>(5, 5, 5),
                                       vec3<float>(0, 0, 1));
    d.R = 33;
  }
  d.view = vplkit::render_dprsm(d.light, d.R, trace_scene, d.P, d.N, d.A);
  if (which == 0) {
    std::vector<int> lit;
    for (int i = 0; i < d.view.texel_count(); ++i)
      if (d.view.texel_valid(i) && d.A[std::size_t(i)] != vec3<float>(0)) lit.push_back(i);
    REQUIRE(lit.size() > 100);
    const vec3<float> c = d.light.position;
    d.P[std::size_t(lit[10])] = c;  // the light's own position
    d.P[std::size_t(lit[20])] = c + vec3<float>(1, 0, 0);
    d.N[std::size_t(lit[20])] = vec3<float>(0, 1, 0);  // exactly edge-on to the light
    d.N[std::size_t(lit[30])] = vec3<float>(0);         // zero normal
  }
  return d;
}

// The kernel prelude: the DPRSM as vec4 SSBOs (std430: no vec3 arrays), the accessors, and the
// view built from a small light buffer {position, intensity, axis_x, axis_y, axis_z, (R, ...)}.
const std::string dprsm_prelude = R"(
#include "vplkit/vpl/dprsm_lookup.glsl"
#include "vplkit/vpl/dprsm_view.glsl"
layout(std430, binding = 2) readonly buffer Positions { vec4 dprsm_position[]; };
layout(std430, binding = 3) readonly buffer Normals { vec4 dprsm_normal[]; };
layout(std430, binding = 4) readonly buffer Albedos { vec4 dprsm_albedo[]; };
layout(std430, binding = 5) readonly buffer Light { vec4 light_data[6]; };
vec3 vplkit_load_dprsm_position(int texel) { return dprsm_position[texel].xyz; }
vec3 vplkit_load_dprsm_normal(int texel) { return dprsm_normal[texel].xyz; }
vec3 vplkit_load_dprsm_albedo(int texel) { return dprsm_albedo[texel].xyz; }
vplkit_dprsm_view load_view() {
  vplkit_light_frame frame = vplkit_light_frame(light_data[0].xyz, light_data[2].xyz,
                                                light_data[3].xyz, light_data[4].xyz);
  vplkit_point_light light = vplkit_point_light(light_data[0].xyz, light_data[1].xyz, frame);
  return vplkit_dprsm_view(int(light_data[5].x), light);
}
)";

// A kernel over d's DPRSM (bindings 2 to 5, the prelude above), `source` after the prelude, the
// caller's query buffer (binding 0), its output (binding 1) and per-item body.
kernel_call dprsm_kernel(const dprsm_data& d, const std::string& source, std::vector<ssbo> queries,
                         const std::string& output_glsl, const std::string& body) {
  std::vector<float4> p, n, a;
  for (std::size_t i = 0; i < d.P.size(); ++i) {
    p.push_back(f4(d.P[i]));
    n.push_back(f4(d.N[i]));
    a.push_back(f4(d.A[i]));
  }
  const auto& f = d.light.frame;
  const std::vector<float4> light = {f4(d.light.position), f4(d.light.intensity), f4(f.axis_x),
                                     f4(f.axis_y), f4(f.axis_z), {float(d.R), 0, 0, 0}};
  queries.insert(queries.end(), {input(2, p), input(3, n), input(4, a), input(5, light)});
  return per_item(dprsm_prelude + source, std::move(queries), output_glsl, body);
}

// vplkit_direct_light at each gather point over d's DPRSM (rgb; w unused).
std::vector<float4> gpu_direct_light(const dprsm_data& d, const std::vector<vplkit::gather_point<float>>& gps) {
  std::vector<float4> in;
  for (const auto& g : gps) {
    in.push_back(f4(g.position, g.shading_normal.x));
    in.push_back(f4(g.normal, g.shading_normal.y));
    in.push_back(f4(g.albedo, g.shading_normal.z));
  }
  return run_compute<float4>(
      dprsm_kernel(d, R"(#include "vplkit/vpl/direct_light.glsl")", {input(0, in, "vec4 q")}, "vec4 result", R"(
  vplkit_gather_point gp = vplkit_unpack_gather_point(q[3u * i], q[3u * i + 1u], q[3u * i + 2u]);
  result[i] = vec4(vplkit_direct_light(gp, load_view()), 0.0);)"),
      gps.size());
}

}  // namespace

TEST_CASE("dprsm_view: vpl_at, texel_valid, solid_angle, texel_count over a synthetic DPRSM") {
  for (int which = 0; which < 2; ++which) {
    const dprsm_data d = make_dprsm(which);
    const int n = d.view.texel_count();
    struct out_t {
      float4 position, normal, flux;
    };
    const auto gpu = run_compute<out_t>(dprsm_kernel(d, "struct out_t { vec4 position; vec4 normal; vec4 flux; };", {},
                                                     "out_t result", R"(
  vplkit_dprsm_view view = load_view();
  int t = int(i);
  vplkit_vpl v = vplkit_dprsm_view_vpl_at(view, t);
  result[i] = out_t(vec4(v.position, vplkit_dprsm_view_texel_valid(view, t) ? 1.0 : 0.0),
                    vec4(v.normal, vplkit_dprsm_view_solid_angle(view, t)),
                    vec4(v.flux, float(vplkit_dprsm_view_texel_count(view))));)"),
                                        std::size_t(n));
    series<std::int32_t> valid, count, nonzero;
    series<std::uint32_t> bits;
    series<float> omega;
    channels<float> g_flux, c_flux;
    std::size_t lit = 0, zero_by_facing = 0, zero_band = 0;
    for (int i = 0; i < n; ++i) {
      const auto& g = gpu[std::size_t(i)];
      const vplkit::vpl<float> v = d.view.vpl_at(i);
      valid.add(g.position.w != 0.0f, d.view.texel_valid(i));
      count.add(std::int32_t(g.flux.w), d.view.texel_count());
      // position and normal are copies: bit-identical
      for (int k = 0; k < 3; ++k) bits.add(bits_of(g.position[k]), bits_of(v.position[k]));
      for (int k = 0; k < 3; ++k) bits.add(bits_of(g.normal[k]), bits_of(v.normal[k]));
      omega.add(g.normal.w, d.view.solid_angle(i));
      g_flux.push(g.flux);
      c_flux.push(v.flux);
      const bool g_nonzero = g.flux.x != 0 || g.flux.y != 0 || g.flux.z != 0;
      const bool c_nonzero = v.flux != vec3<float>(0);
      // The back-facing test (cos alpha > 0) is the one zero/non-zero decision made on a rounded
      // float: a texel whose unclamped cos alpha is within 1e-6 of 0 (8 ulp of 1, beyond the
      // cos_alpha bound) may go either way. None is that close here except the hand-made
      // exactly-edge-on texel, whose dot is exactly 0 on both sides.
      const vec3<double> to_c = vec3<double>(d.light.position) - vec3<double>(v.position);
      const vec3<double> nd = vec3<double>(v.normal);
      const double raw_cos = glm::length(to_c) > 0 && glm::length(nd) > 0
                                 ? glm::dot(glm::normalize(nd), glm::normalize(to_c))
                                 : 1.0;
      const bool in_band = std::abs(raw_cos) < 1e-6 && d.view.texel_valid(i) &&
                           d.A[std::size_t(i)] != vec3<float>(0);
      if (in_band) ++zero_band;
      nonzero.add(g_nonzero || (in_band && c_nonzero) ? 1 : 0, c_nonzero || (in_band && g_nonzero) ? 1 : 0);
      if (c_nonzero) ++lit;
      if (!c_nonzero && d.view.texel_valid(i) && d.A[std::size_t(i)] != vec3<float>(0))
        ++zero_by_facing;
    }
    const std::string what = "vpl_at (light " + std::to_string(which) + ", R " + std::to_string(d.R) + ")";
    auto describe = [&](std::size_t i) {
      const ivec2 xy = vplkit::texel_coords(int(i), d.R);
      return "texel " + std::to_string(i) + " (face " + std::to_string(vplkit::texel_face(int(i), d.R)) +
             ", x " + std::to_string(xy.x) + ", y " + std::to_string(xy.y) + ") y_t " +
             show3(d.P[i]) + " n_t " + show3(d.N[i]) + " rho " + show3(d.A[i]);
    };
    std::cout << "  " << what << ": " << n << " texels, " << lit << " with flux, " << zero_by_facing
              << " valid and non-empty but zeroed (back-facing, coincident, zero normal), "
              << zero_band << " with |unclamped cos alpha| < 1e-6\n";
    CHECK(zero_by_facing >= 3);
    VPLKIT_CHECK_PARITY(compare_exact(valid, describe, what + ": texel_valid"));
    VPLKIT_CHECK_PARITY(compare_exact(count, describe, what + ": texel_count"));
    VPLKIT_CHECK_PARITY(compare_exact(bits, {}, what + ": position, normal (bits)"));
    VPLKIT_CHECK_PARITY(compare_exact(nonzero, describe,
                                      what + ": flux zero / non-zero (exact outside |cos alpha| < 1e-6)"));
    // solid angle: as texel_solid_angle in parity_paraboloid_test (rel 1.5e-6); flux adds two
    // correctly rounded products: rel 2e-6.
    VPLKIT_CHECK_PARITY(compare_floats_abs(omega, within_rel(1.5e-6), describe, what + ": solid_angle"));
    for (int ch = 0; ch < 3; ++ch)
      VPLKIT_CHECK_PARITY(compare_floats_abs(g_flux.c[ch], c_flux.c[ch], within_rel(2e-6), describe,
                                             what + ": flux " + channel_name(ch)));
  }
}

TEST_CASE("dprsm_view: exhaustive VPL sum at gather points (vpl_at + vpl_contribution)") {
  // The estimand of every CDF method, L(x) = sum_t L_t(x), over all 2R^2 texels for 256 gather
  // points on the floor and the wall, dmin = 0.05, no visibility.
  const dprsm_data d = make_dprsm(0);
  random_source rnd(44);
  std::vector<float4> xs;
  std::vector<vec3<float>> gx, gn;
  for (int i = 0; i < 256; ++i) {
    if (i % 2 == 0) {
      gx.push_back(vec3<float>(float(rnd.uniform(-5, 2.9)), float(rnd.uniform(-1.9, 5)), 0));
      gn.push_back(vec3<float>(0, 0, 1));
    } else {
      gx.push_back(vec3<float>(3, float(rnd.uniform(-1.9, 5)), float(rnd.uniform(0, 3.9))));
      gn.push_back(vec3<float>(-1, 0, 0));
    }
    xs.push_back(f4(gx.back()));
    xs.push_back(f4(gn.back()));
  }
  kernel_call call = dprsm_kernel(d, "", {input(0, xs, "vec4 gather")}, "vec4 result", R"(
  vplkit_dprsm_view view = load_view();
  vec3 x = gather[2u * i].xyz, n = gather[2u * i + 1u].xyz;
  vec3 sum = vec3(0.0);
  for (int t = 0; t < vplkit_dprsm_view_texel_count(view); ++t)
    sum += vplkit_vpl_contribution(x, n, vec3(0.5, 0.6, 0.7), vplkit_dprsm_view_vpl_at(view, t), 0.05);
  result[i] = vec4(sum, 0.0);)");
  call.local_size = {16, 1, 1};
  const auto gpu = run_compute<float4>(call, gx.size());
  channels<float> g, c;
  for (std::size_t i = 0; i < gx.size(); ++i) {
    vec3<float> sum(0);
    for (int t = 0; t < d.view.texel_count(); ++t)
      sum += vplkit::vpl_contribution(gx[i], gn[i], vec3<float>(0.5f, 0.6f, 0.7f), d.view.vpl_at(t), 0.05f);
    g.push(gpu[i]);
    c.push(sum);
  }
  auto describe = [&](std::size_t i) { return "x " + show3(gx[i]) + " n " + show3(gn[i]); };
  // ~1600 positive terms summed in the same order on both sides: per-term differences of a few
  // 1e-7 relative (cosines, solid angle) average out; the sum agrees to rel 1e-5 (measured ~1e-6).
  for (int ch = 0; ch < 3; ++ch)
    VPLKIT_CHECK_PARITY(compare_floats_abs(g.c[ch], c.c[ch], within_rel(1e-5), describe,
                                           std::string("VPL sum ") + channel_name(ch)));
}

namespace {

struct texel_probe {
  int cpu_texel, gpu_texel;
};

// Explains a texel that differs between CPU and GPU for a direction (light space l, CPU uv):
// allowed only (a) at the seam: other face, same (x, y), and |l.z| within 2.4e-7 |l| (a rounding
// of the rotation into light space decides the face; uv is the same on both faces there), or
// (b) at a texel edge: same face, x and y each equal or adjacent, and where they differ the CPU's
// u (or v) lies within 1e-6 of the shared edge (8 ulp of 1 plus the edge's own rounding; the uv
// parity bound is 8 ulps).
bool explained(int cpu_t, int gpu_t, int R, vec3<float> l, vec2<float> uv, std::string& why) {
  if (gpu_t < 0 || gpu_t >= vplkit::texel_count(R)) return false;
  const int fc = vplkit::texel_face(cpu_t, R), fg = vplkit::texel_face(gpu_t, R);
  const ivec2 c = vplkit::texel_coords(cpu_t, R), g = vplkit::texel_coords(gpu_t, R);
  if (fc != fg) {
    why = "seam";
    return c == g && std::abs(l.z) <= 2.4e-7f * glm::length(l);
  }
  why = "edge";
  // The owner (texel_owner_from_uv) of a uv within 1e-6 of this one: a texel edge, of uv or of
  // the pulled uv (1 - 2/R) of the rim band, lies that close.
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      if (vplkit::texel_owner_from_uv(uv + 1e-6f * vec2<float>(float(dx), float(dy)), R) == g) return true;
  return false;
}

}  // namespace

TEST_CASE("dprsm_view: texel_of_direction and texel_of_point (10^5 random + centre rays + seam + rim band)") {
  for (int which = 0; which < 2; ++which) {
    dprsm_data d = make_dprsm(which);
    random_source rnd(55 + std::uint32_t(which));
    std::vector<vec3<float>> dirs, points;
    std::vector<std::string> kind;
    for (int i = 0; i < 100000; ++i) {
      dirs.push_back(rnd.sphere_direction() * float(std::pow(10.0, rnd.uniform(-10, 10))));
      points.push_back(d.light.position + rnd.in_box(8));
      kind.push_back("random");
    }
    // The centre ray of every texel (world direction, as the builder casts it).
    for (int face = 0; face < 2; ++face)
      for (int y = 0; y < d.R; ++y)
        for (int x = 0; x < d.R; ++x) {
          const vec3<float> w = d.light.frame.to_world(
              vplkit::paraboloid_to_direction(face, vplkit::texel_center_uv<float>(x, y, d.R)));
          dirs.push_back(w);
          points.push_back(d.light.position + 2.5f * w);
          kind.push_back("centre ray");
        }
    // The seam: light-space rim directions (z = 0) taken to world space; the rotation back into
    // light space leaves z = +-tiny, whose sign decides the face.
    for (int k = 0; k < 4000; ++k) {
      const double phi = rnd.uniform(0, 2 * pi);
      const vec3<float> w =
          d.light.frame.to_world(vec3<float>(float(std::cos(phi)), float(std::sin(phi)), 0.0f));
      dirs.push_back(w);
      points.push_back(d.light.position + 3.0f * w);
      kind.push_back("seam");
    }
    // The rim band: directions within 3 texels of the rim, where a uv inside the disk can lie in
    // an invalid texel and is filed under the valid neighbour that owns it.
    for (int k = 0; k < 8000; ++k) {
      const double phi = rnd.uniform(0, 2 * pi), z = rnd.uniform(-3, 3) / d.R;
      const vec3<float> w = d.light.frame.to_world(vec3<float>(
          float(std::sqrt(1 - z * z) * std::cos(phi)), float(std::sqrt(1 - z * z) * std::sin(phi)), float(z)));
      dirs.push_back(w);
      points.push_back(d.light.position + 3.0f * w);
      kind.push_back("rim band");
    }
    // The poles.
    for (float s : {1.0f, -1.0f}) {
      dirs.push_back(d.light.frame.axis_z * s);
      points.push_back(d.light.position + d.light.frame.axis_z * s);
      kind.push_back("pole");
    }
    std::vector<float4> in;
    for (std::size_t i = 0; i < dirs.size(); ++i) {
      in.push_back(f4(dirs[i]));
      in.push_back(f4(points[i]));
    }
    struct int2 {
      std::int32_t dir, point;
    };
    const auto gpu = run_compute<int2>(dprsm_kernel(d, "", {input(0, in, "vec4 q")}, "ivec2 result", R"(
  vplkit_dprsm_view view = load_view();
  result[i] = ivec2(vplkit_dprsm_view_texel_of_direction(view, q[2u * i].xyz),
                    vplkit_dprsm_view_texel_of_point(view, q[2u * i + 1u].xyz));)"),
                                       dirs.size());
    std::size_t differ[2] = {0, 0}, seam[2] = {0, 0}, unexplained = 0, centre_differ = 0;
    for (std::size_t i = 0; i < dirs.size(); ++i) {
      for (int which_q = 0; which_q < 2; ++which_q) {
        const vec3<float> q = which_q == 0 ? dirs[i] : points[i] - d.light.position;
        const int ct = which_q == 0 ? d.view.texel_of_direction(dirs[i]) : d.view.texel_of_point(points[i]);
        const int gt = which_q == 0 ? gpu[i].dir : gpu[i].point;
        if (ct == gt) continue;
        ++differ[which_q];
        if (kind[i] == "centre ray") ++centre_differ;
        const vec3<float> l = d.light.frame.to_light(q);
        const vec2<float> uv = vplkit::paraboloid_from_direction(l).uv;
        std::string why;
        if (!explained(ct, gt, d.R, l, uv, why)) {
          ++unexplained;
          UNSCOPED_INFO("unexplained texel difference (" << kind[i] << "): cpu " << ct << " gpu "
                        << gt << " q " << show3(q) << " light space " << show3(l));
        } else if (why == "seam") {
          ++seam[which_q];
        }
      }
    }
    std::cout << "  texel_of_direction / texel_of_point (light " << which << ", R " << d.R
              << "): " << dirs.size() << " queries each; differing texels: " << differ[0] << " / "
              << differ[1] << " (seam face flips " << seam[0] << " / " << seam[1]
              << ", the rest at texel edges), unexplained: " << unexplained << "\n";
    CHECK(unexplained == 0);
    CHECK(centre_differ == 0);  // centre rays are far from every edge: exact
    // Random directions: a difference needs a uv within ~1e-6 of an edge (probability ~R * 1e-6
    // per axis): allow at most 0.1% of them.
    CHECK(differ[0] - seam[0] <= 100);
    CHECK(differ[1] - seam[1] <= 100);
  }
}

// Is y within rounding of dprsm_plane_side_of's threshold for texel t (or of its branch's edge)?
// side -1: the behind/on threshold (lit), +1: the on/in-front threshold (in_front).
bool lit_band(const dprsm_data& d, int t, vec3<float> y, float tolerance, int side = -1) {
  const vec3<double> c(d.light.position), y_t(d.P[std::size_t(t)]), yd(y);
  const vec3<double> n = vplkit::unit_or_zero(vec3<double>(d.N[std::size_t(t)]));
  const double d_y = glm::length(yd - c), d_t = glm::length(y_t - c);
  const double tol = double(tolerance) + double(vplkit::dprsm_lookup_slack(float(d_y), d.R));
  const double scale = 8 * double(flt_eps) * (glm::length(yd) + glm::length(y_t) + glm::length(c) + d_y + tol);
  const double h = glm::dot(n, c - y_t), cos_a = -glm::dot(n, (yd - c) / d_y);
  const double min_cos = double(vplkit::dprsm_plane_min_cos<float>());
  if (std::abs(h) <= scale || std::abs(cos_a - min_cos) <= scale / std::max(d_y, 1e-30)) return true;
  if (h > 0 && cos_a > min_cos) return std::abs(glm::dot(n, yd - y_t) - side * tol * cos_a) <= scale;
  return std::abs(d_y - d_t + side * tol) <= scale;
}

TEST_CASE("dprsm_lookup: texel, lit and in-front decisions, exact except within a band around the tolerance") {
  const float tolerance = 0.05f;
  for (int which = 0; which < 2; ++which) {
    const dprsm_data d = make_dprsm(which);
    random_source rnd(66 + std::uint32_t(which));
    std::vector<vec3<float>> ys;
    std::vector<std::string> kind;
    // every stored texel position, and moved along its light ray by fractions of the tolerance
    // (inside, outside, and +-1e-3 relative around it)
    for (int i = 0; i < d.view.texel_count(); ++i) {
      const vec3<float> p = d.P[std::size_t(i)];
      if (d.A[std::size_t(i)] == vec3<float>(0)) continue;
      const vec3<float> c = d.light.position;
      const float len = glm::length(p - c);
      if (!(len > 0)) continue;
      const vec3<float> dir = (p - c) / len;
      for (float f : {0.0f, 0.5f, -0.5f, 0.999f, -0.999f, 1.001f, -1.001f, 2.0f, -2.0f}) {
        ys.push_back(p + dir * (f * tolerance));
        kind.push_back("texel " + std::to_string(i) + " moved " + show(f) + " tolerance");
      }
    }
    // points of each texel's plane off its centre (where the plane, not the centre's depth,
    // decides), moved along their light ray by 0, +-0.5 and +-2 tolerances
    for (int i = 0; i < d.view.texel_count(); i += 2) {
      if (d.A[std::size_t(i)] == vec3<float>(0)) continue;
      const vec3<float> c = d.light.position, n = vplkit::unit_or_zero(d.N[std::size_t(i)]);
      const vplkit::ivec2 xy = vplkit::texel_coords(i, d.R);
      const vec2<float> xi(float(rnd.uniform(0.1, 0.9)), float(rnd.uniform(0.1, 0.9)));
      const vec3<float> w = d.light.frame.to_world(vplkit::paraboloid_to_direction(
          vplkit::texel_face(i, d.R), vplkit::texel_point_uv(xy.x, xy.y, d.R, xi)));
      const float d_p = glm::dot(n, c - d.P[std::size_t(i)]) / -glm::dot(n, w);
      if (!(d_p > 0) || !(d_p < 1e3f)) continue;
      for (float f : {0.0f, 0.5f, -0.5f, 2.0f, -2.0f}) {
        ys.push_back(c + (d_p + f * tolerance) * w);
        kind.push_back("texel " + std::to_string(i) + " plane point moved " + show(f) + " tolerance");
      }
    }
    for (int i = 0; i < 100000; ++i) {
      ys.push_back(d.light.position + rnd.in_box(6));
      kind.push_back("random");
    }
    ys.push_back(d.light.position);
    kind.push_back("the light position");
    std::vector<float4> in;
    for (const auto& y : ys) in.push_back(f4(y));
    kernel_call call = dprsm_kernel(d, "", {input(0, in, "vec4 q")}, "ivec2 result", R"(
  vplkit_dprsm_lookup_result r = vplkit_dprsm_lookup(load_view(), q[i].xyz, TOLERANCE);
  result[i] = ivec2(r.texel, (r.lit ? 1 : 0) + (r.in_front ? 2 : 0));)");
    call.defines = "#define TOLERANCE " + show(double(tolerance)) + "\n";
    struct int2 {
      std::int32_t texel, lit;
    };
    const auto gpu = run_compute<int2>(call, ys.size());
    series<std::int32_t> texel, lit, in_front;
    std::size_t texel_edges = 0, band = 0, lit_count = 0, front_count = 0, unexplained = 0;
    for (std::size_t i = 0; i < ys.size(); ++i) {
      const vplkit::dprsm_lookup_result r = vplkit::dprsm_lookup(d.view, ys[i], tolerance);
      if (r.lit) ++lit_count;
      if (r.in_front) ++front_count;
      int gt = gpu[i].texel;
      int glit = gpu[i].lit & 1;
      int gfront = gpu[i].lit >> 1;
      if (gt != r.texel) {
        const vec3<float> l = d.light.frame.to_light(ys[i] - d.light.position);
        std::string why;
        if (r.texel < 0 || gt < 0 ||
            !explained(r.texel, gt, d.R, l, vplkit::paraboloid_from_direction(l).uv, why)) {
          ++unexplained;
          UNSCOPED_INFO("unexplained lookup texel: cpu " << r.texel << " gpu " << gt << " y "
                        << show3(ys[i]));
        }
        ++texel_edges;  // a different texel legitimately answers lit differently: skip lit
        gt = r.texel;
        glit = r.lit;
        gfront = r.in_front;
      }
      // lit: n . (y - y_t) >= -tol cos(alpha) (or, falling back, d_y <= d_t + tol) with lengths and
      // dot products that differ by an ulp or two (FMA in dot): a point within 8 eps of the scale
      // of the positions from the threshold may go either way, and so may a point whose cos(alpha)
      // or h lies within as much of the branch's edge.
      if (r.texel >= 0 && glit != int(r.lit) && lit_band(d, r.texel, ys[i], tolerance)) {
        ++band;
        glit = r.lit;
        gfront = r.in_front;  // behind on one side: not in front on either
      }
      if (r.texel >= 0 && gfront != int(r.in_front) && lit_band(d, r.texel, ys[i], tolerance, +1)) {
        ++band;
        gfront = r.in_front;
      }
      texel.add(gt, r.texel);
      lit.add(glit, r.lit);
      in_front.add(gfront, r.in_front);
    }
    const std::string what = "dprsm_lookup (light " + std::to_string(which) + ", R " + std::to_string(d.R) + ")";
    std::cout << "  " << what << ": " << ys.size() << " points, " << lit_count
              << " lit on the CPU (" << front_count << " in front); texels differing at edges/seam: " << texel_edges
              << ", lit decisions differing inside the band: " << band << "\n";
    CHECK(unexplained == 0);
    CHECK(texel_edges <= 100);
    auto describe = [&](std::size_t i) { return kind[i] + ": y " + show3(ys[i]); };
    VPLKIT_CHECK_PARITY(compare_exact(texel, describe,
                                      what + ": texel (edge/seam differences explained above)"));
    VPLKIT_CHECK_PARITY(compare_exact(lit, describe,
                                      what + ": lit (exact outside the band)"));
    VPLKIT_CHECK_PARITY(compare_exact(in_front, describe, what + ": in front (exact outside the bands)"));
    CHECK(front_count > 1000);
  }
}

TEST_CASE("direct_light: lit decision and value, exact decisions except near a depth-tolerance edge") {
  for (int which = 0; which < 2; ++which) {
    const dprsm_data d = make_dprsm(which);
    random_source rnd(77 + std::uint32_t(which));
    std::vector<vplkit::gather_point<float>> gps;
    std::vector<std::string> kind;
    // What the light sees (lit, by construction, but for the hand-made texels of light 0) ...
    for (int i = 0; i < d.view.texel_count(); ++i) {
      if (d.A[std::size_t(i)] == vec3<float>(0)) continue;
      gps.push_back({d.P[std::size_t(i)], d.N[std::size_t(i)], d.A[std::size_t(i)]});
      kind.push_back("texel " + std::to_string(i));
    }
    // ... and the floor, partly in the shadow of the walls, with unnormalised normals.
    for (int i = 0; i < 20000; ++i) {
      const vec3<float> p(float(rnd.uniform(-6, 6)), float(rnd.uniform(-6, 6)), 0.0f);
      gps.push_back({p, vec3<float>(0, 0, float(rnd.uniform(0.01, 10))), vec3<float>(0.8f, 0.5f, 0.3f)});
      kind.push_back("floor");
    }
    // ... the floor again with shading normals tilted up to 60 degrees off the geometric one (the
    // cosine is theirs, the facing test and the tolerance are the floor's) ...
    for (int i = 0; i < 2000; ++i) {
      const vec3<float> p(float(rnd.uniform(-6, 6)), float(rnd.uniform(-6, 6)), 0.0f);
      const float a = 1.05f * float(i) / 2000.0f, phi = 0.01f * float(i);
      const vec3<float> ns(std::sin(a) * std::cos(phi), std::sin(a) * std::sin(phi), std::cos(a));
      gps.push_back({p, vec3<float>(0, 0, 1), vec3<float>(0.8f, 0.5f, 0.3f), ns});
      kind.push_back("floor, two normals");
    }
    gps.push_back({d.light.position, vec3<float>(0, 0, 1), vec3<float>(1)});
    kind.push_back("at the light");
    gps.push_back({vec3<float>(1, 1, 0), vec3<float>(0, 0, -1), vec3<float>(1)});
    kind.push_back("facing away");
    gps.push_back({vec3<float>(1, 1, 0), vec3<float>(0), vec3<float>(1)});
    kind.push_back("background");
    const std::vector<float4> gpu = gpu_direct_light(d, gps);
    std::size_t lit = 0, edge = 0;
    series<std::int32_t> lit_decision;
    std::vector<float> gv[3];
    std::vector<double> cv[3];
    for (std::size_t i = 0; i < gps.size(); ++i) {
      const vplkit::gather_point<float>& g = gps[i];
      const vec3<float> c = vplkit::direct_light(g, d.view);
      const vec3<float> gc(gpu[i].x, gpu[i].y, gpu[i].z);
      int gl = gc != vec3<float>(0) ? 1 : 0;
      const int cl = c != vec3<float>(0) ? 1 : 0;
      lit += std::size_t(cl);
      if (gl != cl) {
        // The decision turns on |d_y - d_t| <= tolerance with lengths, a tolerance and a texel
        // of a few float roundings each: a flip is explained only near the tolerance's edge (or
        // at a texel edge, where both sides may look up different texels; counted together).
        ++edge;
        gl = cl;
      }
      lit_decision.add(gl, cl);
      // Values where both are lit, scaled by rho I / (pi d^2): what is compared is cos(alpha).
      const vec3<double> w = vec3<double>(d.light.position) - vec3<double>(g.position);
      for (int ch = 0; ch < 3; ++ch) {
        const double scale = double(g.albedo[ch]) * double(d.light.intensity[ch]) / (pi * glm::dot(w, w));
        const bool both = gc != vec3<float>(0) && c != vec3<float>(0);
        gv[ch].push_back(both ? float(double(gc[ch]) / scale) : 0.0f);
        cv[ch].push_back(both ? double(c[ch]) / scale : 0.0);
      }
    }
    const std::string what = "direct_light (light " + std::to_string(which) + ", R " + std::to_string(d.R) + ")";
    std::cout << "  " << what << ": " << gps.size() << " gather points, " << lit
              << " lit on the CPU; decisions differing at a tolerance or texel edge: " << edge << "\n";
    CHECK(lit > gps.size() / 4);
    CHECK(lit < gps.size() - 1000);  // the walls' shadows are there
    CHECK(edge <= gps.size() / 1000);
    auto describe = [&](std::size_t i) { return kind[i] + ": x " + show3(gps[i].position); };
    VPLKIT_CHECK_PARITY(compare_exact(lit_decision, describe, what + ": lit (flips at edges counted above)"));
    for (int ch = 0; ch < 3; ++ch)
      VPLKIT_CHECK_PARITY(compare_floats_abs(gv[ch], cv[ch], cosine_bound, describe,
                                             what + ": " + channel_name(ch) + " / (rho I / pi d^2)"));
  }
}

TEST_CASE("direct_light: gather points 2^-66 to 2^-60 and 2^40 to 2^70 from the light (scale-first facing test)") {
  // Light 1's DPRSM with the light moved to the origin, so that coordinates are as small as the
  // distances (else the points would coincide with the light). Below 2^-63 the squared distance is
  // a denormal (0 on a GPU that flushes, and in the [ftz-daz] reference), and near 2^-63 the
  // squares of single components are; beyond 2^64 it overflows. The distances are scaled first
  // (scaled_length), so neither decides: lit near the light on both sides, unlit far away.
  dprsm_data d = make_dprsm(1);
  d.light.position = vec3<float>(0);
  d.light.frame.position = vec3<float>(0);
  d.view.light = d.light;
  random_source rnd(91);
  std::vector<vplkit::gather_point<float>> gps;
  std::vector<std::string> kind;
  for (int e = -66; e <= 70; ++e) {
    if (e == -59) e = 40;  // the two ranges
    for (int k = 0; k < 200; ++k) {
      const vec3<float> dir = rnd.sphere_direction();
      const float s = std::ldexp(float(rnd.uniform(1.0, 1.99)), e);
      // Facing the light for most, a random (unnormalised) normal for the rest.
      const vec3<float> n = k % 4 == 3 ? rnd.sphere_direction() * float(rnd.uniform(0.01, 10)) : -dir;
      gps.push_back({dir * s, n, vec3<float>(0.8f, 0.5f, 0.3f)});
      kind.push_back("2^" + std::to_string(e) + " from the light");
    }
  }
  const std::vector<float4> gpu = gpu_direct_light(d, gps);
  series<std::int32_t> lit_decision;
  std::vector<float> gv[3];
  std::vector<double> cv[3];
  std::size_t lit_near = 0, lit_below = 0;
  for (std::size_t i = 0; i < gps.size(); ++i) {
    const vplkit::gather_point<float>& g = gps[i];
    const vec3<float> c = vplkit::direct_light(g, d.view);
    const vec3<float> gc(gpu[i].x, gpu[i].y, gpu[i].z);
    const int cl = c != vec3<float>(0) ? 1 : 0;
    lit_decision.add(gc != vec3<float>(0) ? 1 : 0, cl);
    const double dist = glm::length(vec3<double>(g.position));
    if (cl != 0 && dist < 0x1p-50) ++lit_near;
    if (cl != 0 && dist < 0x1p-64) ++lit_below;
    // Values scaled by rho I / (pi max(d^2, 2^-63)) (reflected_radiance's floor): the cosine.
    const vec3<double> w = vec3<double>(g.position);
    const double d2 = std::max(glm::dot(w, w), 0x1p-63);
    for (int ch = 0; ch < 3; ++ch) {
      const double scale = double(g.albedo[ch]) * double(d.light.intensity[ch]) / (pi * d2);
      const bool both = gc != vec3<float>(0) && c != vec3<float>(0);
      gv[ch].push_back(both ? float(double(gc[ch]) / scale) : 0.0f);
      cv[ch].push_back(both ? double(c[ch]) / scale : 0.0);
    }
  }
  std::cout << "  direct_light near and far: " << gps.size() << " gather points, " << lit_near
            << " lit on the CPU within 2^-50 of the light, " << lit_below << " within 2^-64\n";
  CHECK(lit_near > 100);
  CHECK(lit_below > 50);
  auto describe = [&](std::size_t i) { return kind[i] + ": x " + show3(gps[i].position) + " n " + show3(gps[i].normal); };
  VPLKIT_CHECK_PARITY(compare_exact(lit_decision, describe, "direct_light near and far: lit"));
  for (int ch = 0; ch < 3; ++ch)
    VPLKIT_CHECK_PARITY(compare_floats_abs(gv[ch], cv[ch], cosine_bound, describe,
                                           std::string("direct_light near and far: ") + channel_name(ch) + " / (rho I / pi d^2)"));
}

TEST_CASE("vpl constants: the GLSL values are the C++ values, bit for bit") {
  VPLKIT_CHECK_PARITY(compare_constants(
      R"(#include "vplkit/vpl/vpl.glsl")",
      {{"floatBitsToUint(vplkit_vpl_pi)", bits_of(vplkit::vpl_pi<float>)},
       {"floatBitsToUint(vplkit_vpl_distance_sq_floor())", bits_of(vplkit::vpl_distance_sq_floor<float>())},
       {"floatBitsToUint(vplkit_vpl_min_cos_alpha)", bits_of(vplkit::vpl_min_cos_alpha<float>)},
       {"floatBitsToUint(vplkit_vpl_coincidence_factor)", bits_of(16.0f * flt_eps)},
       // the tolerance itself for a point of size 1 and 3: 16 eps s
       {"floatBitsToUint(vplkit_vpl_coincidence_tolerance(vec3(1.0, 0.0, 0.0), vec3(0.0)))",
        bits_of(vplkit::vpl_coincidence_tolerance(vec3<float>(1, 0, 0), vec3<float>(0)))},
       {"floatBitsToUint(vplkit_vpl_coincidence_tolerance(vec3(0.0), vec3(0.0, -3.0, 2.0)))",
        bits_of(vplkit::vpl_coincidence_tolerance(vec3<float>(0), vec3<float>(0, -3, 2)))}},
      "pi, distance floor, min cos alpha, 16 eps, tolerances (bits)"));
}
