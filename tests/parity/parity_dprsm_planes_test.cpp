// SPDX-License-Identifier: MIT
// CPU/GPU parity of the DPRSM's plane records (glsl/vplkit/vpl/dprsm_plane.glsl, dprsm_planes.comp
// against include/vplkit/vpl/dprsm_plane.hpp, dprsm_planes.hpp), and the patch-sampled VPLs read
// through them (VPLKIT_DPRSM_PLANE_ACCESSOR) against the same kernel without them, on the synthetic
// room of parity_estimators_support.hpp (R = 32) with hard-case texels written in: zero albedo,
// zero / tiny / denormal / huge / NaN / infinite normals, facing away, the light on a texel's plane.
//
// What must be exact: a record's class (height > 0: can hide; < 0: saw nothing, keeps its plane;
// 0: no plane), except where |h| is within its forward error bound (none here: counted, printed),
// and every output of the patch sampler (position, flux, solid angle, distance, cos(alpha), uv,
// accepted, at the centre) bit for bit between the kernel reading the builder's records and the
// kernel computing them: both evaluate vplkit_dprsm_plane_of, whose h is `precise`. Bounded: the
// record's unit normal (the pack's unit_or_zero against the C++: fe_unit_vector, both sides) and
// height (fe_dot of that normal with c - y, both sides), parity_forward_error.hpp.
#include "parity_estimators_support.hpp"
#include "parity_forward_error.hpp"

#include <gl_kernels.hpp>

#include <vplkit/paraboloid/texel_grid.hpp>
#include <vplkit/vpl/dprsm_patch.hpp>
#include <vplkit/vpl/dprsm_planes.hpp>
#include <vplkit/vpl/dprsm_planes_params.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

namespace {

using namespace vplkit::parity::est;
using vplkit::parity::compare_exact;
using vplkit::parity::input;
using vplkit_test::f4;
using vplkit_test::float4;

const scene_fixture& fixture() {
  static const scene_fixture* f = new scene_fixture(32, 32, 24, 24);
  return *f;
}

// The fixture's DPRSM with a hard case written into every fifth texel that saw a surface.
struct hard_dprsm {
  std::vector<v3f> position, normal, albedo;
  std::vector<std::string> kind;  // per texel: "" or the hard case
  hard_dprsm() {
    const scene_fixture& f = fixture();
    position = f.dprsm.position;
    normal = f.dprsm.normal;
    albedo = f.dprsm.albedo;
    kind.assign(position.size(), "");
    const v3f c = f.dprsm.light.position;
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    int k = 0;
    for (std::size_t t = 0; t < position.size(); ++t) {
      if (albedo[t] == v3f(0) || t % 5 != 0) continue;
      switch (k++ % 9) {
        case 0: albedo[t] = v3f(0), kind[t] = "zero albedo"; break;
        case 1: normal[t] = v3f(0), kind[t] = "zero normal"; break;
        case 2: normal[t] *= 1e-30f, kind[t] = "tiny normal"; break;
        case 3: normal[t] = v3f(1e-40f, 0, 0), kind[t] = "denormal normal"; break;
        case 4: normal[t] *= 1e30f, kind[t] = "huge normal"; break;
        case 5: normal[t] = -normal[t], kind[t] = "facing away"; break;
        case 6: position[t].z = c.z, normal[t] = v3f(0, 0, 1), kind[t] = "light on its plane"; break;
        case 7: normal[t] = v3f(nan, 0, 1), kind[t] = "NaN normal"; break;
        case 8: normal[t] = v3f(inf, 1, 0), kind[t] = "infinite normal"; break;
      }
    }
  }
  bool valid(int t) const {
    const int R = fixture().R;
    const vplkit::ivec2 xy = vplkit::texel_coords(t, R);
    return vplkit::texel_is_valid(xy.x, xy.y, R);
  }
  vplkit::dprsm_plane<float> record(int t) const {
    return vplkit::dprsm_plane_of(fixture().dprsm.light.position, valid(t), position[std::size_t(t)],
                                  normal[std::size_t(t)], albedo[std::size_t(t)]);
  }
};

const hard_dprsm& hard() {
  static const hard_dprsm* h = new hard_dprsm();
  return *h;
}

// dprsm_planes.comp over the hard DPRSM: 2 R^2 vec4 (normal, height).
std::vector<float4> run_planes_kernel() {
  vplkit::parity::context();  // the harness's GL context, current from here on
  const scene_fixture& f = fixture();
  const hard_dprsm& h = hard();
  const int n = vplkit::texel_count(f.R);
  vplkit::gpu::dprsm_planes_params p{};
  p.light = vplkit::gpu::make_light_params(f.dprsm.light);
  p.resolution = f.R;
  const auto dp = vplkit::gl::buffer::from_vector(vplkit_test::surfels(h.position, h.normal, h.albedo));
  const auto out = vplkit::gl::buffer::filled(std::size_t(n) * 16, 0xFF);
  const auto ub = vplkit_test::uniform_buffer(p);
  vplkit_test::bind({vplkit_test::storage_at(VPLKIT_DPRSM_PLANES_BINDING_DPRSM, dp),
                     vplkit_test::storage_at(VPLKIT_DPRSM_PLANES_BINDING_PLANES, out),
                     vplkit_test::uniform_at(VPLKIT_DPRSM_PLANES_BINDING_PARAMS, ub)});
  vplkit::gl::dispatch_linear(vplkit_test::pack_kernel("vplkit/vpl/dprsm_planes.comp"),
                              vplkit::gl::groups_for(std::size_t(n), VPLKIT_DPRSM_PLANES_LOCAL_SIZE));
  return out.read<float4>();
}

int record_class(float height) { return height > 0 ? 1 : height < 0 ? -1 : 0; }

}  // namespace

TEST_CASE("dprsm_planes.comp: every texel's record against dprsm_plane_of, hard cases included") {
  const scene_fixture& f = fixture();
  const hard_dprsm& h = hard();
  const std::vector<float4> gpu = run_planes_kernel();
  const int n = vplkit::texel_count(f.R);
  REQUIRE(gpu.size() == std::size_t(n));
  const v3f c = f.dprsm.light.position;
  std::vector<std::int32_t> g_class, c_class;
  std::vector<float> g_val, c_val;
  std::vector<double> bound;
  std::vector<int> which;
  std::size_t ties = 0, flips = 0, counts[3] = {0, 0, 0};
  for (int t = 0; t < n; ++t) {
    const vplkit::dprsm_plane<float> r = h.record(t);
    const float4 g = gpu[std::size_t(t)];
    // The chain's bound on both sides: n_u = unit(n) (fe_unit_vector), h = n_u . (c - y).
    const vplkit_test::fe3 nu = vplkit_test::fe_unit_vector(vplkit_test::fe3_of(h.normal[std::size_t(t)]));
    const v3f y = h.position[std::size_t(t)];
    const vplkit_test::fe3 d{{vplkit_test::fe(c.x) - vplkit_test::fe(y.x), vplkit_test::fe(c.y) - vplkit_test::fe(y.y),
                              vplkit_test::fe(c.z) - vplkit_test::fe(y.z)}};
    const vplkit_test::fe hv = vplkit_test::fe_dot(nu, d);
    const bool tie = h.valid(t) && std::abs(hv.v) <= 2 * hv.e && hv.v != 0;
    ties += tie ? 1 : 0;
    INFO("texel " << t << " (" << h.kind[std::size_t(t)] << ")");
    if (record_class(g.w) != record_class(r.height)) {
      ++flips;
      CHECK(tie);
      continue;
    }
    ++counts[record_class(r.height) + 1];
    g_class.push_back(record_class(g.w));
    c_class.push_back(record_class(r.height));
    if (r.height == 0) {  // no plane: all four zero on both sides
      for (float v : {g.x, g.y, g.z, g.w}) CHECK(v == 0.0f);
      continue;
    }
    const float gv[4] = {g.x, g.y, g.z, std::abs(g.w)};
    const float cv[4] = {r.normal.x, r.normal.y, r.normal.z, std::abs(r.height)};
    for (int k = 0; k < 4; ++k) {
      g_val.push_back(gv[k]);
      c_val.push_back(cv[k]);
      bound.push_back(2 * (k < 3 ? nu[k].e : hv.e));
      which.push_back(4 * t + k);
    }
  }
  std::cout << "  " << n << " records: " << counts[2] << " can hide, " << counts[0] << " saw nothing, " << counts[1]
            << " no plane; " << ties << " within a tie of h = 0, " << flips << " classes differ\n";
  CHECK(counts[2] > 500);
  CHECK(counts[0] > 10);
  CHECK(counts[1] > 100);
  VPLKIT_CHECK_PARITY(compare_exact(g_class, c_class, {}, "dprsm_planes.comp: record class"));
  auto describe = [&](std::size_t k) {
    const int t = which[k] / 4;
    return "texel " + std::to_string(t) + " component " + std::to_string(which[k] % 4) + " (" +
           hard().kind[std::size_t(t)] + ")";
  };
  VPLKIT_CHECK_PARITY(vplkit_test::compare_within_bounds({g_val, c_val}, bound, describe,
                                                         "dprsm_planes.comp: unit normal and |height|"));
  // Every hard case's class as the C++ says (named, so a wrong sentinel reads plainly).
  for (int t = 0; t < n; ++t) {
    const std::string& kind = h.kind[std::size_t(t)];
    if (kind.empty()) continue;
    INFO("texel " << t << " " << kind);
    const float w = gpu[std::size_t(t)].w;
    if (kind == "zero albedo") CHECK(w < 0);
    else if (kind == "tiny normal" || kind == "huge normal") CHECK(w > 0);
    else if (kind != "facing away") CHECK(w == 0);  // facing away: its plane may face the light by its tilt
  }
}

namespace {

struct patch_query {
  std::int32_t texel;
  float xi_x, xi_y, tol;
};
struct patch_out {
  float4 position;  // w: accepted (1) or not (0)
  float4 flux;      // w: solid angle
  float4 extra;     // distance, cos(alpha), uv.x, uv.y
  float4 flags;     // x: at the centre
};

const char* const k_patch = R"(
#include "vplkit/vpl/dprsm_patch.glsl"
#ifdef VPLKIT_DPRSM_PLANE_ACCESSOR
layout(std430, binding = 10) readonly buffer Planes { vec4 planes[]; };
vec4 vplkit_load_dprsm_plane(int texel) { return planes[texel]; }
#endif
struct patch_query { int texel; float xi_x; float xi_y; float tol; };
layout(std430, binding = 9) readonly buffer Queries { patch_query queries[]; };
struct patch_out { vec4 position; vec4 flux; vec4 extra; vec4 flags; };
layout(std430, binding = 1) writeonly buffer Out { patch_out result[]; };
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= VPLKIT_PARITY_COUNT) return;
  patch_query q = queries[i];
  vplkit_dprsm_patch_sample s = vplkit_dprsm_patch_vpl(load_view(), q.texel, vec2(q.xi_x, q.xi_y), q.tol);
  result[i] = patch_out(vec4(s.point.position, vplkit_vpl_has_flux(s.point) ? 1.0 : 0.0), vec4(s.point.flux, s.solid_angle),
                        vec4(s.distance, s.cos_alpha, s.uv), vec4(s.at_centre ? 1.0 : 0.0, 0.0, 0.0, 0.0));
}
)";

std::vector<patch_out> run_patch(const std::vector<patch_query>& qs, const std::vector<float4>* planes) {
  const scene_fixture& f = fixture();
  const hard_dprsm& h = hard();
  std::vector<float4> pos, nor, alb;
  for (std::size_t i = 0; i < h.position.size(); ++i) {
    pos.push_back(f4(h.position[i]));
    nor.push_back(f4(h.normal[i]));
    alb.push_back(f4(h.albedo[i]));
  }
  std::vector<std::uint32_t> words = f.grid.words();
  if (words.empty()) words.push_back(0);
  vplkit::parity::kernel_call call;
  call.name = planes ? "dprsm_patch_vpl_with_planes.comp" : "dprsm_patch_vpl_without_planes.comp";
  call.source = std::string(scene_prelude) + k_patch;
  call.defines = planes ? "#define VPLKIT_DPRSM_PLANE_ACCESSOR\n" : "";
  call.inputs = {input(2, pos), input(3, nor), input(4, alb), input(6, words),
                 input(8, vplkit_test::surfels(f.gbuffer.position, f.gbuffer.normal, f.gbuffer.albedo)),
                 input(5, std::vector<scene_params>{f.params()}), input(7, pack_points({})), input(9, qs)};
  if (planes) call.inputs.push_back(input(10, *planes));
  call.output_binding = 1;
  return vplkit::parity::run_compute<patch_out>(call, qs.size());
}

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

TEST_CASE("dprsm_patch_vpl through the records (VPLKIT_DPRSM_PLANE_ACCESSOR): the same bits as without them") {
  const scene_fixture& f = fixture();
  const hard_dprsm& h = hard();
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<patch_query> qs;
  const float one_below = std::nextafter(1.0f, 0.0f);
  const float xis[][2] = {{0.5f, 0.5f}, {0.0f, 0.0f}, {one_below, one_below}, {0.0f, one_below},
                          {0.137f, 0.862f}, {0.731f, 0.211f}, {0.999f, 0.003f}, {0.25f, 0.75f}};
  for (int t = 0; t < vplkit::texel_count(f.R); ++t) {
    if (!h.valid(t)) continue;
    for (const auto& xi : xis)
      for (float tol : {inf, 0.05f}) qs.push_back({t, xi[0], xi[1], tol});
  }
  const std::vector<float4> planes = run_planes_kernel();
  const std::vector<patch_out> with = run_patch(qs, &planes), without = run_patch(qs, nullptr);
  std::size_t differing = 0, accepted = 0, at_centre = 0, near_hard = 0;
  std::vector<std::uint32_t> g_dec, c_dec;
  for (std::size_t i = 0; i < qs.size(); ++i) {
    const float* a = &with[i].position.x;
    const float* b = &without[i].position.x;
    bool same = true;
    for (int k = 0; k < 16; ++k) same = same && same_bits(a[k], b[k]);
    differing += same ? 0 : 1;
    g_dec.push_back((with[i].position.w == 1.0f ? 1u : 0u) | (with[i].flags.x == 1.0f ? 2u : 0u));
    c_dec.push_back((without[i].position.w == 1.0f ? 1u : 0u) | (without[i].flags.x == 1.0f ? 2u : 0u));
    accepted += with[i].position.w == 1.0f ? 1 : 0;
    at_centre += with[i].flags.x == 1.0f ? 1 : 0;
    const vplkit::ivec2 xy = vplkit::texel_coords(qs[i].texel, f.R);
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int x = xy.x + dx, y = xy.y + dy;
        if (x < 0 || y < 0 || x >= f.R || y >= f.R) continue;
        if (!h.kind[std::size_t(vplkit::texel_index(vplkit::texel_face(qs[i].texel, f.R), x, y, f.R))].empty()) {
          ++near_hard;
          dy = 2;
          break;
        }
      }
  }
  std::cout << "  " << qs.size() << " queries, " << accepted << " accepted, " << at_centre << " at the centre, "
            << near_hard << " next to a hard-case texel, " << differing << " differ in some bit\n";
  CHECK(accepted > qs.size() / 4);
  CHECK(at_centre > 20);
  CHECK(near_hard > qs.size() / 4);
  VPLKIT_CHECK_PARITY(compare_exact(g_dec, c_dec, {}, "dprsm_patch_vpl with / without records: accepted, at centre"));
  CHECK(differing == 0);
}
