// SPDX-License-Identifier: MIT
// CPU/GPU parity of glsl/vplkit/image/median_fill.glsl and the kernel median_fill.comp with
// include/vplkit/image/median_fill.hpp (T = float).
//
// The fill does no arithmetic: every output is an input value (the texel itself, a neighbour's
// value chosen by comparisons, or +0), so CPU and GPU must agree BIT FOR BIT on every
// implementation; the comparison is on the raw bits. One exception, by design of the hardware: a
// GPU that flushes denormals to zero sees a denormal weight as 0, i.e. as a hole, where the CPU
// does not. The denormal case below runs only where the implementation keeps denormals (probed;
// llvmpipe does) and says so otherwise.
#include <parity_harness.hpp>

#include <vplkit/image/median_fill.hpp>
#include <vplkit/image/median_fill_params.h>
#include <vplkit/paraboloid/texel_grid.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iostream>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

using namespace vplkit::parity;
using vplkit_test::flt_max;
using vplkit_test::flt_min;
using vplkit_test::random_source;

namespace {

// Runs median_fill.comp on a 2 R R weight array (non-default bindings and local size, as a host
// would choose them). The output buffer starts as NaN bits: a texel the kernel skips fails.
std::vector<float> gpu_fill_dprsm(const std::vector<float>& in, int R, unsigned local_size = 8) {
  const std::string defines = "#define VPLKIT_MEDIAN_FILL_BINDING_IN 3\n#define VPLKIT_MEDIAN_FILL_BINDING_OUT 5\n"
                              "#define VPLKIT_MEDIAN_FILL_BINDING_PARAMS 1\n#define VPLKIT_MEDIAN_FILL_LOCAL_SIZE " +
                              std::to_string(local_size) + "\n";
  const auto& prog = pack_kernel("vplkit/image/median_fill.comp", defines);
  vplkit::gpu::median_fill_params params{};
  params.resolution = R;
  const auto ib = vplkit::gl::buffer::from_vector(in);
  const auto ob = vplkit::gl::buffer::filled(in.size() * sizeof(float), 0xFF);
  const auto ub = vplkit_test::uniform_buffer(params);
  const GLuint groups = GLuint((R + int(local_size) - 1) / int(local_size));
  vplkit_test::dispatch(prog, {groups, groups, 2},
                        {vplkit_test::storage_at(3, ib), vplkit_test::storage_at(5, ob), vplkit_test::uniform_at(1, ub)});
  return ob.read<float>();
}

std::string texel_text(const std::vector<float>& in, int R, std::size_t i) {
  const int face = int(i) / (R * R), y = (int(i) % (R * R)) / R, x = int(i) % R;
  std::string s = "R " + std::to_string(R) + " face " + std::to_string(face) + " texel (" + std::to_string(x) +
                  ", " + std::to_string(y) + ") valid " + std::to_string(vplkit::texel_is_valid(x, y, R)) +
                  " in " + show(in[i]) + " window:";
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int nx = x + dx, ny = y + dy;
      if (nx < 0 || ny < 0 || nx >= R || ny >= R) continue;
      s += " " + show(in[std::size_t(face * R * R + ny * R + nx)]);
    }
  return s;
}

// GPU vs C++ float bit for bit; also: the C++ double fill gives the same values (selection, not
// arithmetic), and every filled hole holds one of its same-face neighbours' bits.
void check_dprsm(const std::vector<float>& in, int R, const std::string& what, unsigned local_size = 8) {
  std::vector<float> cpu(in.size());
  vplkit::median_fill_dprsm(in.data(), cpu.data(), R);
  const std::vector<float> gpu = gpu_fill_dprsm(in, R, local_size);
  VPLKIT_CHECK_PARITY(compare_exact(bits_of(gpu), bits_of(cpu),
                                    [&](std::size_t i) { return texel_text(in, R, i); }, what + " (bits)"));

  std::vector<double> din(in.begin(), in.end()), dout(in.size());
  vplkit::median_fill_dprsm(din.data(), dout.data(), R);
  std::size_t holes = 0, filled = 0, double_mismatch = 0, not_a_neighbour = 0;
  for (std::size_t i = 0; i < in.size(); ++i) {
    if (bits_of(float(dout[i])) != bits_of(cpu[i])) ++double_mismatch;
    if (in[i] != 0.0f) continue;
    ++holes;
    if (cpu[i] == 0.0f) continue;
    ++filled;
    const int face = int(i) / (R * R), y = (int(i) % (R * R)) / R, x = int(i) % R;
    bool found = false;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int nx = x + dx, ny = y + dy;
        if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= R || ny >= R) continue;
        found |= bits_of(in[std::size_t(face * R * R + ny * R + nx)]) == bits_of(cpu[i]);
      }
    not_a_neighbour += !found;
  }
  std::cout << "  " << what << ": " << in.size() << " texels, " << holes << " holes, " << filled
            << " filled; C++ double differs at " << double_mismatch << ", fill not a neighbour's value at "
            << not_a_neighbour << "\n";
  CHECK(double_mismatch == 0);
  CHECK(not_a_neighbour == 0);
}

// Random DPRSM weights: valid texels get a value or a hole (hole_fraction), drawn from few
// distinct values (ties), a wide magnitude range, negatives, and -0.0 holes; invalid texels are 0
// (as a real DPRSM) except a few.
std::vector<float> random_dprsm(random_source& rnd, int R, double hole_fraction) {
  std::vector<float> w(std::size_t(2 * R * R), 0.0f);
  const float few[5] = {0.25f, 1.0f, 1.0f, 3.5f, 7.0f};
  for (int face = 0; face < 2; ++face)
    for (int y = 0; y < R; ++y)
      for (int x = 0; x < R; ++x) {
        float& v = w[std::size_t(face * R * R + y * R + x)];
        if (!vplkit::texel_is_valid(x, y, R)) {
          if (rnd.unit() < 0.02) v = float(rnd.uniform(0.0, 1.0));
          continue;
        }
        if (rnd.unit() < hole_fraction) {
          v = rnd.unit() < 0.1 ? -0.0f : 0.0f;
          continue;
        }
        const double k = rnd.unit();
        if (k < 0.4) v = few[rnd.integer(0, 4)];
        else if (k < 0.9) v = float(std::pow(10.0, rnd.uniform(-30.0, 30.0)));
        else v = -float(rnd.uniform(0.0, 10.0));
      }
  return w;
}

}  // namespace

TEST_CASE("median_fill.comp: random DPRSM weights with holes, R = 8, 64, 256, bit for bit") {
  random_source rnd(5);
  for (int R : {8, 64, 256}) {
    for (double holes : {0.1, 0.5, 0.9, 0.99}) {
      const auto in = random_dprsm(rnd, R, holes);
      check_dprsm(in, R, "R " + std::to_string(R) + ", hole fraction " + std::to_string(holes));
    }
  }
  // Another local size (the host's choice) and R not a multiple of it.
  const auto in = random_dprsm(rnd, 77, 0.6);
  check_dprsm(in, 77, "R 77, local size 16", 16);
}

TEST_CASE("median_fill.comp: borders, corners and all-hole neighbourhoods") {
  // Values only on the border rows and columns of the map (the disk's rim texels at x or y = 0 or
  // R - 1 exist for R >= 3), holes everywhere else; a lone value; an all-zero map; tiny R.
  for (int R : {1, 2, 3, 4, 8, 64}) {
    std::vector<float> border(std::size_t(2 * R * R), 0.0f);
    for (int face = 0; face < 2; ++face)
      for (int y = 0; y < R; ++y)
        for (int x = 0; x < R; ++x)
          if (x == 0 || y == 0 || x == R - 1 || y == R - 1)
            border[std::size_t(face * R * R + y * R + x)] = float(1 + face * 100 + x + 3 * y);
    check_dprsm(border, R, "border values, R " + std::to_string(R));
    check_dprsm(std::vector<float>(std::size_t(2 * R * R), 0.0f), R, "all holes, R " + std::to_string(R));
    std::vector<float> lone(std::size_t(2 * R * R), 0.0f);
    lone[std::size_t(R * R + (R / 2) * R + R / 2)] = 2.5f;  // face 1 centre: spreads only to its window
    check_dprsm(lone, R, "one value on face 1, R " + std::to_string(R));
  }
  // Face seam: face 0's last row and face 1's first row are adjacent in memory but never mix.
  const int R = 16;
  std::vector<float> seam(std::size_t(2 * R * R), 0.0f);
  for (int x = 0; x < R; ++x) seam[std::size_t((R - 1) * R + x)] = 9.0f;  // face 0, last row
  check_dprsm(seam, R, "face seam");
  std::vector<float> cpu(seam.size());
  vplkit::median_fill_dprsm(seam.data(), cpu.data(), R);
  for (int x = 0; x < R; ++x) CHECK(cpu[std::size_t(R * R + x)] == 0.0f);  // face 1, first row stays 0
}

TEST_CASE("median_fill.comp: extreme magnitudes and -0, denormals where the implementation keeps them") {
  const int R = 32;
  random_source rnd(9);
  std::vector<float> extreme(std::size_t(2 * R * R), 0.0f);
  const float vals[6] = {flt_max, -flt_max, flt_min, -flt_min, 1e-30f, 3e38f};
  for (std::size_t i = 0; i < extreme.size(); ++i) {
    const double k = rnd.unit();
    extreme[i] = k < 0.5 ? (k < 0.05 ? -0.0f : 0.0f) : vals[rnd.integer(0, 5)];
  }
  check_dprsm(extreme, R, "+-FLT_MAX, +-FLT_MIN, -0");

  // Does the implementation keep denormal inputs? (llvmpipe: yes; most GPUs flush them to zero.)
  const std::vector<float> probe_in{1e-40f};
  kernel_call probe;
  probe.inputs = {input(0, std::vector<float>{1e-40f}, "float v")};
  probe.output_glsl = "uint r";
  probe.body = "r[0] = v[0] != 0.0 ? 1u : 0u;";
  const auto kept = run_compute<std::uint32_t>(probe, 1);
  std::vector<float> denormal(std::size_t(2 * R * R), 0.0f);
  for (std::size_t i = 0; i < denormal.size(); ++i)
    if (rnd.unit() < 0.5) denormal[i] = rnd.unit() < 0.5 ? 1e-40f * float(rnd.integer(1, 9)) : 1.0f;
  if (kept[0] == 1u) {
    check_dprsm(denormal, R, "denormal weights (implementation keeps denormals)");
  } else {
    std::cout << "  denormal weights: this implementation flushes denormals; a denormal weight is a hole "
                 "here (documented difference), case skipped\n";
  }
}

TEST_CASE("vplkit_median_fill_texel through the accessor: rectangular images, 1xN, Nx1, 1x1, masks") {
  // Several images stacked in one buffer (the accessor's `face` picks the image), any fillable
  // mask, against the C++ median_fill with the same mask.
  kernel_call call;
  call.source = R"(
#include "vplkit/image/median_fill.glsl"
layout(std430, binding = 0) readonly buffer In { float img[]; };
layout(std430, binding = 3) readonly buffer Dims { int width; int height; };
float vplkit_load_weight(int face, int x, int y) { return img[(face * height + y) * width + x]; }
)";
  call.output_glsl = "float result";
  call.body = R"(
  int per = width * height;
  int face = int(i) / per;
  int r = int(i) % per;
  result[i] = vplkit_median_fill_texel(face, width, height, r % width, r / width, mask[i] != 0u);)";
  random_source rnd(13);
  const int sizes[][2] = {{1, 1}, {1, 9}, {9, 1}, {2, 2}, {3, 7}, {40, 23}, {97, 3}, {128, 128}};
  for (const auto& wh : sizes) {
    const int width = wh[0], height = wh[1], images = 3;
    const std::size_t per = std::size_t(width) * std::size_t(height);
    std::vector<float> img(per * images);
    std::vector<std::uint32_t> mask(per * images);
    for (std::size_t i = 0; i < img.size(); ++i) {
      img[i] = rnd.unit() < 0.6 ? 0.0f : float(rnd.integer(1, 6)) * 0.5f;
      mask[i] = rnd.unit() < 0.8 ? 1u : 0u;
    }
    const std::vector<std::int32_t> dims{width, height};
    call.inputs = {input(0, img), input(2, mask, "uint mask"), input(3, dims)};
    const auto gpu = run_compute<float>(call, img.size());
    std::vector<float> cpu(img.size());
    for (int k = 0; k < images; ++k) {
      const std::uint32_t* m = mask.data() + per * std::size_t(k);
      vplkit::median_fill(img.data() + per * std::size_t(k), cpu.data() + per * std::size_t(k), width, height,
                          [&](int x, int y) { return m[std::size_t(y) * std::size_t(width) + std::size_t(x)] != 0u; });
    }
    VPLKIT_CHECK_PARITY(compare_exact(
        bits_of(gpu), bits_of(cpu),
        [&](std::size_t i) {
          return "image " + std::to_string(i / per) + " texel " + std::to_string(i % per) + " in " + show(img[i]) +
                 " fillable " + std::to_string(mask[i]);
        },
        "median_fill_texel " + std::to_string(width) + "x" + std::to_string(height) + " x 3 images (bits)"));
  }
}
