// SPDX-License-Identifier: MIT
// CPU/GPU parity of glsl/vplkit/estimators/ris_candidate_pool.glsl (with ris_pool_entry.glsl and
// the record of ris_pool_params.h) against include/vplkit/estimators/ris_candidate_pool.hpp,
// T = float, on the synthetic room of parity_ris_mis_support.hpp (DPRSM R = 32, 32^3 voxels, a
// 24 x 24 G-buffer, voxel visibility and the voxel tracer on both sides), point and patch VPLs:
// the record's layout; pool entries drawn on both sides (ris_pool_draw_entry); h of an entry at the
// gather points (ris_pool_unshadowed); reservoirs of pooled candidates and their shade
// (ris_mis_resample_pooled); the whole estimate_ris_mis_pooled per gather point with its range
// form. The pool the last three read is the C++'s, uploaded as records, so that they see the same
// entries: the draw test covers how the GPU makes them. Hard cases: a pool of size 0 and of one
// entry, a pool of empty entries (pmf 0, with and without a texel), at-centre entries with n1 > 0
// (h = 0) and n1 = 0, n_candidates <= 0, n2 = 0, negative counts, draws from a distribution that is
// empty (pmf 0 and denormal) or points outside the view, background and NaN gather points.
//
// What must be exact: the random-number streams (the counter after every call), the entries'
// texels, jitters and pmfs, the confidences, and, where no decision lies at a tie, the kept samples,
// their visibility and the gathering rays' texels. The decisions that may flip on a GPU (and under
// the [fma] reference): a patch point's hidden test or acceptance (an entry's at_centre or
// emptiness), a cosine at 0, a reservoir's u S < w where a weight carries the GPU's rounding
// (checked to be a tie: its margin within the weights' bound), a voxel march or a gathering ray at a
// tie; the estimate test compares a fingerprint of every decision of a gather point's steps, as
// parity_estimators_ris_mis_test does, and excludes, counts and bounds the points where it differs.
// Values are compared within per-item forward error bounds (parity_vpl_error_bound.hpp). The
// kernels are few and each compiles once per process: on llvmpipe the compile, not the dispatch,
// sets the test's time.
#include "parity_ris_mis_support.hpp"
#include "parity_vpl_error_bound.hpp"

#include <gpu_precision.hpp>

#include <vplkit/builders/flux_weights.hpp>
#include <vplkit/distribution/weighted_reservoir.hpp>
#include <vplkit/estimators/ris_candidate_pool.hpp>
#include <vplkit/estimators/ris_mis_estimator.hpp>
#include <vplkit/estimators/ris_pool_params.h>
#include <vplkit/visibility/visibility_callables.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iostream>
#include <iterator>
#include <string>
#include <vector>

// Distribution 0 of parity_ris_mis_support.hpp: the flux weights (a real search over 2048 texels).
std::vector<float> vplkit::parity::rismis::source_weights() { return vplkit::build_flux_weights(fixture().view()); }

namespace {

using namespace vplkit::parity::est;
using namespace vplkit::parity::rismis;
using vplkit::parity::compare_exact;
using vplkit::parity::compare_floats;
using vplkit::parity::input;
using vplkit::parity::within_ulps;
using vplkit_test::float4;
using entry = vplkit::ris_pool_entry<float>;
using record = vplkit::gpu::ris_pool_record;

constexpr std::uint32_t pool_seed = 0xB1000007u;
// Pools of at most pool_stride entries in one buffer, pool p at [p stride, (p + 1) stride): the
// GLSL accessor below maps (pool, index) the same way.
constexpr std::uint32_t pool_stride = 256;
enum pool_id : int { cdf_pool = 0, empty_pool = 1, centre_pool = 2, single_pool = 3, pool_count = 4 };
// A test configuration's pool size that stands for the pool's own.
constexpr std::uint32_t own_size = ~0u;

// The hooks of both distributions, the record header, the pool file and its accessor over the
// records at binding 11.
const std::string hooks = std::string(distribution_hooks_glsl) + R"(#include "vplkit/estimators/ris_pool_params.h"
#include "vplkit/estimators/ris_candidate_pool.glsl"
layout(std430, binding = 11) readonly buffer Pool { vplkit_ris_pool_record pool_records[]; };
vplkit_ris_pool_entry vplkit_load_ris_pool_entry(uint pool, uint index) {
  return vplkit_ris_pool_entry_from_record(pool_records[pool * 256u + index]);
}
)";

// A kernel of the prelude, the hooks and `head`, running `body` for i < count.
template <class Out>
std::vector<Out> run(const std::string& head, const std::string& body, std::size_t count, const scene_params& p,
                     const std::vector<named_point>& pts, const distribution_ref& dist, const std::vector<record>& pool,
                     std::vector<vplkit::parity::ssbo> extra, const std::string& name) {
  extra.push_back(input(11, pool.empty() ? std::vector<record>(1, record{}) : pool));
  return vplkit::parity::run_compute<Out>(
      ris_kernel(name, hooks, head, body, "VPLKIT_PARITY_COUNT", p, pts, dist, std::move(extra)), count);
}

// The relative forward error bound of h for entry e at gp (without base_rel): the VPL contribution's
// conditioning at the entry's point, whose bits both sides share (the entry is uploaded), so only
// the cosines near 0 and the direction's rounding count. 1 where h is 0 on the C++ side by a cosine
// within its noise of 0 (a tie), 0 where it is 0 for another reason (then compared exactly).
double entry_conditioning(const vplkit::gather_point<float>& gp, const entry& e) {
  if (!(e.pmf > 0.0f) || !vplkit::gather_point_valid(gp)) return 0.0;
  const vplkit::vpl<float> v{e.position, e.normal, v3f(1.0f)};
  const vplkit::vec3<float> L = vplkit::vpl_contribution(gp, v, 0.0f);
  const double lum = vplkit::luminance(vplkit::vec3<double>(L));
  const double err = vplkit::luminance(vplkit::vec3<double>(vplkit::parity::vpl_contribution_error(gp, v, 0.0, 0.0f)));
  if (!(lum > 0.0)) return err > 0.0 ? 1.0 : 0.0;
  return std::min(1.0, err / lum);
}

// A texel without a VPL.
int unlit_texel() {
  const auto view = fixture().view();
  for (int t = 0; t < view.texel_count(); ++t)
    if (!vplkit::vpl_has_flux(view.vpl_at(t))) return t;
  return -1;
}

// The pools of one VPL mode, pool_count x pool_stride entries: the CDF's first pool_stride draws;
// empty entries (a texel without flux drawn with pmf 1, and draws of pmf 0); patch entries whose
// point the patch moved to the texel centre; one lit entry alone.
struct pool_set {
  std::vector<entry> entries;
  std::uint32_t size[pool_count] = {};
  const entry* of(int pool) const { return entries.data() + std::size_t(pool) * pool_stride; }
  std::vector<record> records() const {
    std::vector<record> out;
    for (const entry& e : entries) out.push_back(vplkit::gpu::make_ris_pool_record(e));
    return out;
  }
};

pool_set make_pools(vplkit::vpl_mode mode, float tol) {
  const auto view = fixture().view();
  pool_set s;
  s.entries.resize(std::size_t(pool_count) * pool_stride);
  const distribution_ref cdf{};
  for (std::uint32_t i = 0; i < pool_stride; ++i)
    s.entries[i] = vplkit::ris_pool_draw_entry(view, cdf, pool_seed, i, mode, tol);
  s.size[cdf_pool] = pool_stride;
  const distribution_ref unlit = fixed_case(1.0f, unlit_texel()), none = fixed_case(0.0f, lit_texel());
  for (std::uint32_t i = 0; i < pool_stride; ++i)
    s.entries[pool_stride + i] = vplkit::ris_pool_draw_entry(view, i % 2 == 0 ? unlit : none, pool_seed, i, mode, tol);
  s.size[empty_pool] = pool_stride;
  // At-centre points: a grid of jitters over the texels, as dprsm_patch_vpl moves them.
  std::uint32_t n = 0;
  const float xs[] = {0.01f, 0.2f, 0.5f, 0.8f, 0.99f};
  for (int t = 0; t < view.texel_count() && n < 48; ++t)
    for (float a : xs)
      for (float b : xs) {
        const float pmf = source().cdf.pmf(std::size_t(t));
        const vplkit::ris_mis_draw<float> c{vplkit::ris_sample<float>{t, {a, b}}, pmf};
        const entry e = vplkit::ris_pool_make_entry(view, c, vplkit::vpl_mode::patch, tol);
        if (n < 48 && e.at_centre == 1 && e.pmf > 0.0f) s.entries[2 * pool_stride + n++] = e;
      }
  s.size[centre_pool] = n;
  for (std::uint32_t i = 0; i < pool_stride; ++i)
    if (s.entries[i].pmf > 0.0f) {
      s.entries[3 * pool_stride] = s.entries[i];
      s.size[single_pool] = 1;
      break;
    }
  return s;
}

}  // namespace

TEST_CASE("ris pool record: GLSL reads and writes the C++ layout, and needs no accessor") {
  // A kernel with the record header alone: ris_pool_entry.glsl brings no accessor or hook (Mesa
  // would refuse to link an unresolved one), and loads and stores keep every bit (GLSL 4.30 section
  // 4.7.1: no flush, no canonicalisation), so a round trip through the GLSL entry is exact.
  std::vector<record> in;
  for (int i = 0; i < 64; ++i) {
    entry e;
    e.position = v3f(float(i) - 0.5f, std::ldexp(1.0f, i - 40), -3.25f * float(i));
    e.pmf = i % 7 == 0 ? 0.0f : std::ldexp(1.0f, -i);
    e.normal = glm::normalize(v3f(1.0f, float(i % 3), -2.0f));
    e.area = std::ldexp(1.5f, i - 20);
    e.radiance = v3f(0.1f * float(i), 1e-30f, 7.0f);
    e.texel = i % 5 == 0 ? -1 : 37 * i;
    e.xi = vplkit::vec2<float>(float(i) / 64.0f, 1.0f - float(i) / 128.0f);
    e.at_centre = i % 3 == 0 ? 1 : 0;
    in.push_back(vplkit::gpu::make_ris_pool_record(e));
  }
  vplkit::parity::kernel_call call;
  call.name = "ris_pool_record.comp";
  call.source = R"(
#include "vplkit/estimators/ris_pool_params.h"
layout(std430, binding = 9) readonly buffer In { vplkit_ris_pool_record records_in[]; };
layout(std430, binding = 1) writeonly buffer Out { vplkit_ris_pool_record records_out[]; };
layout(std430, binding = 2) writeonly buffer Fields { vec4 fields[]; };
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= VPLKIT_PARITY_COUNT) return;
  vplkit_ris_pool_entry e = vplkit_ris_pool_entry_from_record(records_in[i]);
  records_out[i] = vplkit_make_ris_pool_record(e);
  fields[4u * i] = vec4(e.position, e.pmf);
  fields[4u * i + 1u] = vec4(e.normal, e.area);
  fields[4u * i + 2u] = vec4(e.radiance, float(e.texel));
  fields[4u * i + 3u] = vec4(e.xi, float(e.at_centre), float(e.pad));
}
)";
  call.inputs = {input(9, in)};
  call.more_outputs = {vplkit::parity::output_of<float4>(2, {}, 4 * in.size())};
  const auto out = vplkit::parity::run_kernel(call, in.size(), sizeof(record));
  const auto records = out.get<record>(1);
  const auto fields = out.get<float4>(2);
  REQUIRE(records.size() == in.size());
  REQUIRE(fields.size() == 4 * in.size());
  std::size_t bad_bytes = 0, bad_fields = 0;
  for (std::size_t i = 0; i < in.size(); ++i) {
    bad_bytes += std::memcmp(&records[i], &in[i], sizeof(record)) != 0 ? 1 : 0;
    const entry e = vplkit::gpu::ris_pool_entry_from_record(in[i]);
    const float want[16] = {e.position.x, e.position.y, e.position.z, e.pmf,          e.normal.x, e.normal.y,
                            e.normal.z,   e.area,       e.radiance.x, e.radiance.y,   e.radiance.z,
                            float(e.texel), e.xi.x,     e.xi.y,       float(e.at_centre), 0.0f};
    bool ok = true;
    for (int k = 0; k < 16; ++k) ok = ok && bits(fields[4 * i + std::size_t(k / 4)][k % 4]) == bits(want[k]);
    bad_fields += ok ? 0 : 1;
  }
  std::cout << "  ris pool record: " << in.size() << " records, " << bad_bytes << " differ in a byte, " << bad_fields
            << " with a field read differently\n";
  CHECK(bad_bytes == 0);
  CHECK(bad_fields == 0);
}

TEST_CASE("ris_pool_draw_entry: GPU vs C++ (point and patch, the CDF, one lit texel, empty distributions)") {
  const scene_fixture& f = fixture();
  const auto view = f.view();
  const float tol = window();
  const int lit = lit_texel();
  REQUIRE(lit >= 0);
  REQUIRE(unlit_texel() >= 0);
  // ip.y = seed, ip.z = vpl mode, ip.w = distribution; fp.y = window.
  const std::string head = R"(
layout(std430, binding = 1) writeonly buffer Out { vplkit_ris_pool_record result[]; };
)";
  const std::string body = R"(  result[i] = vplkit_make_ris_pool_record(
      vplkit_ris_pool_draw_entry(load_view(), uint(ip.w), uint(ip.y), i, ip.z, fp.y));
)";
  struct config {
    distribution_ref dist;
    std::uint32_t count;
    const char* name;
    bool empty;  // every entry empty
  };
  const config configs[] = {{{}, 1024, "cdf", false},
                            {fixed_case(1.0f, lit), 32, "one lit texel, pmf 1", false},
                            {fixed_case(0.0f, lit), 32, "pmf 0", true},
                            {fixed_case(3e-39f, lit), 32, "denormal pmf", true},
                            {fixed_case(0.5f, view.texel_count()), 32, "an index outside the view", true},
                            {fixed_case(1.0f, unlit_texel()), 32, "a texel without flux, pmf 1", true}};
  std::size_t flips = 0, compared = 0, at_centre = 0;
  for (const vplkit::vpl_mode mode : {vplkit::vpl_mode::point, vplkit::vpl_mode::patch})
    for (const config& cfg : configs) {
      scene_params p = f.params();
      p.ip.y = int(pool_seed);
      p.ip.z = int(mode);
      p.ip.w = cfg.dist.id;
      p.fp.y = tol;
      const std::string what =
          std::string("ris_pool_draw_entry ") + (mode == vplkit::vpl_mode::patch ? "patch, " : "point, ") + cfg.name;
      const auto gpu = run<record>(head, body, cfg.count, p, {}, cfg.dist, {}, {}, "ris_pool_draw.comp");
      vplkit::parity::series<std::int32_t> texel, pad, zeroed;
      vplkit::parity::series<float> xi, pmf;
      std::vector<float> pg, pc, ng, nc, ag, ac, rg, rc;
      std::vector<double> pb, nb, ab, rb;
      std::size_t non_empty = 0;
      for (std::uint32_t i = 0; i < cfg.count; ++i) {
        const entry c = vplkit::ris_pool_draw_entry(view, cfg.dist, pool_seed, i, mode, tol);
        const entry g = vplkit::gpu::ris_pool_entry_from_record(gpu[i]);
        texel.add(g.texel, c.texel);
        pad.add(gpu[i].pad, 0);
        xi.add(g.xi.x, c.xi.x);
        xi.add(g.xi.y, c.xi.y);
        non_empty += c.pmf > 0.0f ? 1 : 0;
        at_centre += c.at_centre;
        // The patch point's acceptance (its flux) and hidden test: decisions that may flip at a tie.
        if ((g.pmf > 0.0f) != (c.pmf > 0.0f) || g.at_centre != c.at_centre) {
          ++flips;
          continue;
        }
        ++compared;
        pmf.add(g.pmf, c.pmf);  // the stored cdf's difference: the same on both sides
        if (!(c.pmf > 0.0f)) {
          // An empty entry is the default one beyond its texel and jitter: every other field 0.
          const bool zero = g.position == v3f(0.0f) && g.normal == v3f(0.0f) && g.radiance == v3f(0.0f) &&
                            g.area == 0.0f && g.at_centre == 0;
          zeroed.add(zero ? 1 : 0, 1);
          continue;
        }
        // Bounds: a patch point's position error dy (parity_vpl_error_bound.hpp), which turns the
        // direction from the light by dy / d1; cos(alpha) moves by that and its unit vectors' and
        // dot's rounding, and A and L_o divide by it (A through its floor 1e-6).
        double dy = 0.0, d1 = 1.0;
        if (mode == vplkit::vpl_mode::patch) {
          const auto s = vplkit::dprsm_patch_vpl(view, c.texel, c.xi, tol);
          dy = vplkit::parity::patch_point_error(view, c.texel, s);
          d1 = s.distance;
        } else {
          d1 = glm::length(vplkit::vec3<double>(c.position) - vplkit::vec3<double>(view.light.position));
        }
        using namespace vplkit::parity::vpl_error;
        const double e_dir = d1 > 0.0 ? dy / d1 : 0.0;
        const double cos_noise = e_dir + 2.0 * unit + 3.0 * u;
        const glm::dvec3 to_light = glm::dvec3(view.light.position) - glm::dvec3(c.position);
        const double cos_a = glm::dot(glm::dvec3(c.normal), glm::normalize(to_light));
        const double tie = cos_a <= 2.0 * cos_noise ? 1.0 : 0.0;  // back-facing within its noise
        const double shape = 2.0 * (2.0 * e_dir + cos_noise / std::max(cos_a, 1e-6));
        for (int k = 0; k < 3; ++k) {
          pg.push_back(g.position[k]), pc.push_back(c.position[k]), pb.push_back(2.0 * dy);
          ng.push_back(g.normal[k]), nc.push_back(c.normal[k]), nb.push_back(2.0 * unit);
          rg.push_back(g.radiance[k]), rc.push_back(c.radiance[k]);
          rb.push_back((base_rel + shape) * std::abs(double(c.radiance[k])) +
                       tie * (std::abs(double(g.radiance[k])) + std::abs(double(c.radiance[k]))));
        }
        ag.push_back(g.area), ac.push_back(c.area);
        ab.push_back((base_rel + shape) * double(c.area) + tie * (std::abs(double(g.area)) + double(c.area)));
      }
      const auto describe = [&](std::size_t) { return what; };
      VPLKIT_CHECK_PARITY(compare_exact(texel, describe, what + ": texel"));
      VPLKIT_CHECK_PARITY(compare_exact(pad, describe, what + ": record padding"));
      VPLKIT_CHECK_PARITY(compare_exact(zeroed, describe, what + ": empty entries zeroed"));
      VPLKIT_CHECK_PARITY(compare_floats(xi, within_ulps(0), describe, what + ": jitter"));
      VPLKIT_CHECK_PARITY(compare_floats(pmf, within_ulps(0), describe, what + ": pmf"));
      CHECK(vplkit::parity::check_within_bounds(pg, pc, pb, what + ": position"));
      CHECK(vplkit::parity::check_within_bounds(ng, nc, nb, what + ": unit normal"));
      CHECK(vplkit::parity::check_within_bounds(ag, ac, ab, what + ": area of p2"));
      CHECK(vplkit::parity::check_within_bounds(rg, rc, rb, what + ": reflected radiance"));
      if (cfg.empty) CHECK(non_empty == 0);
      else CHECK(non_empty > cfg.count / 2);
    }
  std::cout << "  ris_pool_draw_entry: " << compared << " entries compared, " << flips
            << " with an emptiness or at-centre decision that differs, " << at_centre << " at the centre\n";
  CHECK(at_centre > 0);  // the hard case is exercised
  if (bit_exact_device()) CHECK(flips == 0);
  else CHECK(flips <= compared / 100);
}

namespace {

// The kept sample's visibility as ris_mis_shade_kept queries it: 2 where it queries nothing.
const char* const kept_visible_glsl = R"(
uint kept_visible(vplkit_gather_point gp, vplkit_ris_reservoir r, vplkit_ris_mis_kept kept, vplkit_visibility vis) {
  if (!vplkit_gather_point_valid(gp) || !vplkit_ris_reservoir_has_sample(r)) return 2u;
  if (!(kept.h.x > 0.0 || kept.h.y > 0.0 || kept.h.z > 0.0)) return 2u;
  return vplkit_visibility_test(vis, gp.position, gp.normal, kept.position, kept.normal) ? 1u : 0u;
}
)";

std::uint32_t kept_visible(const vplkit::gather_point<float>& gp, const vplkit::ris_reservoir<float>& r,
                           const vplkit::ris_mis_kept<float>& kept) {
  if (!vplkit::gather_point_valid(gp) || !vplkit::ris_reservoir_has_sample(r)) return 2u;
  if (!(kept.h.x > 0.0f || kept.h.y > 0.0f || kept.h.z > 0.0f)) return 2u;
  const vplkit::voxel_visibility<float> vis{fixture().grid.view()};
  return vis(gp.position, gp.normal, kept.position, kept.normal) ? 1u : 0u;
}

// The pass_facts (parity_ris_mis_support.hpp) of one pooled candidate pass over `size` entries of `pool`.
pass_facts pooled_pass(const vplkit::gather_point<float>& gp, const entry* pool, std::uint32_t size, int m, float n1,
                       float n2, vplkit::counter_rng rng) {
  pass_facts out;
  if (!vplkit::gather_point_valid(gp) || m <= 0 || !(n2 > 0.0f) || size == 0) return out;
  const auto rx = vplkit::make_mis_receiver(gp);
  double sum = 0.0;
  for (int k = 0; k < m; ++k) {
    const float u = vplkit::rng_next_unit<float>(rng);
    const double u_keep = vplkit::rng_next_unit<float>(rng);
    const entry& e = pool[vplkit::ris_pool_index(u, size)];
    const double cond = entry_conditioning(gp, e);
    if (cond >= 0.5) out.cosine_tie = true;
    const float target = vplkit::luminance(vplkit::ris_pool_unshadowed(gp, rx, e, n1, n2));
    if (!vplkit::reservoir_weight_usable(target)) continue;
    const double w = target / e.pmf;  // the float quotient the reservoir is offered
    sum += w;
    out.margin = std::min(out.margin, std::abs(u_keep * sum - w) / w);
    out.weight_rel = std::max(out.weight_rel, base_rel + 2.0 * cond);
  }
  return out;
}

struct unshadowed_item {
  std::int32_t point, pool, index;
  float n1, n2;
  std::int32_t pad0, pad1, pad2;
};

const char* const pass_head = R"(
struct unshadowed_item { int point; int pool; int index; float n1; float n2; int pad0; int pad1; int pad2; };
layout(std430, binding = 13) readonly buffer Items { unshadowed_item items[]; };
)";

// ip2.x = job: 0 h of items[i]; 1 a reservoir at point i (ip.y = M, ip.w = pool, ip2.y = pool size;
// fp.x = n1, fp.z = n2) and its shade.
const char* const pass_body = R"(  if (ip2.x == 0) {
    unshadowed_item it = items[i];
    vplkit_ris_pool_entry e = vplkit_load_ris_pool_entry(uint(it.pool), uint(it.index));
    vec3 h = vplkit_ris_pool_unshadowed(load_point(uint(it.point)), e, it.n1, it.n2);
    result[i] = out4(vec4(h, 0.0), vec4(0.0), ivec4(0), uvec4(0u));
    return;
  }
  vplkit_gather_point gp = load_point(i);
  vplkit_counter_rng rng = vplkit_make_counter_rng(0x815u, i);
  vplkit_ris_mis_kept kept;
  vplkit_ris_reservoir r = vplkit_ris_mis_resample_pooled(gp, uint(ip.w), uint(ip2.y), rng, ip.y, fp.x, fp.z, kept);
  vplkit_visibility vis = vplkit_make_voxel_visibility(load_grid());
  vec3 shade = vplkit_ris_mis_shade_kept(gp, r, kept, vis);
  result[i] = out4(vec4(shade, r.weight_sum), vec4(r.kept.xi, r.target, r.confidence),
                   ivec4(r.kept.texel, int(rng.counter), 0, 0), uvec4(kept_visible(gp, r, kept, vis), 0u, 0u, 0u));
)";

std::string pass_kernel_head() { return std::string(out4_glsl) + kept_visible_glsl + pass_head; }

}  // namespace

TEST_CASE("ris_pool_unshadowed: GPU vs C++ over gather points and entries, at-centre and empty entries") {
  const scene_fixture& f = fixture();
  const auto pts = gather_points();
  const float tol = window();
  struct counts {
    float n1, n2;
  };
  const counts cs[] = {{8, 8}, {0, 4}, {16, 2}, {8, 0}, {0, 0}};
  for (const vplkit::vpl_mode mode : {vplkit::vpl_mode::point, vplkit::vpl_mode::patch}) {
    const pool_set pools = make_pools(mode, tol);
    REQUIRE(pools.size[centre_pool] >= 4);  // the scene has hidden patch points
    std::vector<unshadowed_item> items;
    for (std::size_t i = 0; i < pts.size(); ++i)
      for (std::int32_t k = 0; k < 5; ++k) {
        const counts c = cs[(i + std::size_t(k)) % std::size(cs)];
        const std::int32_t index = std::int32_t((i * 7 + std::size_t(k) * 53) % pool_stride);
        items.push_back({std::int32_t(i), cdf_pool, index, c.n1, c.n2, 0, 0, 0});
      }
    const std::size_t centre_begin = items.size();
    for (std::size_t i = 0; i < pts.size(); i += 3)
      for (std::uint32_t k = 0; k < pools.size[centre_pool]; k += 4)
        for (float n1 : {0.0f, 1.0f, 8.0f})
          items.push_back({std::int32_t(i), centre_pool, std::int32_t(k), n1, 4.0f, 0, 0, 0});
    const std::size_t centre_end = items.size();
    for (std::size_t i = 0; i < pts.size(); i += 5)
      for (std::int32_t k : {0, 1}) items.push_back({std::int32_t(i), empty_pool, k, 0.0f, 8.0f, 0, 0, 0});
    scene_params p = f.params();
    p.ip2.x = 0;
    const auto gpu = run<out4>(pass_kernel_head(), pass_body, items.size(), p, pts, {}, pools.records(),
                               {input(13, items)}, "ris_pool_pass.comp");
    std::vector<float> g, c;
    std::vector<double> rel;
    std::size_t centre_zero_with_gathering = 0, centre_with_gathering = 0, centre_lit_without = 0, empty_nonzero = 0;
    for (std::size_t k = 0; k < items.size(); ++k) {
      const unshadowed_item& it = items[k];
      const auto& gp = pts[std::size_t(it.point)].gp;
      const entry& e = pools.of(it.pool)[it.index];
      const auto h = vplkit::ris_pool_unshadowed(gp, vplkit::make_mis_receiver(gp), e, it.n1, it.n2);
      const double r = base_rel + 2.0 * entry_conditioning(gp, e);
      for (int ch = 0; ch < 3; ++ch) {
        g.push_back(gpu[k].a[ch]);
        c.push_back(h[ch]);
        rel.push_back(r);
      }
      if (k >= centre_begin && k < centre_end) {
        if (it.n1 > 0.0f) {
          ++centre_with_gathering;
          centre_zero_with_gathering += gpu[k].a.x == 0.0f && gpu[k].a.y == 0.0f && gpu[k].a.z == 0.0f;
        } else {
          centre_lit_without += h.x > 0.0f ? 1 : 0;
        }
      }
      if (k >= centre_end) empty_nonzero += gpu[k].a.x != 0.0f || gpu[k].a.y != 0.0f || gpu[k].a.z != 0.0f;
    }
    const std::string what = std::string("ris_pool_unshadowed ") + (mode == vplkit::vpl_mode::patch ? "patch" : "point");
    std::size_t flips = 0;
    CHECK(check_rel(what + ": h", g, c, rel, flips) == 0);
    if (bit_exact_device()) CHECK(flips == 0);
    else CHECK(flips <= g.size() / 100);
    // The hard cases: a point at the centre belongs to gathering when n1 > 0 (h = 0), to the VPL
    // strategy alone when n1 = 0; an empty entry weighs 0 everywhere.
    INFO(what);
    CHECK(centre_zero_with_gathering == centre_with_gathering);
    CHECK(centre_lit_without > 0);
    CHECK(empty_nonzero == 0);
  }
}

TEST_CASE("ris_mis_resample_pooled and its shade: GPU vs C++ (point and patch, M = 1, 8, 32, hard pools)") {
  const scene_fixture& f = fixture();
  const auto pts = gather_points();
  const float tol = window();
  struct config {
    int m;
    float n1, n2;
    int pool;
    std::uint32_t size;  // own_size: the pool's own
    const char* name;
    bool any;  // samples expected (else none)
  };
  const config configs[] = {{1, 8, 8, cdf_pool, own_size, "cdf pool", true},
                            {8, 8, 8, cdf_pool, own_size, "cdf pool", true},
                            {32, 8, 8, cdf_pool, own_size, "cdf pool", true},
                            {8, 0, 4, cdf_pool, own_size, "cdf pool", true},
                            {8, 8, 0, cdf_pool, own_size, "cdf pool, n2 = 0", false},
                            {0, 8, 8, cdf_pool, own_size, "cdf pool, M = 0", false},
                            {-3, 8, 8, cdf_pool, own_size, "cdf pool, M = -3", false},
                            {8, 8, 8, cdf_pool, 0, "pool size 0", false},
                            {8, 8, 8, single_pool, own_size, "one entry", true},
                            {8, 8, 8, empty_pool, own_size, "empty entries", false},
                            {8, 8, 8, centre_pool, own_size, "at-centre entries, n1 > 0", false},
                            {8, 0, 8, centre_pool, own_size, "at-centre entries, n1 = 0", true}};
  std::size_t flipped = 0, compared = 0, vis_flips = 0;
  for (const vplkit::vpl_mode mode : {vplkit::vpl_mode::point, vplkit::vpl_mode::patch}) {
    const pool_set pools = make_pools(mode, tol);
    REQUIRE(pools.size[single_pool] == 1);
    const std::vector<record> records = pools.records();
    for (const config& cfg : configs) {
      const std::uint32_t size = cfg.size == own_size ? pools.size[cfg.pool] : cfg.size;
      scene_params p = f.params();
      p.ip.y = cfg.m;
      p.ip.w = cfg.pool;
      p.ip2.x = 1;
      p.ip2.y = int(size);
      p.fp.x = cfg.n1;
      p.fp.z = cfg.n2;
      const std::string what = std::string("ris_mis_resample_pooled ") +
                               (mode == vplkit::vpl_mode::patch ? "patch" : "point") + ", M = " + std::to_string(cfg.m) +
                               ", n1 = " + std::to_string(int(cfg.n1)) + ", n2 = " + std::to_string(int(cfg.n2)) +
                               ", " + cfg.name;
      const auto gpu = run<out4>(pass_kernel_head(), pass_body, pts.size(), p, pts, {}, records,
                                 {input(13, std::vector<unshadowed_item>(1))}, "ris_pool_pass.comp");
      vplkit::parity::series<std::int32_t> texel, counter, visible;
      vplkit::parity::series<float> confidence;
      std::vector<float> vg, vc, tg, tc, sg, sc;
      std::vector<double> vr, tr, sr;
      std::size_t any_sample = 0;
      for (std::size_t i = 0; i < pts.size(); ++i) {
        const auto& gp = pts[i].gp;
        const vplkit::counter_rng start = vplkit::make_counter_rng(0x815u, std::uint32_t(i));
        vplkit::counter_rng rng = start;
        vplkit::ris_mis_kept<float> kept;
        const auto r = vplkit::ris_mis_resample_pooled(gp, pools.of(cfg.pool), size, rng, cfg.m, cfg.n1, cfg.n2, kept);
        const vplkit::voxel_visibility<float> vis{f.grid.view()};
        const auto shade = vplkit::ris_mis_shade_kept(gp, r, kept, vis);
        const out4& o = gpu[i];
        counter.add(o.c.y, std::int32_t(rng.counter));
        confidence.add(o.b.w, r.confidence);
        any_sample += vplkit::ris_reservoir_has_sample(r) ? 1 : 0;
        if (o.c.x != r.kept.texel || bits(o.b.x) != bits(r.kept.xi.x) || bits(o.b.y) != bits(r.kept.xi.y)) {
          ++flipped;
          const pass_facts pf = pooled_pass(gp, pools.of(cfg.pool), size, cfg.m, cfg.n1, cfg.n2, start);
          INFO(what << ", " << pts[i].name << ": kept samples differ, smallest decision margin " << pf.margin
                    << ", weights' error bound " << pf.weight_rel << (pf.cosine_tie ? ", a cosine at a tie" : ""));
          CHECK((pf.margin <= 2.0 * pf.weight_rel || pf.cosine_tie));  // a tie
          continue;
        }
        ++compared;
        texel.add(o.c.x, r.kept.texel);
        const std::uint32_t vis_cpu = kept_visible(gp, r, kept);
        if (o.d[0] != vis_cpu) {
          ++vis_flips;  // a voxel march or a cosine at a tie: the shade differs by the whole value
          continue;
        }
        visible.add(std::int32_t(o.d[0]), std::int32_t(vis_cpu));
        const pass_facts pf = pooled_pass(gp, pools.of(cfg.pool), size, cfg.m, cfg.n1, cfg.n2, start);
        // weight_sum: the mean of M weights (each within its bound) and M roundings of the sum; the
        // target h's bound at the kept entry; the shade h W = h weight_sum / target shares the
        // kept entry's error between h and the target.
        const double ws_rel = pf.weight_rel + double(std::max(cfg.m, 1)) * vplkit_test::spec::ulp_rel;
        vg.push_back(o.a.w), vc.push_back(r.weight_sum), vr.push_back(ws_rel);
        tg.push_back(o.b.z), tc.push_back(r.target), tr.push_back(pf.weight_rel + base_rel);
        for (int ch = 0; ch < 3; ++ch) {
          sg.push_back(o.a[ch]);
          sc.push_back(shade[ch]);
          sr.push_back(2.0 * tr.back() + ws_rel);
        }
      }
      const auto describe = [&](std::size_t) { return what; };
      VPLKIT_CHECK_PARITY(compare_exact(counter, describe, what + ": stream counters"));
      VPLKIT_CHECK_PARITY(compare_exact(texel, describe, what + ": kept texels"));
      VPLKIT_CHECK_PARITY(compare_exact(visible, describe, what + ": kept samples' visibility"));
      VPLKIT_CHECK_PARITY(compare_floats(confidence, within_ulps(0), describe, what + ": confidence"));
      std::size_t zf = 0;
      CHECK(check_rel(what + ": weight_sum", vg, vc, vr, zf) == 0);
      CHECK(check_rel(what + ": target", tg, tc, tr, zf) == 0);
      CHECK(check_rel(what + ": shade h V W", sg, sc, sr, zf) == 0);
      if (bit_exact_device()) CHECK(zf == 0);
      INFO(what);
      if (!cfg.any) CHECK(any_sample == 0);
      else if (cfg.pool == cdf_pool) CHECK(any_sample > pts.size() / 2);
      else CHECK(any_sample > 0);
    }
  }
  std::cout << "  ris_mis_resample_pooled: " << compared << " reservoirs compared, " << flipped
            << " with a kept sample that differs (each at a tie), " << vis_flips
            << " with a kept sample's visibility that differs\n";
  CHECK(flipped <= compared / 100);
  if (bit_exact_device()) CHECK(vis_flips == 0);
  else CHECK(vis_flips <= compared / 100);
}

namespace {

// The fingerprint (parity_ris_mis_support.hpp) of estimate_ris_mis_pooled's steps: a RIS step is
// ris_mis_resample_pooled over `size` entries of `pool`.
const std::string fingerprint_pooled = fingerprint_glsl("uint pool, uint size", R"(
      vplkit_ris_mis_kept kept;
      vplkit_ris_reservoir r = vplkit_ris_mis_resample_pooled(gp, pool, size, rng, m, n1, n2, kept);
      uint visible = kept_visible(gp, r, kept, vis);)");

point_facts replay_point(const vplkit::gather_point<float>& gp, const entry* pool, std::uint32_t size,
                         vplkit::counter_rng rng, int nd, int nr, int m, vplkit::vpl_mode mode, float tol) {
  return replay_steps(gp, rng, nd, nr, m, mode, tol, [&](vplkit::counter_rng& step_rng, float n1, float n2) {
    const pass_facts pf = pooled_pass(gp, pool, size, m, n1, n2, step_rng);
    vplkit::ris_mis_kept<float> kept;
    const auto r = vplkit::ris_mis_resample_pooled(gp, pool, size, step_rng, m, n1, n2, kept);
    return ris_step_facts{r, kept_visible(gp, r, kept), pf.weight_rel};
  });
}

}  // namespace

TEST_CASE("estimate_ris_mis_pooled: GPU vs C++ per gather point, point and patch, hard pools and counts, range form") {
  const scene_fixture& f = fixture();
  const auto view = f.view();
  const auto pts = gather_points();
  const float tol = window();
  const std::string head = std::string(out4_glsl) + kept_visible_glsl + fingerprint_pooled;
  // ip.y = M, ip.z = vpl mode; ip2 = n_dirs, n_ris, pool, pool size. The range form runs [0, 3),
  // [3, 5), [5, n) in one loop (one copy of the estimator in the program).
  const std::string body = R"(  vplkit_gather_point gp = load_point(i);
  vplkit_dprsm_view view = load_view();
  vplkit_voxel_tracer tracer = vplkit_make_voxel_tracer(load_grid());
  vplkit_visibility vis = vplkit_make_voxel_visibility(load_grid());
  int nd = ip2.x, nr = ip2.y, m = ip.y;
  uint pool = uint(ip2.z), size = uint(ip2.w);
  vplkit_counter_rng rng = vplkit_make_counter_rng(0x5eedu, i);
  uint h = fingerprint(gp, view, pool, size, rng, nd, nr, m, tracer, vis, fp.y, ip.z);
  vec3 e = vplkit_estimate_ris_mis_pooled(gp, view, 0u, pool, size, rng, nd, nr, m, tracer, vis, fp.y, ip.z);
  vplkit_estimator_state s = vplkit_make_estimator_state(vplkit_make_counter_rng(0x5eedu, i));
  int n = max(max(nd, 0), m > 0 ? max(nr, 0) : 0);
  int bounds[4] = int[4](0, min(3, n), min(5, n), n);
  for (int k = 0; k < 3; ++k)
    vplkit_estimate_ris_mis_pooled_range(gp, view, 0u, pool, size, s, bounds[k], bounds[k + 1], nd, nr, m, tracer,
                                         vis, fp.y, ip.z);
  vec3 e2 = vplkit_estimate_ris_mis_finish(s);
  result[i] = out4(vec4(e, 0.0), vec4(e2, 0.0), ivec4(int(rng.counter), int(s.rng.counter), 0, 0), uvec4(h, 0u, 0u, 0u));
)";
  struct config {
    int nd, nr, m, pool;
    std::uint32_t size;  // own_size: the pool's own
    const char* name;
  };
  const std::uint32_t own = own_size;
  const config configs[] = {{8, 8, 8, cdf_pool, own, "cdf pool"},
                            {4, 12, 4, cdf_pool, own, "cdf pool"},
                            {0, 8, 8, cdf_pool, own, "cdf pool"},  // n_dirs = 0: RIS of the unclamped contribution
                            {8, 0, 8, cdf_pool, own, "cdf pool"},  // n_ris = 0: gathering alone
                            {8, 8, 0, cdf_pool, own, "cdf pool"},  // n_candidates = 0: n_ris counts as 0
                            {0, 0, 8, cdf_pool, own, "cdf pool"},
                            {-1, 5, 4, cdf_pool, own, "cdf pool"},
                            {6, -2, 4, cdf_pool, own, "cdf pool"},
                            {8, 8, 8, cdf_pool, 0, "pool size 0"},
                            {4, 8, 4, single_pool, own, "one entry"},
                            {8, 8, 8, empty_pool, own, "empty entries"},
                            {8, 8, 8, centre_pool, own, "at-centre entries, n1 > 0"},
                            {0, 8, 8, centre_pool, own, "at-centre entries, n1 = 0"}};
  std::size_t flipped_total = 0, compared_total = 0;
  for (const vplkit::vpl_mode mode : {vplkit::vpl_mode::point, vplkit::vpl_mode::patch}) {
    const pool_set pools = make_pools(mode, tol);
    const std::vector<record> records = pools.records();
    const distribution_ref cdf{};
    for (const config& cfg : configs) {
      const std::uint32_t size = cfg.size == own ? pools.size[cfg.pool] : cfg.size;
      scene_params p = f.params();
      p.ip.y = cfg.m;
      p.ip.z = int(mode);
      p.fp.y = tol;
      p.ip2 = {cfg.nd, cfg.nr, cfg.pool, int(size)};
      const std::string what = std::string(mode == vplkit::vpl_mode::patch ? "patch" : "point") + ", n_dirs " +
                               std::to_string(cfg.nd) + ", n_ris " + std::to_string(cfg.nr) + ", M " +
                               std::to_string(cfg.m) + ", " + cfg.name;
      const auto gpu = run<out4>(head, body, pts.size(), p, pts, cdf, records, {}, "estimate_ris_mis_pooled.comp");
      vplkit::parity::series<std::int32_t> counter;
      std::vector<float> g, c;
      std::vector<double> rel;
      std::size_t flipped = 0, range_differs = 0, non_zero = 0, bad = 0;
      for (std::size_t i = 0; i < pts.size(); ++i) {
        const auto& gp = pts[i].gp;
        const out4& o = gpu[i];
        vplkit::counter_rng rng = vplkit::make_counter_rng(0x5eedu, std::uint32_t(i));
        const point_facts pf = replay_point(gp, pools.of(cfg.pool), size, rng, cfg.nd, cfg.nr, cfg.m, mode, tol);
        const vplkit::voxel_tracer<float> tracer{f.grid.view()};
        const vplkit::voxel_visibility<float> vis{f.grid.view()};
        const auto e = vplkit::estimate_ris_mis_pooled(gp, view, cdf, pools.of(cfg.pool), size, rng, cfg.nd, cfg.nr,
                                                       cfg.m, tracer, vis, tol, mode);
        counter.add(o.c.x, std::int32_t(rng.counter));
        counter.add(o.c.y, std::int32_t(rng.counter));
        // The range form is the same arithmetic on one device: bit for bit.
        for (int ch = 0; ch < 3; ++ch) range_differs += bits(o.a[ch]) != bits(o.b[ch]) ? 1 : 0;
        for (int ch = 0; ch < 3; ++ch) bad += std::isfinite(o.a[ch]) && o.a[ch] >= 0.0f ? 0 : 1;
        if (o.d[0] != pf.fingerprint) {
          ++flipped;
          continue;
        }
        non_zero += e.x > 0.0f ? 1 : 0;
        for (int ch = 0; ch < 3; ++ch) {
          g.push_back(o.a[ch]);
          c.push_back(e[ch]);
          rel.push_back(base_rel + pf.rel);
        }
      }
      const auto describe = [&](std::size_t k) { return pts[k / 2].name; };
      VPLKIT_CHECK_PARITY(compare_exact(counter, describe, "estimate_ris_mis_pooled " + what + ": rng counters"));
      std::size_t zf = 0;
      CHECK(check_rel("estimate_ris_mis_pooled " + what + ": estimate", g, c, rel, zf) == 0);
      if (bit_exact_device()) CHECK(zf == 0);
      INFO(what);
      CHECK(range_differs == 0);
      CHECK(bad == 0);
      std::cout << "  estimate_ris_mis_pooled " << what << ": " << pts.size() << " gather points, " << flipped
                << " with a decision that differs (excluded), " << non_zero << " non-zero estimates compared\n";
      CHECK(flipped <= std::max<std::size_t>(2, pts.size() / 50));
      // Gathering lights most points whenever it runs; without it only the pool's samples do, and
      // none do from an empty pool, from at-centre entries weighed against gathering, or with no
      // step at all.
      const int nd = std::max(cfg.nd, 0), nr = cfg.m > 0 ? std::max(cfg.nr, 0) : 0;
      if (nd == 0 && nr == 0) CHECK(non_zero == 0);
      else if (nd > 0 || cfg.pool == cdf_pool) CHECK(non_zero > pts.size() / 4);
      else CHECK(non_zero > 0);
      flipped_total += flipped;
      compared_total += pts.size() - flipped;
    }
  }
  std::cout << "  estimate_ris_mis_pooled: " << compared_total << " estimates compared, " << flipped_total
            << " flipped\n";
}
