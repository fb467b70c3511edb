// SPDX-License-Identifier: MIT
#pragma once
// Helpers shared by the distribution parity tests (not a test program: only parity_*.cpp files
// become programs): the packing of several distributions into the buffers the test kernels read,
// and a host driver for the GPU CDF build kernel glsl/vplkit/distribution/cdf_build.comp with the
// comparisons that measure it. Weights: weight_generators.hpp (portable streams).
#include <cdf_build_kernel.hpp>
#include <parity_harness.hpp>
#include <weight_generators.hpp>

#include <vplkit/distribution/defensive_mixture.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/distribution/face_roulette.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace vplkit::parity::dist {

using u32 = std::uint32_t;

using vplkit_test::splitmix_rng;
using namespace vplkit_test::portable;  // the weight generators

// ---- several distributions in the buffers the test kernels read --------------------------------
// std430 of vplkit_discrete_cdf { uint id; uint size; uint guide_size; float total; }.
struct gpu_desc {
  u32 id, size, guide_size;
  float total;
};
static_assert(sizeof(gpu_desc) == 16, "std430 vplkit_discrete_cdf");

// std430 of vplkit_defensive_mixture / vplkit_face_roulette (all members 4-byte scalars).
struct gpu_mixture {
  gpu_desc learned, fallback;
  float effective_eps, fallback_scale, learned_scale;
};
static_assert(sizeof(gpu_mixture) == 44, "std430 vplkit_defensive_mixture");
struct gpu_roulette {
  gpu_desc front, back;
  float b_front, b_back, front_scale, back_scale;
};
static_assert(sizeof(gpu_roulette) == 48, "std430 vplkit_face_roulette");

struct packed_cdfs {
  std::vector<float> cdf;
  std::vector<u32> guide;
  std::vector<u32> offsets;  // (cdf offset, guide offset) per distribution
  std::vector<gpu_desc> descs;

  u32 add_arrays(const std::vector<float>& c, const std::vector<u32>& g, u32 n, u32 m, float total) {
    const u32 id = u32(descs.size());
    offsets.push_back(u32(cdf.size()));
    offsets.push_back(u32(guide.size()));
    cdf.insert(cdf.end(), c.begin(), c.end());
    guide.insert(guide.end(), g.begin(), g.end());
    descs.push_back({id, n, m, total});
    return id;
  }
  u32 add(const discrete_cdf<float>& d) {
    return add_arrays(d.cdf(), d.guide(), u32(d.size()), u32(d.guide_size()), d.total());
  }
  gpu_mixture add(const defensive_mixture<float>& m) {
    const u32 l = add(m.learned());
    const u32 f = add(m.fallback());
    return {descs[l], descs[f], m.effective_eps(), m.fallback_scale(), m.learned_scale()};
  }
  gpu_roulette add(const face_roulette<float>& r) {
    const u32 f = add(r.front());
    const u32 b = add(r.back());
    return {descs[f], descs[b], r.front_probability(), r.back_probability(), r.front_scale(), r.back_scale()};
  }
  // Each distribution `named[k].*part`, in order: the GPU handles of all of them.
  template <class Named, class D>
  auto add_each(const std::vector<Named>& named, D Named::*part) {
    std::vector<decltype(add(std::declval<const D&>()))> handles;
    for (const Named& x : named) handles.push_back(add(x.*part));
    return handles;
  }
  std::vector<ssbo> inputs() const {
    return {input(2, cdf), input(3, guide), input(4, offsets), input(5, descs)};
  }
};

// A kernel over packed CDFs: `include` (a pack file), the accessors over the packed buffers
// (bindings 2 to 5), then `types`; the caller's buffers (bindings 0, 1 and 6 up), its output and
// its per-item body (kernel_call).
inline kernel_call cdf_kernel(const packed_cdfs& packed, const std::string& include, const std::string& types,
                              std::vector<ssbo> buffers, const std::string& output_glsl, const std::string& body) {
  std::vector<ssbo> inputs = packed.inputs();
  for (ssbo& b : buffers) inputs.push_back(std::move(b));
  return per_item("#include \"" + include + "\"\n" + R"(
layout(std430, binding = 2) readonly buffer Cdfs { float cdfs[]; };
layout(std430, binding = 3) readonly buffer Guides { uint guides[]; };
layout(std430, binding = 4) readonly buffer Offsets { uvec2 offsets[]; };
layout(std430, binding = 5) readonly buffer Descs { vplkit_discrete_cdf descs[]; };
float vplkit_load_cdf(uint d, uint i) { return cdfs[offsets[d].x + i]; }
uint vplkit_load_guide(uint d, uint j) { return guides[offsets[d].y + j]; }
)" + types,
                  std::move(inputs), output_glsl, body);
}

// The mixtures of the defensive-mixture tests: learned weights with holes (median-filled CDFs
// leave zeros) and zero runs, a uniform fallback over "valid" entries (0/1 weights, 78 % valid,
// drawn from g), as in docs/math.md section 3, defensive mixing; one mixture per eps, then an empty
// learned part, a default fallback, and both empty.
struct named_mixture {
  std::string name;
  defensive_mixture<float> m;
};
inline std::vector<named_mixture> test_mixtures(u32 n, std::uint64_t learned_seed, splitmix_rng& g,
                                                const std::vector<float>& eps_list) {
  std::vector<float> valid(n);
  const discrete_cdf<float> learned(zero_run_weights(n, 2000, learned_seed));
  for (float& v : valid) v = (g.next_u32() % 100u) < 78u ? 1.0f : 0.0f;
  const discrete_cdf<float> fallback(valid), none;
  const discrete_cdf<float> zeros(std::vector<float>(n, 0.0f));
  std::vector<named_mixture> mixtures;
  for (float eps : eps_list) mixtures.push_back({"eps = " + show(eps), defensive_mixture<float>(learned, fallback, eps)});
  mixtures.push_back({"learned empty, eps = 0.1", defensive_mixture<float>(zeros, fallback, 0.1f)});
  mixtures.push_back({"fallback default, eps = 0.1", defensive_mixture<float>(learned, none, 0.1f)});
  mixtures.push_back({"both empty", defensive_mixture<float>(zeros, none, 0.3f)});
  return mixtures;
}

// ---- the GPU build ------------------------------------------------------------------------------
struct build_options {
  bool float_float = false;
  unsigned local_size = 256;
  unsigned items = 4;
  unsigned max_groups = 65535;  // fewer than the block count exercises the kernels' stride loops
  bool program_per_pass = false;  // VPLKIT_CDF_BUILD_PASS=k instead of the uniform `pass`
  std::string text() const {
    std::ostringstream s;
    s << (float_float ? "float-float" : "double") << ", local " << local_size << " x " << items;
    if (max_groups != 65535) s << ", <= " << max_groups << " groups";
    if (program_per_pass) s << ", one program per pass";
    return s.str();
  }
};

// The kernel's per-distribution record (its sum is a double, or (hi, lo) floats in the same 8
// bytes with VPLKIT_CDF_BUILD_FLOAT_FLOAT; only total and zeroed are read here).
using build_info = vplkit::gpu::cdf_build_info;

struct build_result {
  std::vector<float> cdf;    // D * (n + 1)
  std::vector<u32> guide;    // D * (m + 1)
  std::vector<build_info> info;
  double ms = 0;             // wall time of the six dispatches (llvmpipe: glFinish-bracketed)
};

inline const gl::program& build_program(const build_options& o, int pass) {
  std::ostringstream pre;
  pre << "#define VPLKIT_CDF_BUILD_LOCAL_SIZE " << o.local_size << "\n"
      << "#define VPLKIT_CDF_BUILD_ITEMS " << o.items << "\n";
  if (o.float_float) pre << "#define VPLKIT_CDF_BUILD_FLOAT_FLOAT\n";
  if (pass > 0) pre << "#define VPLKIT_CDF_BUILD_PASS " << pass << "\n";
  return pack_kernel("vplkit/distribution/cdf_build.comp", pre.str());
}

// Builds `count` distributions of n weights each (weights.size() == count * n).
inline build_result gpu_build(const std::vector<float>& weights, u32 n, u32 count,
                              const build_options& o = {}) {
  context();
  const u32 m = u32(discrete_guide_size(n));
  const std::size_t block = std::size_t(o.local_size) * o.items;
  const u32 blocks = u32((n + block - 1) / block);
  const u32 groups = std::min<u32>(blocks, o.max_groups);
  const u32 guide_groups = std::min<u32>(u32((std::size_t(m) + block) / block), o.max_groups);
  // Everything starts as 0xFF bytes: the kernel must need no clearing.
  gl::buffer w = gl::buffer::from_vector(weights);
  gl::buffer cdf = gl::buffer::filled(std::size_t(count) * (n + 1) * 4, 0xFF);
  gl::buffer guide = gl::buffer::filled(std::size_t(count) * (m + 1) * 4, 0xFF);
  gl::buffer blk = gl::buffer::filled(std::size_t(count) * blocks * sizeof(vplkit::gpu::cdf_build_block), 0xFF);
  gl::buffer info = gl::buffer::filled(std::size_t(count) * sizeof(build_info), 0xFF);
  gl::buffer params = gl::buffer::filled(sizeof(vplkit::gpu::cdf_build_params), 0);
  vplkit_test::bind_cdf_build(w, cdf, guide, blk, info, params);
  for (int pass = 1; pass <= 6; ++pass) build_program(o, o.program_per_pass ? pass : 0);
  glFinish();
  const auto t0 = std::chrono::steady_clock::now();
  for (int pass = 1; pass <= 6; ++pass) {
    vplkit::gpu::cdf_build_params p{};
    p.n = n;
    p.pass = u32(pass);
    params.write_bytes(&p, 0, sizeof p);
    const u32 g = pass == 2 || pass == 4 ? 1u : pass == 6 ? guide_groups : groups;
    gl::dispatch(build_program(o, o.program_per_pass ? pass : 0), g, 1, count);
    if (std::getenv("VPLKIT_CDF_BUILD_PROFILE")) {
      glFinish();
      std::cout << "  pass " << pass << ": "
                << std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count()
                << " ms\n";
    }
  }
  glFinish();
  const auto t1 = std::chrono::steady_clock::now();
  build_result r;
  r.ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
  r.cdf = cdf.read<float>();
  r.guide = guide.read<u32>();
  r.info = info.read<build_info>();
  return r;
}

// ---- measuring a built CDF ----------------------------------------------------------------------
// Checks what the kernel promises on one distribution's arrays; returns "" or the first violation.
inline std::string check_invariants(const float* cdf, const u32* guide, const float* w, u32 n,
                                    bool empty) {
  const u32 m = u32(discrete_guide_size(n));
  std::ostringstream s;
  if (bits_of(cdf[0]) != 0u) s << "cdf[0] = " << show(cdf[0]) << " (not +0); ";
  if (cdf[n] != (empty ? 0.0f : 1.0f)) s << "cdf[n] = " << show(cdf[n]) << "; ";
  for (u32 i = 0; i < n && s.str().empty(); ++i) {
    if (!(cdf[i + 1] >= cdf[i])) s << "not monotone at " << i << ": " << show(cdf[i]) << " > " << show(cdf[i + 1]);
    const bool zero = !(w[i] > 0.0f && w[i] <= std::numeric_limits<float>::max());
    if (zero && bits_of(cdf[i + 1]) != bits_of(cdf[i])) {
      s << "zero weight " << i << " has width: " << show(cdf[i]) << " -> " << show(cdf[i + 1]);
    }
  }
  if (!s.str().empty()) return s.str();
  // guide[j] = the largest i in [0, n - 1] with cdf[i] <= j / m (all 0 when empty).
  u32 i = 0;
  for (u32 j = 0; j <= m; ++j) {
    u32 expect = 0;
    if (!empty) {
      const double x = double(j) / double(m);
      while (i + 1 < n && double(cdf[i + 1]) <= x) ++i;
      expect = i;
    }
    if (guide[j] != expect) {
      s << "guide[" << j << "] = " << guide[j] << ", expected " << expect;
      return s.str();
    }
  }
  return "";
}

struct cdf_difference {
  std::size_t differing = 0;   // cdf values that are not bit-identical
  double max_abs = 0;          // max |a[i] - b[i]|
  double max_ulps = 0;
  std::size_t worst = 0;
  double disagreement = 0;     // measure of the u in [0, 1) that map to different indices
  double tv = 0;               // total-variation distance of the two pmfs
};

inline cdf_difference compare_cdfs(const float* a, const float* b, u32 n) {
  cdf_difference d;
  for (u32 i = 0; i <= n; ++i) {
    if (bits_of(a[i]) != bits_of(b[i])) ++d.differing;
    const double diff = std::fabs(double(a[i]) - double(b[i]));
    if (diff > d.max_abs) {
      d.max_abs = diff;
      d.worst = i;
    }
    d.max_ulps = std::max(d.max_ulps, ulp_distance(a[i], b[i]));
  }
  // Sampling maps u to i when a[i] <= u < a[i + 1]: the u that agree are the overlaps of the two
  // bins of each index. Summed per index, small terms, in double.
  for (u32 i = 0; i < n; ++i) {
    const double wa = double(a[i + 1]) - double(a[i]);
    const double wb = double(b[i + 1]) - double(b[i]);
    const double overlap = std::max(0.0, std::min(double(a[i + 1]), double(b[i + 1])) -
                                             std::max(double(a[i]), double(b[i])));
    d.disagreement += wa - overlap;
    d.tv += 0.5 * std::fabs(wa - wb);
  }
  return d;
}

inline std::string describe(const cdf_difference& d) {
  std::ostringstream s;
  s << std::setprecision(3) << d.differing << " cdf values differ, max |diff| " << d.max_abs
    << " (" << d.max_ulps << " ulps, at cdf[" << d.worst << "]), u mapped differently "
    << d.disagreement << ", TV " << d.tv;
  return s.str();
}

// The bounds of the build tests (parity_distribution_build_test.cpp explains them): every value
// within 1 ulp of the C++ build, at most 64 values differing, at most 64 * 2^-24 of [0, 1) sampled
// differently; the kernel's promises (check_invariants), total within 1 ulp, and where the cdfs
// agree the guides too. Returns the measured difference.
constexpr std::size_t build_max_differing = 64;
constexpr double build_max_disagreement = 64 * 0x1p-24;

inline cdf_difference check_build_bounds(const build_result& g, const std::vector<float>& w,
                                         const discrete_cdf<float>& c) {
  const u32 n = u32(w.size());
  CHECK(check_invariants(g.cdf.data(), g.guide.data(), w.data(), n, c.empty()) == "");
  CHECK(ulp_distance(g.info[0].total, c.total()) <= 1.0);
  const cdf_difference d = compare_cdfs(g.cdf.data(), c.cdf().data(), n);
  CHECK(d.max_ulps <= 1.0);
  CHECK(d.differing <= build_max_differing);
  CHECK(d.disagreement <= build_max_disagreement);
  // Where the cdfs are the same, so must the guides be (both are functions of the cdf).
  if (d.differing == 0) CHECK(g.guide == c.guide());
  return d;
}

// float(P_i / total) from the weights summed in double with Neumaier compensation (the C++
// discrete_cdf<double>), rounded once to float: the nearest float to the exact quotient except
// where that lies within ~2^-52 of a rounding tie. Bad weights count as 0.
inline std::vector<float> near_exact_cdf(const float* w, u32 n) {
  std::vector<double> wd(w, w + n);
  for (double& x : wd) x = (x >= 0.0 && x <= double(std::numeric_limits<float>::max())) ? x : 0.0;
  const discrete_cdf<double> c(wd);
  std::vector<float> out(n + 1);
  for (u32 i = 0; i <= n; ++i) out[i] = float(c.cdf()[i]);
  return out;
}

}  // namespace vplkit::parity::dist
