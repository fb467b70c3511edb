// SPDX-License-Identifier: MIT
// Parity of glsl/vplkit/mis/{heuristics,pdf_conversion}.glsl with the C++ templates of
// include/vplkit/mis/ (T = float): random pdfs spanning 1e-38..3e38 (0, denormals, +inf, NaN,
// negatives mixed in), random and invalid counts, and the sweep over every combination of the
// special values of tests/hardcases/mis_hardcases_test.cpp.
//
// Bounds (measured worst differences in docs/glsl/mis.md):
// - weights, scaled terms, balance_combined, vpl_pdf_solid_angle: relative 16 float ulps (1.9e-6),
//   from the specification's table (value_bound below; tests/support/gpu_precision.hpp).
//   Each result is a chain of one division (its divisor in [1, 32) after the exact power-of-two
//   scaling) and a few multiplies and adds of non-negative numbers (no cancellation), so a
//   relative bound holds everywhere. An IEEE device (llvmpipe) rounds each step exactly like the
//   CPU; GLSL allows 2.5 ulp per division on a GPU, and the GPU model shows the bound holds there.
//   Or absolute FLT_MIN: a result that is denormal on one side may be 0 on the other.
// - the clean_* helpers and the cos-pdfs (one or two multiplies): exact.
// On top of parity, the GPU results themselves must never be NaN, the weights must lie in [0, 1]
// and the two strategies' weights must add up to 1 (or both be 0).
//
// Denormals: the normal-range contract (docs/math.md, "GPU arithmetic model") counts denormal counts, pdfs and
// results as 0 on both sides, so the plain C++ reference is the answer of a device that flushes
// them and of one that keeps them (llvmpipe) alike; the FTZ|DAZ variant of this program
// (docs/testing.md) checks the reference itself under flushing. Only vplkit_mis_div, a GLSL helper
// outside the contract, is compared against an FTZ|DAZ reference on a flushing device.
#include <parity_harness.hpp>
#include <parity_sampling_mis_support.hpp>

#include <gpu_model_float.hpp>
#include <gpu_precision.hpp>

#include <vplkit/mis/heuristics.hpp>
#include <vplkit/mis/pdf_conversion.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

using namespace vplkit::parity;
using namespace vplkit::parity::sampmis;

namespace {

const float eps = vplkit_test::flt_eps;
const float flt_min = vplkit_test::flt_min;
const float denorm_min = vplkit_test::flt_denorm_min;
const float flt_max = vplkit_test::flt_max;
const float inf = vplkit_test::flt_inf;
const float qnan = vplkit_test::flt_nan;

// See the file comment. From the specification's table (vplkit_test::spec): each side rounds the
// mantissa products (0.5 ulp each, up to 4), one sum (0.5) and one division (the C++ 0.5 ulp, a
// GPU 2.5 ulp), so the two differ by at most ~9 ulps; 16 ulps (1.9e-6) leave room for FMA
// contraction. Absolute 2 FLT_MIN: a result within the bound of FLT_MIN may fall below it and be
// flushed on one side only (Vulkan: "even if rounding would otherwise give a normal result").
const auto value_bound =
    within_rel(vplkit_test::spec::rel(16)) | within_abs(2 * vplkit_test::spec::flushed_product_abs);
// Partition of unity of the GPU's own weights: the C++ promises 2 ulps; each GPU weight may be
// off by the value bound, so 2 * 2e-6 + 2 eps.
const double partition_tolerance = 4e-6 + 2.0 * eps;

// The special values of tests/hardcases/mis_hardcases_test.cpp, plus a denormal above
// denorm_min, a value above 2^126 where GPUs' reciprocal-based division underflows, and 3e38.
const std::vector<float>& specials() {
  static const std::vector<float> s = {0.0f,  -0.0f, denorm_min, 1e-40f, flt_min, 1e-20f, 0.5f,
                                       1.0f,  3.0f,  1e20f,      1e38f,  3e38f,   flt_max, inf,
                                       -inf, -1.0f, qnan};
  return s;
}

float log_uniform(input_rng& g, double lo, double hi) {
  const double v = std::pow(10.0, lo + (hi - lo) * g.uniform());
  return v > static_cast<double>(flt_max) ? flt_max : static_cast<float>(v);
}

float random_pdf(input_rng& g) {
  if (g.uniform() < 0.15) return specials()[g.index(specials().size())];
  return log_uniform(g, -38.0, 38.6);
}

float random_count(input_rng& g) {
  static const std::vector<float> odd = {0.0f, -0.0f, 0.5f, 1e-40f, denorm_min, flt_min, 1e30f,
                                         3e38f, flt_max, inf, qnan, -1.0f};
  const double r = g.uniform();
  if (r < 0.1) return odd[g.index(odd.size())];
  if (r < 0.55) return static_cast<float>(1 + g.index(64));
  return std::ldexp(1.0f, static_cast<int>(g.index(21)));  // 1 .. 2^20
}

float random_value(input_rng& g) {  // f of balance_combined: any sign, many decades
  static const std::vector<float> odd = {0.0f,  -0.0f, 1.0f,  -2.0f, flt_max, -flt_max,
                                         inf,   -inf,  qnan,  denorm_min, 1e-40f};
  if (g.uniform() < 0.1) return odd[g.index(odd.size())];
  const float v = log_uniform(g, -38.0, 38.0);
  return g.uniform() < 0.3 ? -v : v;
}

bool is_weight(float w) { return w >= 0.0f && w <= 1.0f; }  // false for NaN

struct heuristics_out {
  float4 weights;  // balance, balance swapped, power, power swapped
  float4 combined;  // balance_combined, terms.a, terms.b, balance_combined swapped
  float4 clean;     // clean_count(n1), clean_pdf(p1), clean_count(n2), clean_pdf(p2)
};

// balance_combined is 0 where its quotient overflows: discontinuous at FLT_MAX, where a result
// within the specification's bound of FLT_MAX may land on either side (a 2.5-ulp division). Inputs
// whose exact quotient lies within 2^-16 of FLT_MAX are compared with that margin: left out of the
// value comparison and counted.
bool combined_near_overflow(const float4& nps, float f) {
  const double lo = std::numeric_limits<float>::min(), big = std::numeric_limits<float>::max();
  auto count = [&](double n) { return n >= lo && n <= big ? n : 0.0; };
  const double n1 = count(nps.x), n2 = count(nps.z);
  const double p1 = n1 > 0 && nps.y >= lo ? nps.y : 0.0, p2 = n2 > 0 && nps.w >= lo ? nps.w : 0.0;
  if (std::isinf(p1) || std::isinf(p2) || !std::isfinite(f)) return false;
  const double den = n1 * p1 + n2 * p2;
  if (!(den > 0)) return false;
  const double r = std::abs(double(f)) / den;
  return r > big * (1.0 - std::ldexp(1.0, -16)) && r < big * (1.0 + std::ldexp(1.0, -16));
}

// The C++ side of heuristics_out with T = float (the reference) or T = gpu_float (the GPU model).
template <class T>
heuristics_out heuristics_of(const float4& nps, float fv) {
  const T n1 = nps.x, p1 = nps.y, n2 = nps.z, p2 = nps.w, f = fv;
  const auto t = vplkit::mis_scaled_terms(n1, p1, n2, p2);
  heuristics_out o;
  o.weights = {float(vplkit::balance_heuristic(n1, p1, n2, p2)), float(vplkit::balance_heuristic(n2, p2, n1, p1)),
               float(vplkit::power_heuristic(n1, p1, n2, p2)), float(vplkit::power_heuristic(n2, p2, n1, p1))};
  o.combined = {float(vplkit::balance_combined(f, n1, p1, n2, p2)), float(t.a), float(t.b),
                float(vplkit::balance_combined(f, n2, p2, n1, p1))};
  o.clean = {float(vplkit::mis_clean_count(n1)), float(vplkit::mis_clean_pdf(p1)), float(vplkit::mis_clean_count(n2)),
             float(vplkit::mis_clean_pdf(p2))};
  return o;
}

}  // namespace

TEST_CASE("heuristics.glsl: weights, scaled terms and balance_combined over many decades") {
  device_flushes_denormals();  // prints whether it does: the reference is the same either way
  std::vector<float4> in;  // n1, p1, n2, p2
  std::vector<float> fs;
  input_rng g(11);
  for (int i = 0; i < 200000; ++i) {
    const float p1 = random_pdf(g);
    // every fourth pair close together: weights near 1/2, where rounding shows most
    const float p2 = i % 4 == 0 ? p1 * static_cast<float>(1.0 + (g.uniform() - 0.5) * 1e-3)
                                : random_pdf(g);
    in.push_back({random_count(g), p1, random_count(g), p2});
    fs.push_back(random_value(g));
  }
  const std::size_t n_random = in.size();
  // The hard-case sweep of mis_hardcases_test.cpp.
  for (float n1 : specials())
    for (float p1 : specials())
      for (float n2 : {0.0f, 1.0f, 5.0f, qnan})
        for (float p2 : specials())
          for (float f : {0.0f, 1.0f, -2.0f, flt_max}) {
            in.push_back({n1, p1, n2, p2});
            fs.push_back(f);
          }
  const std::size_t n = in.size();
  const auto gpu = run_compute<heuristics_out>(
      per_item(R"(
#include "vplkit/mis/heuristics.glsl"
struct R { vec4 weights; vec4 combined; vec4 clean; };
)",
               {input(0, in, "vec4 nps"), input(2, fs, "float fs")}, "R result", R"(
  float n1 = nps[i].x, p1 = nps[i].y, n2 = nps[i].z, p2 = nps[i].w, f = fs[i];
  vplkit_mis_terms t = vplkit_mis_scaled_terms(n1, p1, n2, p2);
  result[i].weights = vec4(vplkit_balance_heuristic(n1, p1, n2, p2),
                           vplkit_balance_heuristic(n2, p2, n1, p1),
                           vplkit_power_heuristic(n1, p1, n2, p2),
                           vplkit_power_heuristic(n2, p2, n1, p1));
  result[i].combined = vec4(vplkit_balance_combined(f, n1, p1, n2, p2), t.a, t.b,
                            vplkit_balance_combined(f, n2, p2, n1, p1));
  result[i].clean = vec4(vplkit_mis_clean_count(n1), vplkit_mis_clean_pdf(p1),
                         vplkit_mis_clean_count(n2), vplkit_mis_clean_pdf(p2));)"),
      n);

  std::vector<heuristics_out> cpu(n);
  for (std::size_t i = 0; i < n; ++i) cpu[i] = heuristics_of<float>(in[i], fs[i]);
  auto input_text = [&](std::size_t k) {
    return "n1 = " + show(in[k].x) + ", p1 = " + show(in[k].y) + ", n2 = " + show(in[k].z) +
           ", p2 = " + show(in[k].w) + ", f = " + show(fs[k]) +
           (k < n_random ? " [random]" : " [special sweep]");
  };
  // Each float4 of the output, with the call behind each of its components.
  struct named_float4 {
    float4 heuristics_out::*field;
    const char* what[4];
    bool exact;
  };
  const named_float4 columns[] = {
      {&heuristics_out::weights,
       {"vplkit_balance_heuristic(n1,p1,n2,p2)", "vplkit_balance_heuristic(n2,p2,n1,p1)",
        "vplkit_power_heuristic(n1,p1,n2,p2)", "vplkit_power_heuristic(n2,p2,n1,p1)"},
       false},
      {&heuristics_out::combined,
       {"vplkit_balance_combined(f,n1,p1,n2,p2)", "vplkit_mis_scaled_terms .a", "vplkit_mis_scaled_terms .b",
        "vplkit_balance_combined(f,n2,p2,n1,p1)"},
       false},
      {&heuristics_out::clean,
       {"vplkit_mis_clean_count(n1)", "vplkit_mis_clean_pdf(p1)", "vplkit_mis_clean_count(n2)",
        "vplkit_mis_clean_pdf(p2)"},
       true},
  };
  std::vector<bool> near_overflow(n);
  std::size_t n_near = 0;
  for (std::size_t i = 0; i < n; ++i) n_near += (near_overflow[i] = combined_near_overflow(in[i], fs[i])) ? 1 : 0;
  std::cout << "  balance_combined: " << n_near << " inputs within 2^-16 of FLT_MAX, compared with that margin\n";
  // A balance_combined column with the near-overflow items given the reference's value.
  auto masked = [&](std::vector<float> v, const std::vector<float>& ref, const named_float4& c, int k) {
    if (c.field == &heuristics_out::combined && (k == 0 || k == 3))
      for (std::size_t i = 0; i < n; ++i)
        if (near_overflow[i]) v[i] = ref[i];
    return v;
  };
  for (const auto& c : columns) {
    for (int k = 0; k < 4; ++k) {
      const auto get = [&c, k](const heuristics_out& o) { return (o.*c.field)[k]; };
      const auto gv = component(gpu, get), cv = component(cpu, get);
      VPLKIT_CHECK_PARITY(compare_floats(masked(gv, cv, c, k), cv, c.exact ? within_ulps(0) : value_bound, input_text,
                                         c.what[k]));
      std::size_t nans = 0;
      for (float v : gv) nans += std::isnan(v) ? 1 : 0;
      INFO(c.what[k]);
      CHECK(nans == 0);
    }
  }
  // The same bound for the GPU model (gpu_model_float.hpp): the C++ with every division at -2 and
  // +2 ulps and at random offsets within the specification's 2.5 ulps, under the thread's
  // denormal mode (FTZ|DAZ in this program's [ftz-daz] variant).
  std::uint64_t model_seed = 1;
  for (const auto deviation : vplkit_test::gpu_model_deviations) {
    const vplkit_test::gpu_model_scope model(deviation, model_seed++);
    std::vector<heuristics_out> mv(n);
    for (std::size_t i = 0; i < n; ++i) mv[i] = heuristics_of<vplkit_test::gpu_float>(in[i], fs[i]);
    // The model's weights stay in [0, 1]: a division 2 ulps high makes a / a = 1 + 2^-22, the
    // NVIDIA H200's weights above 1 (5826 inputs) before the quotient was capped.
    std::size_t out_of_range = 0;
    for (const auto& o : mv)
      out_of_range += is_weight(o.weights.x) && is_weight(o.weights.y) && is_weight(o.weights.z) && is_weight(o.weights.w) ? 0 : 1;
    INFO("GPU model (" << vplkit_test::to_string(deviation) << "): weights outside [0, 1]");
    CHECK(out_of_range == 0);
    for (const auto& c : columns) {
      for (int k = 0; k < 4; ++k) {
        const auto get = [&c, k](const heuristics_out& o) { return (o.*c.field)[k]; };
        const auto cv = component(cpu, get);
        VPLKIT_CHECK_PARITY(compare_floats(masked(component(mv, get), cv, c, k), cv, c.exact ? within_ulps(0) : value_bound,
                                           input_text,
                                           std::string("GPU model (") + vplkit_test::to_string(deviation) + "): " + c.what[k]));
      }
    }
  }
  // The GPU's own weights: in [0, 1], a partition of unity or both 0.
  std::size_t bad = 0;
  double worst_balance = 0, worst_power = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const float4& w = gpu[i].weights;
    const bool live = cpu[i].weights.x + cpu[i].weights.y > 0.0f;
    bool ok = is_weight(w.x) && is_weight(w.y) && is_weight(w.z) && is_weight(w.w);
    if (live) {
      const double eb = std::abs(static_cast<double>(w.x) + w.y - 1.0);
      const double ep = std::abs(static_cast<double>(w.z) + w.w - 1.0);
      worst_balance = std::max(worst_balance, eb);
      worst_power = std::max(worst_power, ep);
      ok = ok && eb <= partition_tolerance && ep <= partition_tolerance;
    } else {
      ok = ok && w.x == 0.0f && w.y == 0.0f && w.z == 0.0f && w.w == 0.0f;
    }
    if (!ok) {
      if (bad < 10) WARN("GPU weights not a partition of unity: " << input_text(i));
      ++bad;
    }
  }
  std::cout << "  GPU partition of unity: worst |w1 + w2 - 1| balance " << worst_balance / eps
            << " eps, power " << worst_power / eps << " eps\n";
  CHECK(bad == 0);
}

TEST_CASE("heuristics.glsl: the MIS hard cases (both pdfs 0, one infinite, denormal) give the C++ values on the GPU") {
  // (n1, p1, n2, p2, f) rows of mis_hardcases_test.cpp with their exact expected balance weight
  // (and power weight / balance_combined where that test pins them).
  const bool ftz = device_flushes_denormals();
  const float d = denorm_min, m = flt_min, h = 1e38f, big = flt_max;
  struct row {
    float4 nps;
    float f;
    float balance, power, combined;  // NaN: not pinned
    const char* what;
  };
  const float x = qnan;
  std::vector<row> rows = {
      {{1, 0, 1, 0}, 1, 0, 0, 0, "both pdfs 0"},
      {{4, 0, 9, -0.0f}, 5, 0, 0, 0, "both pdfs 0 (-0)"},
      {{1, inf, 1, 0.5f}, 7, 1, 1, 0, "one infinite"},
      {{1, 0.5f, 1, inf}, 7, 0, 0, 0, "one infinite (second)"},
      {{3, inf, 2, big}, 1, 1, 1, 0, "infinite against max"},
      {{1, inf, 1, 1e30f}, 1, 1, 1, 0, "infinite against 1e30"},
      {{1, inf, 1, inf}, 1, 0.5f, 0.5f, 0, "both infinite"},
      {{1, inf, 3, inf}, 1, 0.25f, 0.1f, 0, "both infinite, by counts"},
      {{1, d, 1, d}, d, 0, 0, 0, "denormal pdfs count as 0"},
      {{1, 3 * d, 1, d}, 1, 0, 0, 0, "denormal 3:1 counts as 0"},
      {{1, 3 * m, 1, m}, 1, 0.75f, 0.9f, x, "tiny normal 3:1 (naive power: 0/0)"},
      {{1, m, 2, m}, m, 1.0f / 3.0f, 0.2f, 1.0f / 3.0f, "smallest normal"},
      {{1, 1, 1, d}, 1, 1, 1, x, "denormal against 1"},
      {{1, d, 1, 0}, 1, 0, 0, 0, "a denormal pdf alone: no strategy"},
      {{1, m, 1, 0}, 4, 1, 1, 0, "f / FLT_MIN overflows: guarded to 0"},
      {{d, 1, 1, 0.5f}, 1, 0, 0, 2, "denormal count"},
      {{4, h, 4, h}, h, 0.5f, 0.5f, 0.125f, "1e38 (n p overflows without rescaling)"},
      {{1, big, 3, big}, 1, 0.25f, 0.1f, x, "max, counts 1:3"},
      {{1, 3e37f, 1, 1e37f}, 1, 0.75f, 0.9f, x, "3e37 : 1e37"},
      {{big, big, big, big}, 1, 0.5f, 0.5f, x, "max everywhere"},
      {{0, 1, 3, 0.5f}, 2, 0, 0, x, "n1 = 0"},
      {{0, inf, 2, 1}, 2, 0, 0, 1, "n1 = 0 with p1 infinite (no 0 * inf)"},
      {{2, 1, 0, inf}, 2, 1, 1, 1, "n2 = 0 with p2 infinite"},
      {{0, 1, 0, 1}, 2, 0, 0, 0, "both counts 0"},
      {{1, x, 1, 0.5f}, 1, 0, 0, 2, "NaN pdf"},
      {{x, 1, 1, 0.5f}, 1, 0, 0, 2, "NaN count"},
      {{1, 1, 1, 1}, x, 0.5f, 0.5f, 0, "NaN f"},
      {{1, 1, 1, 1}, inf, 0.5f, 0.5f, 0, "infinite f"},
  };
  std::vector<float4> in;
  std::vector<float> fs;
  for (const auto& r : rows) {
    in.push_back(r.nps);
    fs.push_back(r.f);
  }
  const auto gpu = run_compute<float4>(per_item(R"(#include "vplkit/mis/heuristics.glsl")",
                                            {input(0, in, "vec4 nps"), input(2, fs, "float fs")}, "vec4 result", R"(
  float n1 = nps[i].x, p1 = nps[i].y, n2 = nps[i].z, p2 = nps[i].w;
  result[i] = vec4(vplkit_balance_heuristic(n1, p1, n2, p2), vplkit_power_heuristic(n1, p1, n2, p2),
                   vplkit_balance_combined(fs[i], n1, p1, n2, p2), 0.0);)"),
                                   in.size());
  std::cout << "  the device " << (ftz ? "flushes" : "keeps") << " denormals; every row must give the C++ value\n";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const row& r = rows[i];
    INFO(r.what << ": n1 = " << r.nps.x << ", p1 = " << r.nps.y << ", n2 = " << r.nps.z
                << ", p2 = " << r.nps.w << ", f = " << r.f);
    CHECK(gpu[i].x == Approx(r.balance).epsilon(2e-6).margin(0));
    CHECK(gpu[i].y == Approx(r.power).epsilon(2e-6).margin(0));
    if (!std::isnan(r.combined)) CHECK(gpu[i].z == Approx(r.combined).epsilon(2e-6).margin(0));
    CHECK(std::isfinite(gpu[i].z));
  }
}

namespace {

struct conversion_in {
  float4 geometry;  // pmf, d2_squared, patch_area, cos_theta1
  float4 angle;     // cos_theta, sin_theta, alpha, unused
};

struct conversion_out {
  float4 a;  // vpl_pdf_solid_angle, cosine_pdf_solid_angle(cos), cosine_pdf_as_published, w.gathering
  float4 b;  // w.vpl, -, -, -
};

// The C++ side with T = float (the reference) or T = gpu_float (the GPU model).
template <class T>
conversion_out conversions_of(const conversion_in& c) {
  const float4 &ge = c.geometry, &an = c.angle;
  const auto w = vplkit::mis_weights_as_published(T(an.x), T(an.y), T(an.z));
  conversion_out o;
  o.a = {float(vplkit::vpl_pdf_solid_angle(T(ge.x), T(ge.y), T(ge.z), T(ge.w))),
         float(vplkit::cosine_pdf_solid_angle(T(an.x))), float(vplkit::cosine_pdf_as_published(T(an.x), T(an.y))),
         float(w.gathering)};
  o.b = {float(w.vpl), 0.0f, 0.0f, 0.0f};
  return o;
}

}  // namespace

TEST_CASE("pdf_conversion.glsl: solid-angle densities and the as-published weights") {
  device_flushes_denormals();  // prints whether it does: the reference is the same either way
  std::vector<conversion_in> in;
  input_rng g(12);
  auto maybe_special = [&](float v) {
    return g.uniform() < 0.1 ? specials()[g.index(specials().size())] : v;
  };
  for (int i = 0; i < 200000; ++i) {
    const float pmf = maybe_special(log_uniform(g, -30.0, 0.0));
    const float d2 = maybe_special(log_uniform(g, -38.0, 38.0));
    const float area = maybe_special(log_uniform(g, -38.0, 38.0));
    const float c1 = maybe_special(g.uniform() < 0.5 ? static_cast<float>(g.uniform())
                                                     : log_uniform(g, -38.0, 0.0));
    const double theta = 3.14159265358979323846 * g.uniform();
    const float ct = maybe_special(static_cast<float>(std::cos(theta)));
    const float st = maybe_special(static_cast<float>(std::sin(theta)));
    const float alpha = maybe_special(log_uniform(g, -38.0, 0.0));
    in.push_back({{pmf, d2, area, c1}, {ct, st, alpha, 0.0f}});
  }
  const std::size_t n_random = in.size();
  // The sweep of mis_hardcases_test.cpp: vpl_pdf(a, b, c, d), as_published(d, b, a), pdfs of a.
  for (float a : specials())
    for (float b : specials())
      for (float c : specials())
        for (float d : {-1.0f, 0.0f, 1e-30f, 0.3f, 1.0f, inf, qnan}) {
          in.push_back({{a, b, c, d}, {d, b, a, 0.0f}});
        }
  const std::size_t n = in.size();
  const auto gpu = run_compute<conversion_out>(per_item(R"(
#include "vplkit/mis/pdf_conversion.glsl"
struct I { vec4 geometry; vec4 angle; };
struct R { vec4 a; vec4 b; };
)",
                                                        {input(0, in, "I data")}, "R result", R"(
  vec4 g = data[i].geometry, a = data[i].angle;
  vplkit_mis_weight_pair w = vplkit_mis_weights_as_published(a.x, a.y, a.z);
  result[i].a = vec4(vplkit_vpl_pdf_solid_angle(g.x, g.y, g.z, g.w),
                     vplkit_cosine_pdf_solid_angle(a.x),
                     vplkit_cosine_pdf_as_published(a.x, a.y), w.gathering);
  result[i].b = vec4(w.vpl, 0.0, 0.0, 0.0);)"),
                                               n);
  std::vector<conversion_out> cpu(n);
  for (std::size_t i = 0; i < n; ++i) cpu[i] = conversions_of<float>(in[i]);
  auto geometry_text = [&](std::size_t k) {
    const float4& ge = in[k].geometry;
    return "pmf = " + show(ge.x) + ", d2^2 = " + show(ge.y) + ", A = " + show(ge.z) +
           ", cos1 = " + show(ge.w) + (k < n_random ? " [random]" : " [special sweep]");
  };
  auto angle_text = [&](std::size_t k) {
    const float4& an = in[k].angle;
    return "cos = " + show(an.x) + ", sin = " + show(an.y) + ", alpha = " + show(an.z) +
           (k < n_random ? " [random]" : " [special sweep]");
  };
  auto col = [&](const std::vector<conversion_out>& v, int which) {
    return component(v, [which](const conversion_out& o) { return (which < 4 ? o.a : o.b)[which % 4]; });
  };
  // vpl_pdf: two products of mantissas, one division (divisor in [1, 4)) and an exact power of
  // two: the value bound.
  VPLKIT_CHECK_PARITY(compare_floats(col(gpu, 0), col(cpu, 0), value_bound, geometry_text,
                                     "vplkit_vpl_pdf_solid_angle"));
  // One multiply by 1/pi, and cos * sin * (1/pi): exact on an IEEE device; 1 ulp allows a GPU
  // that fuses nothing but rounds its multiplies differently (none known), or a denormal flush.
  VPLKIT_CHECK_PARITY(compare_floats(col(gpu, 1), col(cpu, 1), within_ulps(0) | within_abs(flt_min),
                                     angle_text, "vplkit_cosine_pdf_solid_angle"));
  VPLKIT_CHECK_PARITY(compare_floats(col(gpu, 2), col(cpu, 2), within_ulps(1) | within_abs(flt_min),
                                     angle_text, "vplkit_cosine_pdf_as_published"));
  VPLKIT_CHECK_PARITY(compare_floats(col(gpu, 3), col(cpu, 3), value_bound, angle_text,
                                     "vplkit_mis_weights_as_published .gathering"));
  VPLKIT_CHECK_PARITY(compare_floats(col(gpu, 4), col(cpu, 4), value_bound, angle_text,
                                     "vplkit_mis_weights_as_published .vpl"));
  // The GPU model (gpu_model_float.hpp) within the same bounds.
  std::uint64_t model_seed = 7;
  for (const auto deviation : vplkit_test::gpu_model_deviations) {
    const vplkit_test::gpu_model_scope model(deviation, model_seed++);
    std::vector<conversion_out> mv(n);
    for (std::size_t i = 0; i < n; ++i) mv[i] = conversions_of<vplkit_test::gpu_float>(in[i]);
    std::size_t out_of_range = 0;  // the as-published weights in [0, 1] (as in the heuristics test)
    for (const auto& o : mv) out_of_range += is_weight(o.a.w) && is_weight(o.b.x) ? 0 : 1;
    INFO("GPU model (" << vplkit_test::to_string(deviation) << "): as-published weights outside [0, 1]");
    CHECK(out_of_range == 0);
    const std::string m = std::string("GPU model (") + vplkit_test::to_string(deviation) + "): ";
    VPLKIT_CHECK_PARITY(compare_floats(col(mv, 0), col(cpu, 0), value_bound, geometry_text, m + "vpl_pdf_solid_angle"));
    VPLKIT_CHECK_PARITY(compare_floats(col(mv, 3), col(cpu, 3), value_bound, angle_text, m + "as_published .gathering"));
    VPLKIT_CHECK_PARITY(compare_floats(col(mv, 4), col(cpu, 4), value_bound, angle_text, m + "as_published .vpl"));
  }
  // Never NaN on the GPU; pdfs >= 0; the paper's two weights add up to 1 or are both 0.
  std::size_t bad = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const float4 &a = gpu[i].a, &b = gpu[i].b;
    const bool live = cpu[i].a.w + cpu[i].b.x > 0.0f;
    bool ok = a.x >= 0.0f && a.y >= 0.0f && a.z >= 0.0f && is_weight(a.w) && is_weight(b.x);
    ok = ok && (live ? std::abs(static_cast<double>(a.w) + b.x - 1.0) <= partition_tolerance
                     : a.w == 0.0f && b.x == 0.0f);
    if (!ok) {
      if (bad < 10) WARN("GPU densities / weights invalid: " << geometry_text(i) << "; " << angle_text(i));
      ++bad;
    }
  }
  CHECK(bad == 0);
}

TEST_CASE("pdf_conversion.glsl: the special cases of vpl_pdf_solid_angle") {
  const bool ftz = device_flushes_denormals();
  struct row {
    float4 g;
    float want;
    const char* what;
  };
  const float x = qnan;
  const std::vector<row> rows = {
      {{0.5f, 4.0f, 2.0f, 0.5f}, 2.0f, "0.5 * (4 / 2) / 0.5"},
      {{0.0f, 4.0f, 2.0f, 0.5f}, 0.0f, "pmf 0"},
      {{0.5f, 4.0f, 2.0f, -0.5f}, 0.0f, "behind the patch"},
      {{0.5f, 4.0f, 2.0f, 0.0f}, 0.0f, "edge-on"},
      {{0.5f, 0.0f, 2.0f, 0.5f}, 0.0f, "d2 = 0"},
      {{0.5f, 4.0f, 0.0f, 0.5f}, inf, "zero area"},
      {{0.5f, 4.0f, inf, 0.5f}, 0.0f, "infinite area"},
      {{0.5f, inf, 2.0f, 0.5f}, inf, "infinite distance"},
      {{x, 4.0f, 2.0f, 0.5f}, 0.0f, "NaN pmf"},
      {{0.5f, x, 2.0f, 0.5f}, 0.0f, "NaN d2"},
      {{0.5f, 4.0f, x, 0.5f}, 0.0f, "NaN area"},
      {{0.5f, 4.0f, 2.0f, x}, 0.0f, "NaN cos"},
      {{0.5f, 4.0f, -2.0f, 0.5f}, 0.0f, "negative area"},
      {{1.0f, 1e38f, 1e38f, 1.0f}, 1.0f, "1e38 / 1e38 (divisor above 2^126)"},
      {{1.0f, 3e38f, 1e-30f, 0.5f}, inf, "overflow"},
      {{1e-10f, 1e-30f, 1e30f, 1.0f}, 0.0f, "underflow"},
      {{1.0f, 1.0f, 1.0f, 1e-30f}, 1e30f, "grazing"},
      {{0.5f, 3e38f, 1e-30f, inf}, 0.0f, "infinite cos (C++ gave inf / inf = NaN before the fix)"},
      {{0.5f, 4.0f, 2.0f, inf}, 0.0f, "infinite cos"},
  };
  std::vector<float4> in;
  for (const auto& r : rows) in.push_back(r.g);
  const auto gpu = run_compute<float>(per_item(R"(#include "vplkit/mis/pdf_conversion.glsl")", {input(0, in, "vec4 g")},
                                              "float p", "p[i] = vplkit_vpl_pdf_solid_angle(g[i].x, g[i].y, g[i].z, g[i].w);"),
                                     in.size());
  (void)ftz;  // no denormals here
  for (std::size_t i = 0; i < rows.size(); ++i) {
    INFO(rows[i].what);
    CHECK(gpu[i] == Approx(rows[i].want).epsilon(2e-6).margin(0));
    CHECK(gpu[i] == Approx(vplkit::vpl_pdf_solid_angle(in[i].x, in[i].y, in[i].z, in[i].w)).epsilon(2e-6).margin(0));
  }
}

TEST_CASE("heuristics.glsl: the GLSL-only helpers mis_div and mis_is_nan") {
  // vplkit_mis_div(x, y) must give x / y for every y, including y >= 2^126 (where a GPU's
  // reciprocal underflows) and denormal y; vplkit_mis_is_nan must be isnan on the bits.
  const bool ftz = device_flushes_denormals();
  std::vector<float> xy;
  input_rng g(13);
  auto any_float = [&]() {
    const double r = g.uniform();
    if (r < 0.1) return specials()[g.index(specials().size())];
    if (r < 0.3) return log_uniform(g, 37.9, 38.6);  // the range above 2^126 ~ 8.5e37
    const float v = log_uniform(g, -45.0, 38.6);     // denormals included
    return g.uniform() < 0.3 ? -v : v;
  };
  for (int i = 0; i < 100000; ++i) {
    xy.push_back(any_float());
    xy.push_back(any_float());
  }
  // NaN payloads and signs: every one must read as NaN; infinities must not.
  for (std::uint32_t bits : {0x7FC00000u, 0xFFC00000u, 0x7F800001u, 0xFF800001u, 0x7FFFFFFFu,
                             0x7F800000u, 0xFF800000u, 0x7F7FFFFFu}) {
    xy.push_back(float_of(bits));
    xy.push_back(1.0f);
  }
  const std::size_t n = xy.size() / 2;
  struct f2 {
    float q, nan;
  };
  const auto gpu = run_compute<f2>(
      per_item(R"(#include "vplkit/mis/heuristics.glsl")", {input(0, xy, "vec2 xy")}, "vec2 result",
               "result[i] = vec2(vplkit_mis_div(xy[i].x, xy[i].y), vplkit_mis_is_nan(xy[i].x) ? 1.0 : 0.0);"),
      n);
  std::vector<float> gq(n), cq(n), gn(n), cn(n);
  {
    cpu_denormals_like_device mode(ftz);
    for (std::size_t i = 0; i < n; ++i) {
      gq[i] = gpu[i].q;
      cq[i] = xy[2 * i] / xy[2 * i + 1];
      gn[i] = gpu[i].nan;
      cn[i] = std::isnan(xy[2 * i]) ? 1.0f : 0.0f;
    }
  }
  auto text = [&](std::size_t k) { return "x = " + show(xy[2 * k]) + ", y = " + show(xy[2 * k + 1]); };
  // GLSL specifies division to 2.5 ulp (in range, which the helper guarantees); an IEEE device
  // is exact. A denormal quotient may flush on a GPU.
  VPLKIT_CHECK_PARITY(compare_floats(gq, cq, within_ulps(3) | within_abs(flt_min), text,
                                     "vplkit_mis_div vs x / y"));
  VPLKIT_CHECK_PARITY(compare_floats(gn, cn, within_ulps(0), text, "vplkit_mis_is_nan vs isnan"));
}
