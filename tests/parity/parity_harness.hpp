// SPDX-License-Identifier: MIT
#pragma once
// Parity-test harness: run a GLSL kernel that #includes the pack on the headless GL context and
// compare what it wrote with the C++ templates' answer. A parity test is data (inputs, the GLSL
// per-item statement, the C++ reference) and checks; everything else is here.
//
//   kernel_call k;
//   k.source = R"(#include "vplkit/core/constants.glsl")";
//   k.inputs = {input(0, us, "float u")};          // the harness declares the buffer ...
//   k.output_glsl = "float result";                // ... and the output (binding 1 by default)
//   k.body = "result[i] = u[i] * vplkit_PI;";       // main(): `i` is the item, < VPLKIT_PARITY_COUNT
//   const auto gpu = run_compute<float>(k, us.size());
//   VPLKIT_CHECK_PARITY(compare_floats(gpu, cpu, within_ulps(2),
//       [&](std::size_t i) { return "u = " + show(us[i]); }, "u * pi"));
//
// What the harness adds to the kernel, after its own #version 430 line: `uniform uint
// vplkit_parity_count;` (the number of items, set before each dispatch) with `#define
// VPLKIT_PARITY_COUNT vplkit_parity_count`, the call's `defines`, and `layout(local_size_x = ..)
// in;`; then `source`; then the buffers and uniform blocks given a GLSL declaration; then, with
// `body`, a main() that runs `body` once per item. Without `body`, `source` is the whole kernel
// (it bounds its items with `if (i >= VPLKIT_PARITY_COUNT) return;`). The count is not a constant
// expression (no array sizes from it): being a uniform, it keeps the text the same for every
// count, so each kernel compiles once per process (a GPU driver spends tens of seconds on each
// distinct text on a cold shader cache). VPLKIT_PARITY_PROGRAM_LOG=1 prints one line per program
// compiled and the total at the end of the run. Includes
// resolve against the pack root (VPLKIT_GLSL_SOURCE_DIR) with vplkit's include_resolver, so
// compile errors name the pack file and line. Every output buffer starts filled with 0xFF bytes
// (NaN floats, ~0u integers): an element the kernel never wrote fails.
// Buffer element types must match std430 (scalars, vec2, vec4, or hand-padded structs; see
// std430_types.hpp). Several results per item come back as one struct, or as several outputs
// (kernel_call::more_outputs, read with run_kernel).
//
// The pack's own kernels (glsl/vplkit/**/*.comp) run through pack_kernel() and the bindings of
// gl_kernels.hpp, with their parameter headers (*_params.h) as the uniform blocks.
#include <float_bits.hpp>
#include <gl_kernels.hpp>
#include <random_streams.hpp>
#include <std430_types.hpp>
#include <value_text.hpp>

#include <headless_gl/compute.hpp>
#include <headless_gl/context.hpp>

#include <catch2/catch.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <iostream>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

namespace vplkit::parity {

// The helpers every parity test uses, under the harness's name.
using vplkit_test::bits_of;
using vplkit_test::f4;
using vplkit_test::float4;
using vplkit_test::float_of;
using vplkit_test::int4;
using vplkit_test::show;
using vplkit_test::show2;
using vplkit_test::show3;
using vplkit_test::showi3;
using vplkit_test::ulp_distance;
using vplkit_test::xyz;

// The process-wide context, created on first use (prints "parity: OpenGL ... via ..." once).
// Kept alive until exit on purpose: tearing Mesa down from a static destructor races its own
// atexit handlers.
gl::headless_context& context();

// True on Mesa's CPU renderers, whose division and sqrt are correctly rounded.
bool software_renderer();

// A pack kernel file (vplkit_test::pack_kernel) on the parity context.
const gl::program& pack_kernel(const std::string& file, const std::string& defines = "");

// ---- kernels written by the tests ---------------------------------------------------------------
struct ssbo {
  unsigned binding = 0;
  std::vector<unsigned char> bytes;
  std::string glsl;  // "vec4 q": the harness declares `readonly buffer { vec4 q[]; }`; "": the source does
};

template <class T>
ssbo input(unsigned binding, const std::vector<T>& data, std::string glsl = {}) {
  static_assert(std::is_trivially_copyable<T>::value, "SSBO elements must be trivially copyable");
  ssbo s;
  s.binding = binding;
  const auto* p = reinterpret_cast<const unsigned char*>(data.data());
  s.bytes.assign(p, p + data.size() * sizeof(T));
  s.glsl = std::move(glsl);
  return s;
}

// A uniform block (std140): `glsl` is the block's name and members, e.g. "Params { vec4 a; int n; }".
struct uniform_block {
  unsigned binding = 0;
  std::vector<unsigned char> bytes;
  std::string glsl;
};

template <class P>
uniform_block uniform(unsigned binding, const P& block, std::string glsl = {}) {
  static_assert(std::is_trivially_copyable<P>::value, "a uniform block must be trivially copyable");
  uniform_block u;
  u.binding = binding;
  const auto* p = reinterpret_cast<const unsigned char*>(&block);
  u.bytes.assign(p, p + sizeof block);
  u.glsl = std::move(glsl);
  return u;
}

// A further output buffer: `count` elements of `element_size` bytes (0: the call's count).
struct output {
  unsigned binding = 0;
  std::size_t element_size = 0;
  std::string glsl;  // as for ssbo, declared writeonly
  std::size_t count = 0;
};

template <class T>
output output_of(unsigned binding, std::string glsl = {}, std::size_t count = 0) {
  static_assert(std::is_trivially_copyable<T>::value, "SSBO elements must be trivially copyable");
  return {binding, sizeof(T), std::move(glsl), count};
}

struct kernel_call {
  std::string name = "parity_kernel.comp";  // labels the kernel in compile errors
  std::string source;                       // no #version: the harness writes it
  std::string body;                         // main()'s statements for item `uint i` (see above)
  std::array<unsigned, 3> local_size{64, 1, 1};
  std::array<unsigned, 3> groups{0, 0, 0};  // {0,0,0}: ceil(count / local_size x) groups in x
  std::vector<ssbo> inputs;
  std::vector<uniform_block> uniforms;
  unsigned output_binding = 1;
  std::string output_glsl;                  // as for ssbo, declared writeonly
  std::vector<output> more_outputs;
  std::string defines;                      // extra preamble, e.g. "#define N 4\n"
  std::string version = "#version 430";
};

// The common kernel in one expression: `source` (includes, types), the inputs, the output at
// binding 1 declared `output_glsl`, and the statements run for item `i`.
inline kernel_call per_item(std::string source, std::vector<ssbo> inputs, std::string output_glsl, std::string body) {
  kernel_call k;
  k.source = std::move(source);
  k.inputs = std::move(inputs);
  k.output_glsl = std::move(output_glsl);
  k.body = std::move(body);
  return k;
}

// What one run read back: every output buffer, by binding.
class kernel_outputs {
public:
  std::map<unsigned, std::vector<unsigned char>> bytes;

  template <class T>
  std::vector<T> get(unsigned binding) const {
    static_assert(std::is_trivially_copyable<T>::value, "output must be trivially copyable");
    const std::vector<unsigned char>& b = bytes.at(binding);
    std::vector<T> out(b.size() / sizeof(T));
    if (!out.empty()) std::memcpy(out.data(), b.data(), out.size() * sizeof(T));
    return out;
  }
};

// Runs `call` over `count` items: the main output holds `count` elements of `out_element_size`
// bytes. Programs are cached by their final source text (which the count is not part of), so
// repeating a call, with any count, does not recompile.
kernel_outputs run_kernel(const kernel_call& call, std::size_t count, std::size_t out_element_size);

template <class Out>
std::vector<Out> run_compute(const kernel_call& call, std::size_t count) {
  return run_kernel(call, count, sizeof(Out)).get<Out>(call.output_binding);
}

template <class Out>
std::vector<Out> run_compute(const std::string& source, std::array<unsigned, 3> local_size,
                             std::vector<ssbo> inputs, unsigned output_binding, std::size_t count) {
  kernel_call call;
  call.source = source;
  call.local_size = local_size;
  call.inputs = std::move(inputs);
  call.output_binding = output_binding;
  return run_compute<Out>(call, count);
}

// ---- comparisons ------------------------------------------------------------------------------
// A float result passes when ANY stated part of its bound holds: ulp distance <= ulps, or
// |gpu - cpu| <= rel * |cpu|, or |gpu - cpu| <= abs. Parts left at their default (-1) are off.
// Both NaN counts as equal; infinities must match exactly.
struct float_bound {
  double ulps = -1;
  double rel = -1;
  double abs = -1;
  std::string text() const;
};
inline float_bound within_ulps(double n) { float_bound b; b.ulps = n; return b; }
inline float_bound within_rel(double r) { float_bound b; b.rel = r; return b; }
inline float_bound within_abs(double a) { float_bound b; b.abs = a; return b; }
inline float_bound operator|(float_bound a, const float_bound& b) {
  if (b.ulps >= 0) a.ulps = b.ulps;
  if (b.rel >= 0) a.rel = b.rel;
  if (b.abs >= 0) a.abs = b.abs;
  return a;
}

struct comparison {
  bool ok = false;
  std::size_t count = 0;
  std::size_t failures = 0;
  std::size_t worst_index = 0;
  double worst_ulps = 0, worst_abs = 0, worst_rel = 0;  // floats only
  std::string report;  // multi-line, printed by VPLKIT_CHECK_PARITY
};

using describe_fn = std::function<std::string(std::size_t)>;

comparison compare_floats(const std::vector<float>& gpu, const std::vector<float>& cpu,
                          const float_bound& bound, const describe_fn& describe = {},
                          const std::string& what = {});
// Double reference: ulps are counted to float(cpu), rel/abs against the double value.
comparison compare_floats(const std::vector<float>& gpu, const std::vector<double>& cpu,
                          const float_bound& bound, const describe_fn& describe = {},
                          const std::string& what = {});

// compare_floats plus a line with the largest absolute difference (the harness reports the worst
// ulp and relative differences; for quantities that cancel toward 0 the absolute one tells).
comparison compare_floats_abs(const std::vector<float>& gpu, const std::vector<float>& cpu,
                              const float_bound& bound, const describe_fn& describe, const std::string& what);
comparison compare_floats_abs(const std::vector<float>& gpu, const std::vector<double>& cpu,
                              const float_bound& bound, const describe_fn& describe, const std::string& what);

// Integers (indices, faces, voxel hits, raw bits): exact. Works for any integral type.
template <class I>
comparison compare_exact(const std::vector<I>& gpu, const std::vector<I>& cpu,
                         const describe_fn& describe = {}, const std::string& what = {});

// One quantity measured item by item on both sides (a double reference: series<float, double>):
//   series<std::uint32_t> index;  ...  index.add(gpu[k].index, sample.index);
//   VPLKIT_CHECK_PARITY(compare_exact(index, describe, "index"));
template <class G, class C = G>
struct series {
  std::vector<G> gpu;
  std::vector<C> cpu;
  template <class GV, class CV>
  void add(const GV& g, const CV& c) {
    gpu.push_back(G(g));
    cpu.push_back(C(c));
  }
};
template <class I>
comparison compare_exact(const series<I>& s, const describe_fn& describe, const std::string& what) {
  return compare_exact(s.gpu, s.cpu, describe, what);
}
template <class C>
comparison compare_floats(const series<float, C>& s, const float_bound& bound, const describe_fn& describe,
                          const std::string& what) {
  return compare_floats(s.gpu, s.cpu, bound, describe, what);
}
template <class C>
comparison compare_floats_abs(const series<float, C>& s, const float_bound& bound, const describe_fn& describe,
                              const std::string& what) {
  return compare_floats_abs(s.gpu, s.cpu, bound, describe, what);
}

// One field of every element: component(results, [](const out_t& o) { return o.t; }).
template <class S, class F>
auto component(const std::vector<S>& v, F f) {
  std::vector<decltype(f(v.front()))> out;
  out.reserve(v.size());
  for (const S& s : v) out.push_back(f(s));
  return out;
}

// The comparisons above on one field of every element of both sides:
//   compare_field_abs(gpu, cpu, [](const out_t& o) { return o.t; }, within_ulps(4), describe, "t").
template <class S, class F>
comparison compare_field_abs(const std::vector<S>& gpu, const std::vector<S>& cpu, F field, const float_bound& bound,
                             const describe_fn& describe, const std::string& what) {
  return compare_floats_abs(component(gpu, field), component(cpu, field), bound, describe, what);
}
template <class S, class F>
comparison compare_field_exact(const std::vector<S>& gpu, const std::vector<S>& cpu, F field,
                               const describe_fn& describe, const std::string& what) {
  return compare_exact(component(gpu, field), component(cpu, field), describe, what);
}

// Constants of the pack against the C++ ones, bit for bit: each `glsl` is a uint expression
// (floatBitsToUint(vplkit_PI), uint(vplkit_paraboloid_front)) evaluated after `source`.
struct glsl_constant {
  std::string glsl;
  std::uint32_t cpu;
};
comparison compare_constants(const std::string& source, const std::vector<glsl_constant>& constants,
                             const std::string& what);

// The r, g, b channels of colours, one vector each (pushed together).
template <class T>
struct channels {
  std::vector<T> c[3];
  template <class V>
  void push(const V& v) {
    for (int ch = 0; ch < 3; ++ch) c[ch].push_back(T(v[ch]));
  }
};
inline const char* channel_name(int ch) { return ch == 0 ? "r" : ch == 1 ? "g" : "b"; }

namespace detail {
template <class I>
std::string show_integer(I v) {
  if (std::is_signed<I>::value) return show(static_cast<std::int64_t>(v));
  return show(static_cast<std::uint64_t>(v));
}
std::string exact_report(const std::string& what, std::size_t count, std::size_t failures,
                         const std::vector<std::string>& first_failures, bool size_mismatch,
                         std::size_t gpu_size, std::size_t cpu_size);
}

template <class I>
comparison compare_exact(const std::vector<I>& gpu, const std::vector<I>& cpu,
                         const describe_fn& describe, const std::string& what) {
  static_assert(std::is_integral<I>::value, "compare_exact is for integers; use compare_floats");
  comparison c;
  c.count = cpu.size();
  std::vector<std::string> first;
  const bool size_mismatch = gpu.size() != cpu.size();
  if (!size_mismatch) {
    for (std::size_t i = 0; i < cpu.size(); ++i) {
      if (gpu[i] == cpu[i]) continue;
      if (c.failures == 0) c.worst_index = i;
      if (first.size() < 10) {
        std::string line = "[" + std::to_string(i) + "] gpu=" + detail::show_integer(gpu[i]) +
                           " cpu=" + detail::show_integer(cpu[i]);
        if (describe) line += "  input: " + describe(i);
        first.push_back(line);
      }
      ++c.failures;
    }
  }
  c.ok = !size_mismatch && c.failures == 0;
  c.report = detail::exact_report(what, c.count, c.failures, first, size_mismatch, gpu.size(),
                                  cpu.size());
  return c;
}

}  // namespace vplkit::parity

// Prints the report (always: the worst observed difference is part of every run's output) and
// records a Catch2 CHECK (or REQUIRE) at the caller's line.
#define VPLKIT_PARITY_ASSERT_(assertion, ...)                      \
  do {                                                            \
    const ::vplkit::parity::comparison vplkit_c_ = (__VA_ARGS__); \
    std::cout << vplkit_c_.report << std::flush;                  \
    INFO(vplkit_c_.report);                                       \
    assertion(vplkit_c_.ok);                                      \
  } while (false)
#define VPLKIT_CHECK_PARITY(...) VPLKIT_PARITY_ASSERT_(CHECK, __VA_ARGS__)
#define VPLKIT_REQUIRE_PARITY(...) VPLKIT_PARITY_ASSERT_(REQUIRE, __VA_ARGS__)
