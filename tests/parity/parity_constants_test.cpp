// SPDX-License-Identifier: MIT
// Parity of glsl/vplkit/core/constants.glsl with the C++ values, bit for bit, and a self-check of
// the harness (sentinel detection, float and integer comparison reports, declared buffers, several
// outputs, uniform blocks, pack kernels driven through their parameter headers).
#include <parity_harness.hpp>

#include <fp_mode.hpp>

#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

namespace {

using namespace vplkit::parity;

struct named_constant {
  const char* glsl;
  double value;  // the C++ side: static_cast<float>(value) is what the pack must hold
};

const std::vector<named_constant>& constants() {
  static const std::vector<named_constant> list = {
      {"vplkit_PI", 3.14159265358979323846},
      {"vplkit_TWO_PI", 2.0 * 3.14159265358979323846},
      {"vplkit_HALF_PI", 0.5 * 3.14159265358979323846},
      {"vplkit_INV_PI", 1.0 / 3.14159265358979323846},
      {"vplkit_INV_TWO_PI", 0.5 / 3.14159265358979323846},
      {"vplkit_INV_FOUR_PI", 0.25 / 3.14159265358979323846},
      {"vplkit_ONE_MINUS_EPSILON", 1.0 - std::numeric_limits<float>::epsilon() / 2.0},
      {"vplkit_TWO_POW_MINUS_24", 1.0 / 16777216.0},
      {"vplkit_FLT_MAX", static_cast<double>(std::numeric_limits<float>::max())},
      {"vplkit_FLT_MIN", static_cast<double>(std::numeric_limits<float>::min())},
  };
  return list;
}

}  // namespace

TEST_CASE("constants.glsl holds the C++ constants bit for bit") {
  std::string body = "#include \"vplkit/core/constants.glsl\"\n"
                     "layout(std430, binding = 0) writeonly buffer Out { uint bits[]; };\n"
                     "void main() {\n"
                     "  if (gl_GlobalInvocationID.x != 0u) return;\n";
  for (std::size_t i = 0; i < constants().size(); ++i) {
    body += "  bits[" + std::to_string(i) + "] = floatBitsToUint(" + constants()[i].glsl + ");\n";
  }
  body += "}\n";
  const auto& list = constants();
  const auto gpu = run_compute<std::uint32_t>(body, {1, 1, 1}, {}, 0, list.size());
  std::vector<std::uint32_t> cpu;
  for (const auto& c : list) cpu.push_back(bits_of(static_cast<float>(c.value)));
  VPLKIT_CHECK_PARITY(compare_exact(
      gpu, cpu,
      [&](std::size_t i) {
        return std::string(list[i].glsl) + " = " + show(list[i].value);
      },
      "constants.glsl (float bits)"));
}

TEST_CASE("harness: one invocation per element, inputs at their bindings, float report") {
  // result = u * vplkit_PI on 1000 inputs (not a multiple of the local size).
  std::vector<float> u(1000);
  for (std::size_t i = 0; i < u.size(); ++i) u[i] = static_cast<float>(i) / 999.0f;
  const std::string kernel = R"(
#include "vplkit/core/constants.glsl"
layout(std430, binding = 3) readonly buffer In { float u[]; };
layout(std430, binding = 1) writeonly buffer Out { float result[]; };
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= VPLKIT_PARITY_COUNT) return;
  result[i] = u[i] * vplkit_PI;
}
)";
  const auto gpu = run_compute<float>(
      kernel, {64, 1, 1}, {input(3, u)}, 1, u.size());
  std::vector<double> cpu(u.size());
  for (std::size_t i = 0; i < u.size(); ++i) {
    cpu[i] = static_cast<double>(u[i]) * 3.14159265358979323846;
  }
  // One float multiply against the exact product: within 1 ulp of float(exact).
  VPLKIT_CHECK_PARITY(compare_floats(
      gpu, cpu, within_ulps(1),
      [&](std::size_t i) { return "u = " + show(u[i]); }, "u * vplkit_PI"));
}

TEST_CASE("harness: an element the kernel does not write fails the comparison") {
  // The kernel skips the last element; the 0xFF sentinel (NaN) must make the comparison fail.
  const std::string kernel = R"(
layout(std430, binding = 0) writeonly buffer Out { float result[]; };
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i + 1u >= VPLKIT_PARITY_COUNT) return;
  result[i] = 1.0;
}
)";
  const auto gpu = run_compute<float>(kernel, {32, 1, 1}, {}, 0, 100);
  const std::vector<float> cpu(100, 1.0f);
  const auto c = compare_floats(gpu, cpu, within_rel(1e-3));
  CHECK_FALSE(c.ok);
  CHECK(c.failures == 1);
  CHECK(c.worst_index == 99);
  CHECK(c.report.find("[99]") != std::string::npos);
}

TEST_CASE("harness: comparison reports name the worst element and its input") {
  const std::vector<float> cpu = {1.0f, 2.0f, 3.0f, 0.0f};
  std::vector<float> gpu = cpu;
  gpu[2] = std::nextafter(std::nextafter(3.0f, 4.0f), 4.0f);  // 2 ulps off
  auto describe = [](std::size_t i) { return "x = " + std::to_string(i * 10); };
  const auto loose = compare_floats(gpu, cpu, within_ulps(2), describe);
  CHECK(loose.ok);
  CHECK(loose.worst_index == 2);
  CHECK(loose.worst_ulps == 2.0);
  CHECK(loose.report.find("x = 20") != std::string::npos);
  const auto tight = compare_floats(gpu, cpu, within_ulps(1), describe);
  CHECK_FALSE(tight.ok);
  CHECK(tight.report.find("FAIL: 1 of 4") != std::string::npos);
  // A relative bound alone cannot pass a wrong value next to a zero reference; abs can.
  gpu = cpu;
  gpu[3] = 1e-9f;
  CHECK_FALSE(compare_floats(gpu, cpu, within_rel(1e-3)).ok);
  CHECK(compare_floats(gpu, cpu, within_rel(1e-3) | within_abs(1e-8)).ok);
  // Integers: exact, with the input printed.
  const std::vector<std::uint32_t> want = {1, 2, 3};
  const std::vector<std::uint32_t> got = {1, 5, 3};
  const auto ints = compare_exact(got, want, describe, "indices");
  CHECK_FALSE(ints.ok);
  CHECK(ints.report.find("[1] gpu=5 cpu=2  input: x = 10") != std::string::npos);
}

TEST_CASE("harness: an overflow matches FLT_MAX within the bound, nothing else matches an infinity") {
  // Vulkan, "Precision and Operation of SPIR-V Instructions" (ULP): where the allowed range passes
  // the largest finite float, a device may return +-Inf or +-FLT_MAX.
  const float inf = std::numeric_limits<float>::infinity();
  const float big = std::numeric_limits<float>::max();
  const float below = std::nextafter(big, 0.0f);
  CHECK(compare_floats({inf}, std::vector<float>{big}, within_ulps(1)).ok);
  CHECK(compare_floats({below}, std::vector<float>{inf}, within_ulps(2)).ok);
  CHECK_FALSE(compare_floats({below}, std::vector<float>{inf}, within_ulps(1)).ok);
  CHECK(compare_floats({inf}, std::vector<float>{below}, within_rel(1e-6)).ok);
  CHECK_FALSE(compare_floats({inf}, std::vector<float>{1e38f}, within_rel(1e-6)).ok);
  CHECK_FALSE(compare_floats({-inf}, std::vector<float>{big}, within_ulps(4)).ok);
  CHECK_FALSE(compare_floats({inf}, std::vector<float>{big}, within_abs(1e30)).ok);
}

TEST_CASE("harness: the reference runs with FTZ|DAZ exactly when VPLKIT_PARITY_FTZ_DAZ=1, the driver in IEEE") {
  const bool requested = vplkit_test::reference_ftz_daz_requested();
  CHECK(vplkit_test::ftz_daz_active() == requested);
  volatile float tiny = std::numeric_limits<float>::min();
  volatile float half = 0.5f;
  const float product = tiny * half;  // a denormal, or 0 under FTZ
  CHECK((product == 0.0f) == requested);
  // The GL device keeps its own mode (llvmpipe keeps denormals) whatever the reference's.
  kernel_call k;
  k.output_glsl = "uint result";
  k.body = "result[i] = floatBitsToUint(uintBitsToFloat(0x00800000u + i * 0u) * 0.5);";
  const auto gpu = run_compute<std::uint32_t>(k, 1);
  REQUIRE(gpu.size() == 1);
  std::cout << "parity: the device " << (gpu[0] == 0u ? "flushes" : "keeps") << " the denormal FLT_MIN / 2\n";
  CHECK(vplkit_test::ftz_daz_active() == requested);
}

TEST_CASE("harness: declared buffers, a per-item body, several outputs and a uniform block") {
  struct params {  // std140 { vec4 scale; uint shift; } padded to 32 bytes
    float4 scale;
    std::uint32_t shift, pad[3];
  };
  const params p{{2.0f, 3.0f, 0.0f, 0.0f}, 7u, {0u, 0u, 0u}};
  std::vector<float> u(300);
  for (std::size_t i = 0; i < u.size(); ++i) u[i] = static_cast<float>(i) * 0.25f;
  kernel_call k;
  k.inputs = {input(4, u, "float u")};
  k.uniforms = {uniform(2, p, "Params { vec4 scale; uint shift; }")};
  k.output_glsl = "float twice";
  k.more_outputs = {output_of<std::uint32_t>(5, "uint shifted"), output_of<float>(6, "float once", 2)};
  k.body = "twice[i] = u[i] * scale.x;\n"
           "  shifted[i] = i + shift;\n"
           "  if (i < 2u) once[i] = scale.y;";
  const kernel_outputs out = run_kernel(k, u.size(), sizeof(float));
  const auto twice = out.get<float>(1);
  const auto shifted = out.get<std::uint32_t>(5);
  const auto once = out.get<float>(6);
  std::vector<float> cpu_twice;
  std::vector<std::uint32_t> cpu_shifted;
  for (std::size_t i = 0; i < u.size(); ++i) {
    cpu_twice.push_back(u[i] * 2.0f);
    cpu_shifted.push_back(std::uint32_t(i) + 7u);
  }
  VPLKIT_CHECK_PARITY(compare_floats(twice, cpu_twice, within_ulps(0), {}, "harness: main output"));
  VPLKIT_CHECK_PARITY(compare_exact(shifted, cpu_shifted, {}, "harness: second output"));
  VPLKIT_CHECK_PARITY(compare_floats(once, std::vector<float>{3.0f, 3.0f}, within_ulps(0), {},
                                     "harness: third output, its own count"));
  // Two buffers at one binding are refused before anything runs.
  k.more_outputs.push_back(output_of<float>(4));
  CHECK_THROWS_WITH(run_kernel(k, u.size(), sizeof(float)), Catch::Contains("binding 4"));
}

TEST_CASE("harness: a pack kernel through its parameter header and the group spread") {
  // spread_groups: 65535 groups at most along x, the rest folded into y.
  CHECK(vplkit_test::spread_groups(65535) == std::array<GLuint, 3>{65535u, 1u, 1u});
  CHECK(vplkit_test::spread_groups(65536) == std::array<GLuint, 3>{65535u, 2u, 1u});
  CHECK(vplkit_test::spread_groups(1000, 64) == std::array<GLuint, 3>{16u, 1u, 1u});
  CHECK(vplkit_test::spread_groups(0) == std::array<GLuint, 3>{0u, 0u, 1u});
  // pack_kernel compiles a kernel file once per (file, defines).
  const auto& a = pack_kernel("vplkit/image/median_fill.comp");
  const auto& b = pack_kernel("vplkit/image/median_fill.comp");
  const auto& c = pack_kernel("vplkit/image/median_fill.comp", "#define VPLKIT_MEDIAN_FILL_LOCAL_SIZE 4\n");
  CHECK(&a == &b);
  CHECK(&a != &c);
  CHECK(c.local_size()[0] == 4);
}
