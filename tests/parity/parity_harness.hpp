#pragma once
// Parity-test harness: run a GLSL kernel that #includes the pack on the headless GL context and
// compare what it wrote with the C++ templates' answer.
//
//   const std::string kernel = R"(
//   #include "vplkit/core/constants.glsl"
//   layout(std430, binding = 0) readonly buffer In { float u[]; };
//   layout(std430, binding = 1) writeonly buffer Out { float result[]; };
//   void main() {
//     uint i = gl_GlobalInvocationID.x;
//     if (i >= VPLKIT_PARITY_COUNT) return;
//     result[i] = u[i] * vplkit_PI;
//   })";
//   auto gpu = vplkit::parity::run_compute<float>(kernel, {64, 1, 1},
//                                                 {vplkit::parity::input(0, us)}, 1, us.size());
//   VPLKIT_CHECK_PARITY(vplkit::parity::compare_floats(gpu, cpu, vplkit::parity::within_ulps(2),
//       [&](std::size_t i) { return "u = " + vplkit::parity::show(us[i]); }, "u * pi"));
//
// What the harness adds to the kernel, after its own #version 430 line: `#define
// VPLKIT_PARITY_COUNT <count>u`, the call's `defines`, and `layout(local_size_x = ..) in;`.
// Includes resolve against the pack root (VPLKIT_GLSL_SOURCE_DIR) with vplkit's
// include_resolver, so compile errors name the pack file and line. The output buffer starts
// filled with 0xFF bytes (NaN floats, ~0u integers): an element the kernel never wrote fails.
// Buffer element types must match std430 (scalars, vec2, vec4, or hand-padded structs). Several
// results per element (an index and its pmf, say) come back as one struct, e.g.
// `struct result { std::uint32_t index; float pmf; };` <-> `struct R { uint index; float pmf; };`.
#include <headless_gl/compute.hpp>
#include <headless_gl/context.hpp>

#include <catch2/catch.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <iostream>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

namespace vplkit::parity {

// The process-wide context, created on first use (prints "parity: OpenGL ... via ..." once).
// Kept alive until exit on purpose: tearing Mesa down from a static destructor races its own
// atexit handlers.
gl::headless_context& context();

struct ssbo {
  unsigned binding = 0;
  std::vector<unsigned char> bytes;
};

template <class T>
ssbo input(unsigned binding, const std::vector<T>& data) {
  static_assert(std::is_trivially_copyable<T>::value, "SSBO elements must be trivially copyable");
  ssbo s;
  s.binding = binding;
  const auto* p = reinterpret_cast<const unsigned char*>(data.data());
  s.bytes.assign(p, p + data.size() * sizeof(T));
  return s;
}

struct kernel_call {
  std::string name = "parity_kernel.comp";  // labels the kernel in compile errors
  std::string source;                       // no #version: the harness writes it
  std::array<unsigned, 3> local_size{64, 1, 1};
  std::array<unsigned, 3> groups{0, 0, 0};  // {0,0,0}: ceil(count / local_size x) groups in x
  std::vector<ssbo> inputs;
  unsigned output_binding = 0;
  std::string defines;                      // extra preamble, e.g. "#define N 4\n"
  std::string version = "#version 430";
};

// Runs `call` and returns the first `out_bytes` bytes of the output buffer. Programs are cached
// by their final source text, so repeating a call does not recompile.
std::vector<unsigned char> run_compute_bytes(const kernel_call& call, std::size_t count,
                                             std::size_t out_bytes);

template <class Out>
std::vector<Out> run_compute(const kernel_call& call, std::size_t count) {
  static_assert(std::is_trivially_copyable<Out>::value, "output must be trivially copyable");
  const auto bytes = run_compute_bytes(call, count, count * sizeof(Out));
  std::vector<Out> out(count);
  if (count > 0) std::memcpy(out.data(), bytes.data(), count * sizeof(Out));
  return out;
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

// Ordered distance in float ulps (+0 and -0 are 0 apart); huge when one side is NaN or the two
// differ in infinity.
double ulp_distance(float a, float b);

comparison compare_floats(const std::vector<float>& gpu, const std::vector<float>& cpu,
                          const float_bound& bound, const describe_fn& describe = {},
                          const std::string& what = {});
// Double reference: ulps are counted to float(cpu), rel/abs against the double value.
comparison compare_floats(const std::vector<float>& gpu, const std::vector<double>& cpu,
                          const float_bound& bound, const describe_fn& describe = {},
                          const std::string& what = {});

// Integers (indices, faces, voxel hits, raw bits): exact. Works for any integral type.
template <class I>
comparison compare_exact(const std::vector<I>& gpu, const std::vector<I>& cpu,
                         const describe_fn& describe = {}, const std::string& what = {});

// Formats a value for messages with enough digits to round-trip.
std::string show(float v);
std::string show(double v);
std::string show(std::int64_t v);
std::string show(std::uint64_t v);
inline std::string show(int v) { return show(static_cast<std::int64_t>(v)); }
inline std::string show(unsigned v) { return show(static_cast<std::uint64_t>(v)); }

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
// records a Catch2 check at the caller's line.
#define VPLKIT_CHECK_PARITY(...)                         \
  do {                                                   \
    const ::vplkit::parity::comparison vplkit_c_ = (__VA_ARGS__); \
    std::cout << vplkit_c_.report << std::flush;         \
    INFO(vplkit_c_.report);                              \
    CHECK(vplkit_c_.ok);                                 \
  } while (false)

#define VPLKIT_REQUIRE_PARITY(...)                       \
  do {                                                   \
    const ::vplkit::parity::comparison vplkit_c_ = (__VA_ARGS__); \
    std::cout << vplkit_c_.report << std::flush;         \
    INFO(vplkit_c_.report);                              \
    REQUIRE(vplkit_c_.ok);                               \
  } while (false)
