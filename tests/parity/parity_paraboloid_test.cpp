// SPDX-License-Identifier: MIT
// CPU/GPU parity of glsl/vplkit/paraboloid/*.glsl with include/vplkit/paraboloid/*.hpp (T = float):
// unit_or_zero, the dual paraboloid mapping both ways, the texel grid (integers exact), the texel
// solid angle and the light frame. Random inputs with fixed seeds plus the hard cases of
// docs/math.md section 10 (poles, rim z = 0 and +-1 ulp, r2 slightly above 1 from rounding, texels
// next to the rim).
//
// Why exact integers are possible: every integer result (face, texel) is decided on values that
// both sides compute with the same correctly rounded operations (GLSL 4.30 4.7.1: + - * are
// correctly rounded), or in integer arithmetic (texel_is_valid). Division and sqrt are not
// correctly rounded in GLSL (2.5 and 3 ulp); where a GPU quotient feeds an integer decision (a uv
// computed from a direction, then its texel) the test bounds and explains the possible difference
// instead (see "texel of a direction" below).
#include <parity_harness.hpp>

#include <gpu_model_float.hpp>
#include <gpu_precision.hpp>

#include <vplkit/core/unit_or_zero.hpp>
#include <vplkit/paraboloid/light_frame.hpp>
#include <vplkit/paraboloid/paraboloid.hpp>
#include <vplkit/paraboloid/texel_grid.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <vector>

using namespace vplkit::parity;
using vplkit::ivec2;
using vplkit::vec2;
using vplkit::vec3;
using vplkit_test::flt_eps;
using vplkit_test::flt_inf;
using vplkit_test::flt_max;
using vplkit_test::flt_min;
using vplkit_test::pi;
using vplkit_test::random_source;

namespace {

// ---- mapping ---------------------------------------------------------------------------------

struct point_out {  // std430 { vec2 uv; int face; int pad; }
  float u, v;
  std::int32_t face, pad;
};

std::vector<point_out> gpu_from_direction(const std::vector<vec3<float>>& dirs) {
  std::vector<float4> in;
  for (const auto& d : dirs) in.push_back(f4(d));
  return run_compute<point_out>(per_item(R"(
#include "vplkit/paraboloid/paraboloid.glsl"
struct point_out { vec2 uv; int face; int pad; };
)",
                                         {input(0, in, "vec4 d")}, "point_out result", R"(
  vplkit_paraboloid_point p = vplkit_paraboloid_from_direction(d[i].xyz);
  result[i] = point_out(p.uv, p.face, 0);)"),
                                dirs.size());
}

// uv: the C++ normalises (1 / sqrt and a product: 1.5 ulp), divides by 1 + |z| (0.5) and, on the
// rim, scales by 1 / sqrt(r2) (1.5); the GLSL does the same with a GPU's inversesqrt
// (spec::normalize_ulps: 2.5), division (spec::div_ulps: 2.5) and inversesqrt again (2 + 0.5): with
// correctly rounded operations (llvmpipe) the bits nearly agree; a GPU within the table may differ
// by 3.5 + 7.5 = 11 ulps, and FMA contraction of the dot products adds about one. No subtraction
// is involved, so ulps are meaningful down to uv = 0. The GPU model below shows the bound holds for
// any division and inversesqrt within the table.
constexpr double uv_ulps = 3.5 + vplkit_test::spec::normalize_ulps + vplkit_test::spec::div_ulps +
                           vplkit_test::spec::inversesqrt_ulps + vplkit_test::spec::add_mul_ulps + 1.0;
static_assert(uv_ulps == 12.0, "the bound the comment derives");

// A direction through the GPU model (gpu_model_float.hpp).
point_out model_from_direction(const vec3<float>& d) {
  using W = vplkit_test::gpu_float;
  const auto p = vplkit::paraboloid_from_direction(vec3<W>(W(d.x), W(d.y), W(d.z)));
  return {float(p.uv.x), float(p.uv.y), p.face, 0};
}

// Compares faces exactly and uv within uv_ulps; also requires dot(uv, uv) <= 1 + 1 ulp on the GPU
// (the C++ side guarantees <= 1; a GPU rsqrt/division may leave the clamp 1 ulp outside).
void check_from_direction(const std::vector<vec3<float>>& dirs, const std::string& what) {
  const auto gpu = gpu_from_direction(dirs);
  std::vector<point_out> cpu;
  for (const auto& d : dirs) {
    const auto p = vplkit::paraboloid_from_direction(d);
    cpu.push_back({p.uv.x, p.uv.y, p.face, 0});
  }
  auto describe = [&](std::size_t i) {
    const auto p = vplkit::paraboloid_from_direction(dirs[i]);
    return "d = " + show3(dirs[i]) + " cpu uv = " + show2(p.uv) + " face " + show(p.face);
  };
  VPLKIT_CHECK_PARITY(compare_field_exact(gpu, cpu, [](const point_out& p) { return p.face; }, describe,
                                          what + ": face"));
  VPLKIT_CHECK_PARITY(compare_field_abs(gpu, cpu, [](const point_out& p) { return p.u; }, within_ulps(uv_ulps),
                                        describe, what + ": u"));
  VPLKIT_CHECK_PARITY(compare_field_abs(gpu, cpu, [](const point_out& p) { return p.v; }, within_ulps(uv_ulps),
                                        describe, what + ": v"));
  // The same bounds for the GPU model at its extremes and at random within the table.
  std::uint64_t seed = 3;
  for (const auto deviation : vplkit_test::gpu_model_deviations) {
    const vplkit_test::gpu_model_scope model(deviation, seed++);
    std::vector<point_out> mv;
    for (const auto& d : dirs) mv.push_back(model_from_direction(d));
    const std::string m = what + ", GPU model (" + vplkit_test::to_string(deviation) + ")";
    VPLKIT_CHECK_PARITY(compare_field_exact(mv, cpu, [](const point_out& p) { return p.face; }, describe, m + ": face"));
    VPLKIT_CHECK_PARITY(compare_field_abs(mv, cpu, [](const point_out& p) { return p.u; }, within_ulps(uv_ulps),
                                          describe, m + ": u"));
    VPLKIT_CHECK_PARITY(compare_field_abs(mv, cpu, [](const point_out& p) { return p.v; }, within_ulps(uv_ulps),
                                          describe, m + ": v"));
  }
  std::size_t outside = 0, above_one_ulp = 0;
  for (std::size_t i = 0; i < gpu.size(); ++i) {
    const float r2 = gpu[i].u * gpu[i].u + gpu[i].v * gpu[i].v;
    if (r2 > 1.0f) ++outside;
    if (r2 > 1.0f + flt_eps) {
      ++above_one_ulp;
      UNSCOPED_INFO("gpu uv outside the disk by more than 1 ulp: " << describe(i));
    }
    REQUIRE(std::isfinite(gpu[i].u));
    REQUIRE(std::isfinite(gpu[i].v));
  }
  std::cout << "  " << what << ": gpu uv with r2 > 1: " << outside << ", > 1 + eps: "
            << above_one_ulp << " (of " << gpu.size() << ")\n";
  CHECK(above_one_ulp == 0);
}

}  // namespace

TEST_CASE("unit_or_zero and max_abs_component: random vectors of any scale and degenerate ones") {
  random_source rnd(101);
  std::vector<vec3<float>> vs;
  for (int i = 0; i < 100000; ++i) {
    // a direction times 10^[-30, 30]; a third of them with components of mixed magnitudes
    vec3<float> d = rnd.sphere_direction();
    if (i % 3 == 0) d.y *= float(std::pow(10.0, rnd.uniform(-20, 0)));
    vs.push_back(d * float(std::pow(10.0, rnd.uniform(-30, 30))));
  }
  for (float s : {1.0f, 1e-30f, 1e30f, 4.0f * flt_min, flt_max})
    for (vec3<float> d : {vec3<float>(0, 0, 1), vec3<float>(0, 0, -1), vec3<float>(1, 1, 1),
                          vec3<float>(-1, 1, -1), vec3<float>(1, -1e-7f, 0)})
      vs.push_back(d * s);
  for (vec3<float> d :
       {vec3<float>(0), vec3<float>(-0.0f), vec3<float>(flt_max, flt_max, flt_max),
        vec3<float>(flt_inf, 0, 0), vec3<float>(1, -flt_inf, 1), vec3<float>(flt_inf, -flt_inf, 0)})
    vs.push_back(d);
  // NaN components: 0 on both sides, the GPU's decided on the bits (a compiler that assumes no NaN
  // may fold the comparisons; NVIDIA 580 did for the plane records).
  const float flt_nan = std::numeric_limits<float>::quiet_NaN();
  for (vec3<float> d : {vec3<float>(flt_nan, 0, 1), vec3<float>(1, 1, flt_nan), vec3<float>(flt_nan, flt_inf, 0),
                        vec3<float>(flt_nan, flt_nan, flt_nan), vec3<float>(flt_nan, 1e30f, 1e-30f)})
    vs.push_back(d);
  std::vector<float4> in;
  for (const auto& v : vs) in.push_back(f4(v));
  const auto gpu = run_compute<float4>(
      per_item(R"(#include "vplkit/core/unit_or_zero.glsl")", {input(0, in, "vec4 v")}, "vec4 result",
               "result[i] = vec4(vplkit_unit_or_zero(v[i].xyz), vplkit_max_abs_component(v[i].xyz));"),
      vs.size());
  std::vector<float4> cpu;
  for (const auto& v : vs) cpu.push_back(f4(vplkit::unit_or_zero(v), vplkit::max_abs_component(v)));
  std::vector<float4> gpu_max = gpu, cpu_max = cpu;  // max_abs_component of a NaN vector: no contract
  for (std::size_t i = 0; i < vs.size(); ++i)
    if (std::isnan(vs[i].x) || std::isnan(vs[i].y) || std::isnan(vs[i].z)) gpu_max[i].w = cpu_max[i].w = 0.0f;
  auto describe = [&](std::size_t i) { return "v = " + show3(vs[i]); };
  // max_abs_component: abs and comparisons only -> exact (NaN components excepted: the GPU may
  // fold the comparisons into max(), which may or may not drop a NaN).
  VPLKIT_CHECK_PARITY(compare_field_abs(gpu_max, cpu_max, [](const float4& v) { return v.w; }, within_ulps(0),
                                        describe, "max_abs_component"));
  // An exact power-of-two scaling, dot, then the C++ divides by sqrt (1 ulp) where the GLSL
  // multiplies by inversesqrt (spec::normalize_ulps); a dot contracted into FMAs moves len2 by an
  // ulp (0.5 ulp of the result): 1 + 2.5 + 0.5 = 4 ulps; no cancellation, so ulps stay meaningful
  // for small components. Bound 8 ulps, shown below to hold for the GPU model too.
  const double unit_ulps = 8;
  for (int c = 0; c < 3; ++c) {
    VPLKIT_CHECK_PARITY(compare_field_abs(gpu, cpu, [c](const float4& v) { return v[c]; }, within_ulps(unit_ulps),
                                          describe, std::string("unit_or_zero ") + "xyz"[c]));
  }
  std::uint64_t seed = 5;
  for (const auto deviation : vplkit_test::gpu_model_deviations) {
    const vplkit_test::gpu_model_scope model(deviation, seed++);
    using W = vplkit_test::gpu_float;
    std::vector<float4> mv;
    for (const auto& v : vs) {
      const auto u = vplkit::unit_or_zero(vec3<W>(W(v.x), W(v.y), W(v.z)));
      mv.push_back({float(u.x), float(u.y), float(u.z), 0.0f});
    }
    for (int c = 0; c < 3; ++c) {
      VPLKIT_CHECK_PARITY(compare_field_abs(mv, cpu, [c](const float4& v) { return v[c]; }, within_ulps(unit_ulps),
                                            describe, std::string("GPU model (") + vplkit_test::to_string(deviation) +
                                                          "): unit_or_zero " + "xyz"[c]));
    }
  }
}

TEST_CASE("scaled_length: random vectors of any scale (2^-126 to FLT_MAX) and degenerate ones") {
  random_source rnd(103);
  std::vector<vec3<float>> vs;
  for (int i = 0; i < 60000; ++i) {
    // a direction times 2^[-126, 128]; a third of them with components of mixed magnitudes
    vec3<float> d = rnd.sphere_direction();
    if (i % 3 == 0) d.y *= float(std::pow(2.0, rnd.uniform(-40, 0)));
    vs.push_back(d * float(std::ldexp(1.0, rnd.integer(-124, 127))));
  }
  for (float s : {0x1p-126f, 0x1p-64f, 0x1p-63f, 0x1p-50f, 0x1p-51f, 0x1p62f, 0x1p63f, 0x1p64f, flt_max})
    for (vec3<float> d : {vec3<float>(0, 0, 1), vec3<float>(1, 1, 1), vec3<float>(-1, 1, -1),
                          vec3<float>(0.75f, -0.5f, 0.25f), vec3<float>(1, 0x1p-20f, 0x1p-30f)})
      vs.push_back(d * s);
  for (vec3<float> d : {vec3<float>(0), vec3<float>(flt_max, flt_max, flt_max), vec3<float>(flt_inf, 0, 0),
                        vec3<float>(1, -flt_inf, 1)})
    vs.push_back(d);
  std::vector<float4> in;
  for (const auto& v : vs) in.push_back(f4(v));
  const auto gpu = run_compute<float>(per_item(R"(#include "vplkit/core/unit_or_zero.glsl")", {input(0, in, "vec4 v")},
                                               "float result", "result[i] = vplkit_scaled_length(v[i].xyz);"),
                                      vs.size());
  std::vector<float> cpu;
  for (const auto& v : vs) cpu.push_back(vplkit::scaled_length(v));
  auto describe = [&](std::size_t i) { return "v = " + show3(vs[i]); };
  // sqrt (spec::sqrt_ulps, inherited from 1 / inversesqrt) against the C++'s correctly rounded one
  // (0.5), a dot contracted into FMAs (an ulp of len2: 0.5 ulp of the length), the exact scalings:
  // 4.5 + 0.5 + 0.5 = 5.5 ulps; bound 8, shown below to hold for the GPU model too.
  const double length_ulps = 8;
  VPLKIT_CHECK_PARITY(compare_floats(gpu, cpu, within_ulps(length_ulps), describe, "scaled_length"));
  std::uint64_t seed = 11;
  for (const auto deviation : vplkit_test::gpu_model_deviations) {
    const vplkit_test::gpu_model_scope model(deviation, seed++);
    const vplkit_test::reciprocal_division_scope reciprocal;  // NVIDIA's division, should one enter
    using W = vplkit_test::gpu_float;
    std::vector<float> mv;
    for (const auto& v : vs) mv.push_back(float(vplkit::scaled_length(vec3<W>(W(v.x), W(v.y), W(v.z)))));
    VPLKIT_CHECK_PARITY(compare_floats(mv, cpu, within_ulps(length_ulps), describe,
                                       std::string("GPU model (") + vplkit_test::to_string(deviation) +
                                           "): scaled_length"));
  }
  // Never 0 for a vector with a normal component, on either side (glm::length is 0 below 2^-75).
  std::size_t zero = 0;
  for (std::size_t i = 0; i < vs.size(); ++i)
    if (vplkit::max_abs_component(vs[i]) >= flt_min && (gpu[i] == 0.0f || cpu[i] == 0.0f)) ++zero;
  CHECK(zero == 0);
}

TEST_CASE("paraboloid_from_direction: 10^5 random directions, face exact, uv within the specification's bound") {
  random_source rnd(202);
  std::vector<vec3<float>> dirs;
  for (int i = 0; i < 100000; ++i) {
    dirs.push_back(rnd.sphere_direction() * float(std::pow(10.0, rnd.uniform(-30, 30))));
  }
  check_from_direction(dirs, "from_direction (random)");

  // What float costs against the exact map, on both sides (T = double reference): informational
  // context for the bound above.
  const auto gpu = gpu_from_direction(dirs);
  std::vector<double> ref_u;
  for (const auto& d : dirs) ref_u.push_back(vplkit::paraboloid_from_direction(vec3<double>(d)).uv.x);
  VPLKIT_CHECK_PARITY(compare_floats_abs(component(gpu, [](const point_out& p) { return p.u; }), ref_u,
                                         within_ulps(8), {}, "from_direction u, gpu vs T = double"));
}

TEST_CASE("paraboloid_from_direction: hard cases (poles, rim z = 0 and +-1 ulp, r2 above 1)") {
  random_source rnd(303);
  std::vector<vec3<float>> dirs;
  // d = (0,0,+-1) at any length, and next to the back pole without cancellation.
  for (float s : {1.0f, 1e-30f, 1e30f, 4.0f * flt_min, flt_max}) {
    dirs.push_back(vec3<float>(0, 0, s));
    dirs.push_back(vec3<float>(0, 0, -s));
  }
  for (float x : {1e-3f, 1e-10f, 1e-20f, 1e-30f, 4.0f * flt_min}) {
    dirs.push_back(vec3<float>(x, -x, -1));
    dirs.push_back(vec3<float>(-x, x, 1));
  }
  // Rim: z = 0, z = -0, z = +-(smallest normal), +-eps/2, +-eps (the first floats beside 0 that a
  // GPU does not flush), at 2000 azimuths each, plus the axis directions.
  for (int k = 0; k < 2000; ++k) {
    const double phi = rnd.uniform(0.0, 2.0 * pi);
    const float x = float(std::cos(phi)), y = float(std::sin(phi));
    for (float z : {0.0f, -0.0f, flt_min, -flt_min, flt_eps / 2, -flt_eps / 2, flt_eps, -flt_eps})
      dirs.push_back(vec3<float>(x, y, z));
  }
  for (float z : {0.0f, -0.0f, flt_min, -flt_min, flt_eps, -flt_eps}) {
    dirs.push_back(vec3<float>(1, 0, z));
    dirs.push_back(vec3<float>(0, -1, z));
    dirs.push_back(vec3<float>(0.70710678f, 0.70710678f, z));
  }
  // r2 slightly above 1 from rounding: rim directions whose unclamped uv lands outside the disk
  // (about 1 in 5); keep 20000 of them.
  std::size_t above = 0;
  while (above < 20000) {
    const double phi = rnd.uniform(0.0, 2.0 * pi);
    const vec3<float> d(float(std::cos(phi)), float(std::sin(phi)), rnd.unit() < 0.5 ? 0.0f : -0.0f);
    const vec3<float> n = vplkit::unit_or_zero(d);
    const vec2<float> uv = vec2<float>(n.x, n.y) / (1.0f + std::abs(n.z));
    if (glm::dot(uv, uv) > 1.0f) {
      dirs.push_back(d);
      ++above;
    }
  }
  check_from_direction(dirs, "from_direction (hard cases)");
}

TEST_CASE("paraboloid_from_direction: denormal rim z (GPUs may flush: face may differ, uv not)") {
  // |z| < FLT_MIN: a GPU that flushes denormals sees z = +-0 and files the direction under the
  // front face where the CPU says back. The seam convention makes that harmless: uv is the same
  // on both faces at the rim. Required: equal faces, or |z| < FLT_MIN and uv within the bound.
  std::vector<vec3<float>> dirs;
  const float dmin = std::numeric_limits<float>::denorm_min();
  for (int k = 0; k < 360; ++k) {
    const double phi = 2.0 * pi * k / 360.0;
    for (float z : {dmin, -dmin, 3 * dmin, -3 * dmin, flt_min / 2, -flt_min / 2})
      dirs.push_back(vec3<float>(float(std::cos(phi)), float(std::sin(phi)), z));
  }
  const auto gpu = gpu_from_direction(dirs);
  std::size_t flips = 0;
  series<float> u, v;
  for (std::size_t i = 0; i < dirs.size(); ++i) {
    const auto p = vplkit::paraboloid_from_direction(dirs[i]);
    if (gpu[i].face != p.face) {
      ++flips;
      REQUIRE(std::abs(dirs[i].z) < flt_min);
    }
    u.add(gpu[i].u, p.uv.x);
    v.add(gpu[i].v, p.uv.y);
  }
  std::cout << "  denormal rim z: " << flips << " face flips of " << dirs.size()
            << " (0 where denormals are kept, e.g. llvmpipe)\n";
  VPLKIT_CHECK_PARITY(compare_floats_abs(u, within_ulps(uv_ulps), {}, "denormal rim: u"));
  VPLKIT_CHECK_PARITY(compare_floats_abs(v, within_ulps(uv_ulps), {}, "denormal rim: v"));
}

TEST_CASE("paraboloid_to_direction, paraboloid_jacobian and the round trip") {
  random_source rnd(404);
  std::vector<vec2<float>> uvs;
  std::vector<int> faces;
  for (int i = 0; i < 100000; ++i) {
    // mostly inside the disk, some in the corners (r2 > 1), both faces
    const float r = float(i % 5 == 0 ? rnd.uniform(0.0, 1.4142) : std::sqrt(rnd.unit()));
    const double phi = rnd.uniform(0.0, 2.0 * pi);
    uvs.push_back(vec2<float>(r * float(std::cos(phi)), r * float(std::sin(phi))));
    faces.push_back(int(i & 1));
  }
  for (int face = 0; face < 2; ++face) {
    for (vec2<float> uv : {vec2<float>(0, 0), vec2<float>(1, 0), vec2<float>(0, -1),
                           vec2<float>(-1, 0), vec2<float>(1, 1), vec2<float>(-1, 1),
                           vec2<float>(0.6f, 0.8f), vec2<float>(flt_min, -flt_min)}) {
      uvs.push_back(uv);
      faces.push_back(face);
    }
    for (int k = 0; k < 2000; ++k) {  // rim uvs (r2 = 1 to rounding, clamped into the disk)
      const double phi = rnd.uniform(0.0, 2.0 * pi);
      uvs.push_back(vplkit::paraboloid_clamp_to_disk(
          vec2<float>(float(std::cos(phi)), float(std::sin(phi)))));
      faces.push_back(face);
    }
  }
  std::vector<float4> in;
  for (std::size_t i = 0; i < uvs.size(); ++i) in.push_back({uvs[i].x, uvs[i].y, float(faces[i]), 0});
  struct out_t {
    float4 dir_jac;
    float u, v;
    std::int32_t face, pad;
  };
  const auto gpu = run_compute<out_t>(per_item(R"(
#include "vplkit/paraboloid/paraboloid.glsl"
struct out_t { vec4 dir_jac; vec2 round_uv; int round_face; int pad; };
)",
                                               {input(0, in, "vec4 q")}, "out_t result", R"(
  int face = int(q[i].z);
  vec3 d = vplkit_paraboloid_to_direction(face, q[i].xy);
  vplkit_paraboloid_point p = vplkit_paraboloid_from_direction(d);
  result[i] = out_t(vec4(d, vplkit_paraboloid_jacobian(q[i].xy)), p.uv, p.face, 0);)"),
                                      uvs.size());
  std::vector<out_t> cpu;
  for (std::size_t i = 0; i < uvs.size(); ++i) {
    const vec3<float> d = vplkit::paraboloid_to_direction(faces[i], uvs[i]);
    const auto p = vplkit::paraboloid_from_direction(d);
    cpu.push_back({f4(d, vplkit::paraboloid_jacobian(uvs[i])), p.uv.x, p.uv.y, p.face, 0});
  }
  auto describe = [&](std::size_t i) { return "face " + show(faces[i]) + " uv = " + show2(uvs[i]); };
  // d.x, d.y: products and one division (1 / (1 + r2)): a few ulp. d.z = (1 - r2) s cancels at the
  // rim, where an ulp of r2 (FMA in dot, or not) is 6e-8 absolute: bound 8 ulps or 2.4e-7 abs
  // (4 ulp of 1: components of a unit vector).
  const auto dir_bound = within_ulps(8) | within_abs(2.4e-7);
  for (int c = 0; c < 3; ++c) {
    VPLKIT_CHECK_PARITY(compare_field_abs(gpu, cpu, [c](const out_t& o) { return o.dir_jac[c]; }, dir_bound,
                                          describe, std::string("to_direction ") + "xyz"[c]));
  }
  // 4 / q^2, q = 1 + dot(uv, uv). llvmpipe contracts the dot into an FMA in this context, so q
  // can differ by 1 ulp (relative <= eps); squaring doubles that and the result's binade ([1, 4])
  // shows it as up to ~6 ulps (measured: rel 3.9e-7 = 3.3 eps). A GPU at the GLSL limit (division
  // 2.5 ulp) adds ~2 eps more: bound rel 1e-6 (8.4 eps).
  VPLKIT_CHECK_PARITY(compare_field_abs(gpu, cpu, [](const out_t& o) { return o.dir_jac.w; }, within_rel(1e-6),
                                        describe, "paraboloid_jacobian"));
  // Round trip uv -> d -> uv on each side. Where d.z is +-tiny the face of the round trip follows
  // its sign, which a GPU may compute differently at the rim (r2 = 1 +- 1 ulp): then both faces
  // are legitimate and, by the seam convention, the uv is the same. Required: equal faces, or a
  // CPU |d.z| <= 2.4e-7 (the bound above); uv within the direction bound.
  std::size_t seam_flips = 0;
  for (std::size_t i = 0; i < uvs.size(); ++i) {
    if (gpu[i].face == cpu[i].face) continue;
    ++seam_flips;
    INFO(describe(i));
    REQUIRE(std::abs(cpu[i].dir_jac.z) <= 2.4e-7f);
  }
  std::cout << "  round trip: " << seam_flips << " seam face flips (|d.z| <= 2.4e-7) of "
            << uvs.size() << "\n";
  VPLKIT_CHECK_PARITY(compare_field_abs(gpu, cpu, [](const out_t& o) { return o.u; }, dir_bound, describe,
                                        "round trip u"));
  VPLKIT_CHECK_PARITY(compare_field_abs(gpu, cpu, [](const out_t& o) { return o.v; }, dir_bound, describe,
                                        "round trip v"));
}

namespace {

struct int2 {
  std::int32_t x, y;
};

void check_texel_from_uv(const std::vector<vec2<float>>& uvs, const std::vector<int>& Rs,
                         const std::string& what) {
  std::vector<float4> in;
  for (std::size_t i = 0; i < uvs.size(); ++i) in.push_back({uvs[i].x, uvs[i].y, float(Rs[i]), 0});
  const auto gpu = run_compute<int2>(per_item(R"(#include "vplkit/paraboloid/texel_grid.glsl")",
                                              {input(0, in, "vec4 q")},  // (u, v, R, -)
                                              "ivec2 result", "result[i] = vplkit_texel_from_uv(q[i].xy, int(q[i].z));"),
                                     uvs.size());
  series<std::int32_t> x, y;
  for (std::size_t i = 0; i < uvs.size(); ++i) {
    const ivec2 t = vplkit::texel_from_uv(uvs[i], Rs[i]);
    x.add(gpu[i].x, t.x);
    y.add(gpu[i].y, t.y);
  }
  auto describe = [&](std::size_t i) { return "uv = " + show2(uvs[i]) + " R = " + show(Rs[i]); };
  VPLKIT_CHECK_PARITY(compare_exact(x, describe, what + ": x"));
  VPLKIT_CHECK_PARITY(compare_exact(y, describe, what + ": y"));
}

const std::vector<int> grid_resolutions = {1, 2, 3, 4, 5, 7, 8, 10, 16, 31, 63, 64, 100,
                                           255, 256, 512, 1000, 3001, 4096, 4097, 16383, 16384};

}  // namespace

TEST_CASE("texel_from_uv: random uv (inside and outside the map), exact") {
  random_source rnd(505);
  std::vector<vec2<float>> uvs;
  std::vector<int> Rs;
  for (int i = 0; i < 100000; ++i) {
    uvs.push_back(vec2<float>(float(rnd.uniform(-1.25, 1.25)), float(rnd.uniform(-1.25, 1.25))));
    Rs.push_back(i % 2 == 0 ? rnd.integer(1, 64)
                            : grid_resolutions[std::size_t(rnd.integer(0, int(grid_resolutions.size()) - 1))]);
  }
  // far outside and infinite (the clamp runs before int(); NaN is not sent to the GPU)
  for (int R : {1, 7, 64, 16384})
    for (float u : {-1.0f, 1.0f, -flt_inf, flt_inf, -flt_max, flt_max, 1e30f, -1e30f, 0.0f, -0.0f}) {
      uvs.push_back(vec2<float>(u, -u));
      Rs.push_back(R);
    }
  check_texel_from_uv(uvs, Rs, "texel_from_uv (random)");
}

TEST_CASE("texel_from_uv: uv exactly on texel edges and one ulp either side, exact") {
  // Edge k of an R-texel axis is u = -1 + 2k/R, rounded to float (exact when R is a power of two).
  // Both sides then evaluate (u + 1) * 0.5 * R with the same correctly rounded + and *, so an edge
  // is assigned identically (to the texel above it when the rounded product reaches k; GLSL has no
  // freedom there: no division, and no a*b+c pattern an FMA could fuse). Exact agreement required.
  std::vector<vec2<float>> uvs;
  std::vector<int> Rs;
  for (int R : grid_resolutions) {
    const int step = R <= 1024 ? 1 : R / 1024;
    std::vector<int> ks;
    for (int k = 0; k < R; k += step) ks.push_back(k);
    ks.push_back(R);
    for (int k : ks) {
      const float e = float(-1.0 + 2.0 * double(k) / double(R));
      for (float u : {e, std::nextafter(e, -2.0f), std::nextafter(e, 2.0f)}) {
        uvs.push_back(vec2<float>(u, -u));
        Rs.push_back(R);
      }
    }
  }
  check_texel_from_uv(uvs, Rs, "texel_from_uv (edges)");
  std::cout << "  edges checked: " << uvs.size() << "\n";
}

namespace {

// Every texel-grid function for one (face, x, y, R).
struct texel_out {  // std430: vec2 (8-aligned) first
  float cu, cv;        // texel_center_uv
  float omega;         // texel_solid_angle
  std::int32_t valid;  // texel_is_valid
  std::int32_t index;  // texel_index
  std::int32_t face;   // texel_face(index)
  std::int32_t x, y;   // texel_coords(index)
  std::int32_t fx, fy; // texel_from_uv(texel_center_uv)
  std::int32_t count;  // texel_count(R)
  std::int32_t pad;
};


texel_out cpu_texel(int x, int y, int R, int face) {
  texel_out o{};
  const vec2<float> c = vplkit::texel_center_uv<float>(x, y, R);
  o.cu = c.x;
  o.cv = c.y;
  o.omega = vplkit::texel_solid_angle<float>(x, y, R);
  o.valid = vplkit::texel_is_valid(x, y, R) ? 1 : 0;
  const bool in_range = x >= 0 && y >= 0 && x < R && y < R;
  o.index = in_range ? vplkit::texel_index(face, x, y, R) : -1;
  o.face = in_range ? vplkit::texel_face(o.index, R) : -1;
  const ivec2 xy = in_range ? vplkit::texel_coords(o.index, R) : ivec2(-1);
  o.x = xy.x;
  o.y = xy.y;
  const ivec2 f = vplkit::texel_from_uv(c, R);
  o.fx = f.x;
  o.fy = f.y;
  o.count = vplkit::texel_count(R);
  return o;
}

void check_texels(const std::vector<int4>& q, const std::string& what) {
  const auto gpu = run_compute<texel_out>(per_item(R"(
#include "vplkit/paraboloid/texel_grid.glsl"
struct texel_out { vec2 c; float omega; int valid; int index; int face; ivec2 xy; ivec2 f;
                   int count; int pad; };
)",
                                                   {input(0, q, "ivec4 q")},  // (x, y, R, face)
                                                   "texel_out result", R"(
  int x = q[i].x, y = q[i].y, R = q[i].z, face = q[i].w;
  texel_out o;
  o.c = vplkit_texel_center_uv(x, y, R);
  o.omega = vplkit_texel_solid_angle(x, y, R);
  o.valid = vplkit_texel_is_valid(x, y, R) ? 1 : 0;
  bool in_range = x >= 0 && y >= 0 && x < R && y < R;
  o.index = in_range ? vplkit_texel_index(face, x, y, R) : -1;
  o.face = in_range ? vplkit_texel_face(o.index, R) : -1;
  o.xy = in_range ? vplkit_texel_coords(o.index, R) : ivec2(-1);
  o.f = vplkit_texel_from_uv(o.c, R);
  o.count = vplkit_texel_count(R);
  o.pad = 0;
  result[i] = o;)"),
                                          q.size());
  std::vector<texel_out> cpu;
  for (const auto& t : q) cpu.push_back(cpu_texel(t.x, t.y, t.z, t.w));
  auto describe = [&](std::size_t i) {
    return "x " + show(q[i].x) + " y " + show(q[i].y) + " R " + show(q[i].z) + " face " +
           show(q[i].w);
  };
  // Integers: exact. valid is integer arithmetic; index/face/coords are integer; texel_from_uv of
  // the centre depends on the centre's float bits (compared just below), which are far from edges.
  const std::pair<const char*, int (*)(const texel_out&)> integers[] = {
      {": texel_is_valid", [](const texel_out& o) { return o.valid; }},
      {": texel_index", [](const texel_out& o) { return o.index; }},
      {": texel_face", [](const texel_out& o) { return o.face; }},
      {": texel_coords (x * 65536 + y)", [](const texel_out& o) { return o.x * 65536 + o.y; }},
      {": texel_from_uv(centre) (x * 65536 + y)", [](const texel_out& o) { return o.fx * 65536 + o.fy; }},
      {": texel_count", [](const texel_out& o) { return o.count; }}};
  for (const auto& field : integers)
    VPLKIT_CHECK_PARITY(compare_field_exact(gpu, cpu, field.second, describe, what + field.first));
  // Centre: (x + 0.5) / R * 2 - 1, one division: a GPU may be 2.5 ulp off in the quotient; the
  // final - 1 can cancel (centres near u = 0 are small), so 4 ulps or 4 ulp of 1 (4.8e-7) abs.
  const auto centre_bound = within_ulps(4) | within_abs(4.8e-7);
  VPLKIT_CHECK_PARITY(compare_field_abs(gpu, cpu, [](const texel_out& o) { return o.cu; }, centre_bound, describe,
                                        what + ": texel_center_uv u"));
  VPLKIT_CHECK_PARITY(compare_field_abs(gpu, cpu, [](const texel_out& o) { return o.cv; }, centre_bound, describe,
                                        what + ": texel_center_uv v"));
  // Solid angle: the Jacobian at the centre (see the Jacobian bound: an FMA-contracted dot moves
  // q by an ulp, ~3.3 eps in the result) times (2/R)^2 (two more roundings). Measured rel 5.5e-7
  // (4.6 eps); bound rel 1.5e-6 (12.6 eps), which also covers a division at the GLSL limit.
  VPLKIT_CHECK_PARITY(compare_field_abs(gpu, cpu, [](const texel_out& o) { return o.omega; }, within_rel(1.5e-6),
                                        describe, what + ": texel_solid_angle"));
}

}  // namespace

TEST_CASE("texel grid: every texel of R = 1..64 and 512 (validity, indices, centre, solid angle)") {
  std::vector<int4> q;
  std::uint32_t k = 0;
  auto add_resolution = [&](int R) {
    for (int y = 0; y < R; ++y)
      for (int x = 0; x < R; ++x) q.push_back({x, y, R, std::int32_t((k++ * 2654435761u) >> 31)});
    // out of range: invalid, solid angle 0
    for (int t : {-1, R}) {
      q.push_back({t, 0, R, 0});
      q.push_back({0, t, R, 1});
    }
  };
  for (int R = 1; R <= 64; ++R) add_resolution(R);
  add_resolution(512);
  check_texels(q, "texel grid R = 1..64, 512");
  std::cout << "  texels checked: " << q.size() << "\n";
}

TEST_CASE("texel grid: texels next to the rim for R in the thousands, exact validity") {
  // For each column x, the last valid texel of the column (largest b = 2y + 1 - R with
  // a^2 + b^2 <= R^2, found in 64-bit integers) and its neighbours; these are the texels whose
  // centres lie within 1/R^2 of the rim, where a float r2 test fails.
  std::vector<int4> q;
  for (int R : {3001, 4096, 4097, 16383, 16384}) {
    const int stride = R > 5000 ? 3 : 1;
    for (int x = 0; x < R; x += stride) {
      const std::int64_t a = 2 * std::int64_t(x) + 1 - R;
      const std::int64_t rest = std::int64_t(R) * R - a * a;
      std::int64_t b = std::int64_t(std::sqrt(double(rest)));
      while (b * b > rest) --b;
      while ((b + 1) * (b + 1) <= rest) ++b;
      if (((b + R - 1) & 1) != 0) --b;  // b has the parity of R + 1
      const std::int64_t y = (b + R - 1) / 2;
      for (std::int64_t dy : {-1, 0, 1, 2}) {
        const std::int64_t yy = y + dy;
        if (yy >= 0 && yy < R) q.push_back({x, std::int32_t(yy), R, x & 1});
      }
    }
  }
  check_texels(q, "texel grid near the rim, R in the thousands");
  std::cout << "  near-rim texels checked: " << q.size() << "\n";
}

namespace {

struct frame_out {
  float4 ax, ay, az;
};

}  // namespace

TEST_CASE("light_frame: construction from random and special front axes") {
  random_source rnd(606);
  std::vector<vec3<float>> axes;
  for (int i = 0; i < 20000; ++i)
    axes.push_back(rnd.sphere_direction() * float(std::pow(10.0, rnd.uniform(-30, 30))));
  for (vec3<float> a : {vec3<float>(1, 0, 0), vec3<float>(-1, 0, 0), vec3<float>(0, 1, 0),
                        vec3<float>(0, -1, 0), vec3<float>(0, 0, 1), vec3<float>(0, 0, -1),
                        vec3<float>(1, 0, -0.0f), vec3<float>(0, 1, -0.0f), vec3<float>(flt_min, 0, -1),
                        vec3<float>(1e-4f, -1e-4f, -1), vec3<float>(0, 0, -1e30f),
                        vec3<float>(0, 0, -4 * flt_min), vec3<float>(3, 4, 0)})
    axes.push_back(a);
  std::vector<float4> in;
  for (const auto& a : axes) in.push_back(f4(a));
  const auto gpu = run_compute<frame_out>(per_item(R"(
#include "vplkit/paraboloid/light_frame.glsl"
struct frame_out { vec4 ax; vec4 ay; vec4 az; };
)",
                                                   {input(0, in, "vec4 axis")}, "frame_out result", R"(
  vplkit_light_frame f = vplkit_make_light_frame(vec3(1.0, 2.0, 3.0), axis[i].xyz);
  result[i] = frame_out(vec4(f.axis_x, f.position.x), vec4(f.axis_y, f.position.y),
                        vec4(f.axis_z, f.position.z));)"),
                                          axes.size());
  std::vector<frame_out> cpu;
  for (const auto& a : axes) {
    const vplkit::light_frame<float> f(vec3<float>(1, 2, 3), a);
    cpu.push_back({f4(f.axis_x, f.position.x), f4(f.axis_y, f.position.y), f4(f.axis_z, f.position.z)});
  }
  auto describe = [&](std::size_t i) { return "front axis = " + show3(axes[i]); };
  // Components of unit vectors; 1 + s x^2 a and s + y^2 a cancel toward 0 when the axis is near
  // +-x / +-y, so absolute error is what is meaningful there. The normalised axis differs by 1-2
  // ulp (FMA in dot), x^2 a doubles that, and the sum may be fused: measured 3.0e-7 (2.5 ulp of
  // 1). Bound 8 ulps or 1e-6 abs (8.4 ulp of 1), room for sqrt/division at the GLSL limits.
  const auto bound = within_ulps(8) | within_abs(1e-6);
  const char* names[3][4] = {{"axis_x.x", "axis_x.y", "axis_x.z", "position.x"},
                             {"axis_y.x", "axis_y.y", "axis_y.z", "position.y"},
                             {"axis_z.x", "axis_z.y", "axis_z.z", "position.z"}};
  for (int a = 0; a < 3; ++a) {
    for (int c = 0; c < 4; ++c) {
      auto pick = [a, c](const frame_out& o) { return (a == 0 ? o.ax : a == 1 ? o.ay : o.az)[c]; };
      VPLKIT_CHECK_PARITY(
          compare_field_abs(gpu, cpu, pick, bound, describe, std::string("make_light_frame ") + names[a][c]));
    }
  }
}

TEST_CASE("light_frame: to_light, to_world, to_light_point, to_world_point") {
  // The frames come from the CPU (uploaded bit for bit), so this isolates the transforms: dot
  // products and sums of products, with cancellation when the result is small. Inputs |dir| <= 1
  // and |p - c| <= ~20: absolute bounds of a few ulp of the magnitude involved.
  random_source rnd(707);
  const int frames = 64;
  std::vector<vplkit::light_frame<float>> fs;
  for (int i = 0; i < frames; ++i) {
    const vec3<float> c(float(rnd.uniform(-10, 10)), float(rnd.uniform(-10, 10)),
                        float(rnd.uniform(-10, 10)));
    fs.emplace_back(c, i == 0 ? vec3<float>(0, 0, -1) : i == 1 ? vec3<float>(0, 0, 1) : rnd.sphere_direction());
  }
  const int n = 100000;
  std::vector<float4> in;   // per case: frame (4 vec4), dir, point
  std::vector<vec3<float>> dirs, points;
  std::vector<int> which;
  for (int i = 0; i < n; ++i) {
    const int f = i % frames;
    which.push_back(f);
    dirs.push_back(rnd.sphere_direction() * float(rnd.uniform(0.1, 1.0)));
    points.push_back(fs[std::size_t(f)].position +
                     vec3<float>(float(rnd.uniform(-10, 10)), float(rnd.uniform(-10, 10)),
                                 float(rnd.uniform(-10, 10))));
  }
  for (const auto& f : fs) {
    in.push_back(f4(f.position));
    in.push_back(f4(f.axis_x));
    in.push_back(f4(f.axis_y));
    in.push_back(f4(f.axis_z));
  }
  std::vector<float4> cases;
  for (int i = 0; i < n; ++i) {
    cases.push_back(f4(dirs[std::size_t(i)], float(which[std::size_t(i)])));
    cases.push_back(f4(points[std::size_t(i)]));
  }
  // Four outputs, one per transform.
  kernel_call call = per_item(R"(#include "vplkit/paraboloid/light_frame.glsl")",
                              {input(0, in, "vec4 fr"), input(2, cases, "vec4 cs")}, "vec4 to_light", R"(
  int k = int(cs[2u * i].w);
  vplkit_light_frame f = vplkit_light_frame(fr[4 * k].xyz, fr[4 * k + 1].xyz, fr[4 * k + 2].xyz,
                                            fr[4 * k + 3].xyz);
  vec3 d = cs[2u * i].xyz;
  vec3 p = cs[2u * i + 1u].xyz;
  to_light[i] = vec4(vplkit_light_frame_to_light(f, d), 0.0);
  to_world[i] = vec4(vplkit_light_frame_to_world(f, d), 0.0);
  to_light_point[i] = vec4(vplkit_light_frame_to_light_point(f, p), 0.0);
  to_world_point[i] = vec4(vplkit_light_frame_to_world_point(f, p - f.position), 0.0);)");
  call.more_outputs = {output_of<float4>(3, "vec4 to_world"), output_of<float4>(4, "vec4 to_light_point"),
                       output_of<float4>(5, "vec4 to_world_point")};
  const kernel_outputs out = run_kernel(call, std::size_t(n), sizeof(float4));
  const std::vector<float4> gpu[4] = {out.get<float4>(1), out.get<float4>(3), out.get<float4>(4), out.get<float4>(5)};
  std::vector<float4> cpu[4];
  for (int i = 0; i < n; ++i) {
    const auto& f = fs[std::size_t(which[std::size_t(i)])];
    const vec3<float> d = dirs[std::size_t(i)], p = points[std::size_t(i)];
    cpu[0].push_back(f4(f.to_light(d)));
    cpu[1].push_back(f4(f.to_world(d)));
    cpu[2].push_back(f4(f.to_light_point(p)));
    cpu[3].push_back(f4(f.to_world_point(p - f.position)));
  }
  auto describe = [&](std::size_t i) {
    return "frame " + show(which[i]) + " dir " + show3(dirs[i]) + " point " + show3(points[i]);
  };
  // Directions (|d| <= 1): three products and two sums; llvmpipe fuses some into FMAs, so the
  // difference is an ulp or two of the largest term (measured 1.2e-7 = 1 ulp of 1): bound 8 ulps
  // or 4.8e-7 abs (4 ulp of 1). to_world (a sum of vector products) came out bit-identical.
  // Points (|p - c| components <= 10, products up to ~17): the same in ulps of 16 (1.9e-6, which
  // is also the measured worst): bound 8 ulps or 7.6e-6 abs (4 ulp of 16).
  const auto dir_bound = within_ulps(8) | within_abs(4.8e-7);
  const auto point_bound = within_ulps(8) | within_abs(7.6e-6);
  const char* names[4] = {"to_light ", "to_world ", "to_light_point ", "to_world_point "};
  for (int c = 0; c < 3; ++c) {
    for (int t = 0; t < 4; ++t) {
      VPLKIT_CHECK_PARITY(compare_field_abs(gpu[t], cpu[t], [c](const float4& v) { return v[c]; },
                                            t < 2 ? dir_bound : point_bound, describe, names[t] + std::string(1, "xyz"[c])));
    }
  }
}

TEST_CASE("paraboloid constants: the GLSL values are the C++ values, bit for bit") {
  const float scale = 1.0f - 2.0f * flt_eps;  // the factor inside paraboloid_clamp_to_disk<float>
  VPLKIT_CHECK_PARITY(compare_constants(
      R"(#include "vplkit/paraboloid/texel_grid.glsl")",
      {{"floatBitsToUint(vplkit_paraboloid_clamp_scale)", bits_of(scale)},
       {"uint(vplkit_paraboloid_front)", std::uint32_t(vplkit::paraboloid_front)},
       {"uint(vplkit_paraboloid_back)", std::uint32_t(vplkit::paraboloid_back)},
       {"uint(vplkit_paraboloid_max_resolution)", std::uint32_t(vplkit::paraboloid_max_resolution)}},
      "clamp scale bits, face constants, max resolution"));
}

TEST_CASE("texel_owner_from_uv and texel_patch_block: the rim band (exact off texel edges)") {
  // The owner of a uv inside the disk (texel_grid.hpp, "The rim band"): the texel holding uv when
  // valid, else the texel holding uv (1 - 2/R). The GPU's 2.0 / float(R) may round differently
  // (GLSL division is not correctly rounded), so the pulled uv may differ by an ulp: owners may
  // differ only where uv or the pulled uv lies within 1e-6 of a texel edge. The block of a texel
  // is integer arithmetic: exact.
  random_source rnd(909);
  std::vector<float4> in;
  std::vector<vec2<float>> uvs;
  std::vector<int> Rs;
  for (int R : grid_resolutions)
    for (int k = 0; k < 3000; ++k) {
      const double phi = rnd.uniform(0, 2 * pi), r = 1.0 - rnd.uniform(0, 3) / R;
      const vec2<float> uv = vplkit::paraboloid_clamp_to_disk(vec2<float>(float(r * std::cos(phi)), float(r * std::sin(phi))));
      uvs.push_back(uv);
      Rs.push_back(R);
      in.push_back({uv.x, uv.y, float(R), 0});
    }
  const auto gpu = run_compute<int2>(per_item(R"(#include "vplkit/paraboloid/texel_grid.glsl")",
                                              {input(0, in, "vec4 q")},  // (u, v, R, -)
                                              "ivec2 result",
                                              "result[i] = vplkit_texel_owner_from_uv(q[i].xy, int(q[i].z));"),
                                     uvs.size());
  std::size_t band = 0, differ = 0, unexplained = 0;
  std::vector<int4> owners;
  for (std::size_t i = 0; i < uvs.size(); ++i) {
    const int R = Rs[i];
    const ivec2 c = vplkit::texel_owner_from_uv(uvs[i], R);
    owners.push_back({c.x, c.y, R, 0});
    if (c != vplkit::texel_from_uv(uvs[i], R)) ++band;
    if (gpu[i].x == c.x && gpu[i].y == c.y) continue;
    ++differ;
    bool near_edge = false;
    for (const vec2<double> p : {vec2<double>(uvs[i]), vec2<double>(uvs[i]) * (1.0 - 2.0 / R)})
      for (int k = 0; k < 2; ++k) {
        const double t = (p[k] + 1.0) * 0.5 * R;
        near_edge = near_edge || std::abs(t - std::round(t)) * (2.0 / R) < 1e-6;
      }
    if (!near_edge) {
      ++unexplained;
      UNSCOPED_INFO("owner differs off an edge: uv " << show2(uvs[i]) << " R " << R << " cpu (" << c.x << ", " << c.y
                                                     << ") gpu (" << gpu[i].x << ", " << gpu[i].y << ")");
    }
  }
  const auto blocks = run_compute<int4>(per_item(R"(#include "vplkit/paraboloid/texel_grid.glsl")",
                                                 {input(0, owners, "ivec4 q")},  // (x, y, R, -)
                                                 "ivec4 result", R"(
  vplkit_texel_block b = vplkit_texel_patch_block(q[i].x, q[i].y, q[i].z);
  result[i] = ivec4(b.x0, b.y0, b.nx, b.ny);)"),
                                        owners.size());
  std::size_t block_differ = 0, rim = 0;
  for (std::size_t i = 0; i < owners.size(); ++i) {
    const vplkit::texel_block b = vplkit::texel_patch_block(owners[i].x, owners[i].y, owners[i].z);
    rim += b.nx * b.ny != 1;
    if (blocks[i].x != b.x0 || blocks[i].y != b.y0 || blocks[i].z != b.nx || blocks[i].w != b.ny) ++block_differ;
  }
  std::cout << "  texel_owner_from_uv: " << uvs.size() << " uv within 3 texels of the rim, " << band
            << " in the band; owners differing " << differ << " (unexplained " << unexplained
            << "); patch blocks of the owners: " << rim << " rim texels, differing " << block_differ << "\n";
  CHECK(band > 1000);
  CHECK(unexplained == 0);
  CHECK(differ <= uvs.size() / 1000);
  CHECK(block_differ == 0);
}

// paraboloid_clamp_to_disk of a uv far outside the disk: the GPU scales as the C++ does. Bound, per
// component: the GPU's normalisation (inversesqrt, 2 ulp, and its product: spec::normalize_ulps)
// and the clamp factor's product (0.5), a contracted dot product (spec::contraction_ulps), and the
// C++ side's own 1 / sqrt and two products (1.5); the unscaled path below the switch (inversesqrt
// of r2 and two products, 3 ulps) stays inside it.
constexpr double clamp_far_ulps = vplkit_test::spec::normalize_ulps + vplkit_test::spec::add_mul_ulps +
                                  vplkit_test::spec::contraction_ulps + 1.5;
static_assert(clamp_far_ulps == 5.0, "the bound the comment derives");

TEST_CASE("paraboloid_clamp_to_disk: uv far outside the disk (|uv| up to FLT_MAX, r2 overflowing), on the rim") {
  random_source rnd(505);
  std::vector<vec2<float>> uvs;
  for (int e = 0; e <= 127; ++e) {  // |uv| ~ 2^e in random directions: r2 overflows from e = 64 on
    for (int k = 0; k < 40; ++k) {
      const double phi = rnd.uniform(0.0, 2.0 * pi);
      const double m = std::ldexp(rnd.uniform(1.0, 1.99), e);
      uvs.push_back(vec2<float>(float(m * std::cos(phi)), float(m * std::sin(phi))));
    }
  }
  for (const vec2<float> uv : {vec2<float>(flt_max, 0), vec2<float>(0, -flt_max), vec2<float>(flt_max, flt_max),
                               vec2<float>(-flt_max, 1), vec2<float>(0x1p63f, 0x1p63f), vec2<float>(0x1p64f, 0),
                               vec2<float>(std::nextafter(0x1p63f, flt_inf), -0x1p63f), vec2<float>(3e19f, -4e19f)})
    uvs.push_back(uv);
  std::vector<float4> in;
  for (const auto& uv : uvs) in.push_back({uv.x, uv.y, 0, 0});
  const auto gpu = run_compute<float4>(per_item(R"(#include "vplkit/paraboloid/paraboloid.glsl")",
                                                {input(0, in, "vec4 q")}, "vec4 result", R"(
  result[i] = vec4(vplkit_paraboloid_clamp_to_disk(q[i].xy), 0.0, 0.0);)"),
                                       uvs.size());
  std::vector<float4> cpu;
  for (const auto& uv : uvs) {
    const vec2<float> r = vplkit::paraboloid_clamp_to_disk(uv);
    cpu.push_back({r.x, r.y, 0, 0});
  }
  auto describe = [&](std::size_t i) { return "uv = " + show2(uvs[i]); };
  for (int c = 0; c < 2; ++c)
    VPLKIT_CHECK_PARITY(compare_field_abs(gpu, cpu, [c](const float4& v) { return v[c]; },
                                          within_ulps(clamp_far_ulps), describe,
                                          std::string("clamp_to_disk far outside: ") + (c == 0 ? "u" : "v")));
  // The GPU model: inversesqrt anywhere within the table (no division is involved).
  std::uint64_t seed = 7;
  for (const auto deviation : vplkit_test::gpu_model_deviations) {
    const vplkit_test::gpu_model_scope model(deviation, seed++);
    using W = vplkit_test::gpu_float;
    std::vector<float4> mv;
    for (const auto& uv : uvs) {
      const vec2<W> r = vplkit::paraboloid_clamp_to_disk(vec2<W>(W(uv.x), W(uv.y)));
      mv.push_back({float(r.x), float(r.y), 0, 0});
    }
    for (int c = 0; c < 2; ++c)
      VPLKIT_CHECK_PARITY(compare_field_abs(mv, cpu, [c](const float4& v) { return v[c]; },
                                            within_ulps(clamp_far_ulps), describe,
                                            "clamp_to_disk far outside, GPU model (" +
                                                std::string(vplkit_test::to_string(deviation)) + ")"));
  }
  // On the rim on both sides (the centre, 0, is what an overflowing r2 gives unscaled).
  std::size_t off_rim = 0;
  for (std::size_t i = 0; i < uvs.size(); ++i) {
    for (const float4& r : {gpu[i], cpu[i]}) {
      const double r2 = double(r.x) * r.x + double(r.y) * r.y;
      if (!(r2 <= 1.0 + 2.0 * flt_eps) || !(r2 >= 1.0 - 16.0 * flt_eps)) {
        ++off_rim;
        UNSCOPED_INFO("off the rim: " << describe(i) << " -> (" << show(r.x) << ", " << show(r.y) << ")");
      }
    }
  }
  std::cout << "  clamp_to_disk far outside: " << uvs.size() << " uv, off the rim (GPU or C++): " << off_rim << "\n";
  CHECK(off_rim == 0);
}
