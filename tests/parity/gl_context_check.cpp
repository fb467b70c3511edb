// SPDX-License-Identifier: MIT
// gl_context_check <expected path prefix>
// Creates the headless context the way VPLKIT_GL asks (ctest sets it: gl_context_egl,
// gl_context_osmesa), prints GL_VERSION / GL_RENDERER, checks that the path taken is the one
// asked for, runs a compute shader that writes SSBOs through an #include of the pack, checks the
// timer and that a compile error inside an included file names that file and line. Then it
// closes the context and opens one through the other path in the same process (OSMesa re-points
// epoxy's dispatch and must put it back). Any failure, "no context" included, exits non-zero:
// CI always has Mesa, so a missing context is a broken machine, not a reason to skip.
#include <headless_gl/compute.hpp>
#include <headless_gl/context.hpp>

#if __has_include(<epoxy/egl.h>)
#include <epoxy/egl.h>
#endif

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <unistd.h>

namespace {

using vplkit::gl::buffer;
using vplkit::gl::program;

// Empty string: all good; otherwise what went wrong.
std::string run_compute_check() {
  // Every invocation writes a value no other invocation writes; the pack's constant proves the
  // include path works on this context too.
  const std::string kernel = R"(#version 430
#include "vplkit/core/constants.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer In { uint in_values[]; };
layout(std430, binding = 1) writeonly buffer Out { uint out_values[]; };
layout(std430, binding = 2) writeonly buffer OutF { float out_pi[]; };
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(in_values.length())) return;
  out_values[i] = in_values[i] * 2654435761u + i;
  out_pi[i] = vplkit_PI * float(i);
}
)";
  const std::size_t n = 1000;  // not a multiple of 64: the bounds check in the kernel matters
  std::vector<std::uint32_t> input(n);
  for (std::size_t i = 0; i < n; ++i) input[i] = static_cast<std::uint32_t>(i * 7 + 3);

  auto prog = program::compute_with_includes(kernel, "gl_context_check.comp");
  const auto local = prog.local_size();
  if (local[0] != 64 || local[1] != 1 || local[2] != 1) return "local size is not 64x1x1";
  auto in = buffer::from_vector(input);
  auto out = buffer::filled(n * sizeof(std::uint32_t), 0xFF);
  auto out_pi = buffer::filled(n * sizeof(float), 0xFF);
  in.bind(0);
  out.bind(1);
  out_pi.bind(2);

  // Timer sanity, not timing: device time can never exceed the wall time around it.
  const auto wall_begin = std::chrono::steady_clock::now();
  vplkit::gl::timer_query timer;
  timer.begin();
  vplkit::gl::dispatch(prog, vplkit::gl::groups_for(n, local[0]));
  timer.end();
  const double ms = timer.milliseconds();
  const double wall_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall_begin)
          .count();

  const auto result = out.read<std::uint32_t>();
  const auto pis = out_pi.read<float>();
  std::size_t wrong = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t want = input[i] * 2654435761u + static_cast<std::uint32_t>(i);
    const float want_pi = static_cast<float>(3.14159265358979323846) * static_cast<float>(i);
    // One float multiply each side: at most 1 ulp apart (4e-7 relative covers it).
    if (result[i] != want || !(std::fabs(pis[i] - want_pi) <= 4e-7f * std::fabs(want_pi))) {
      if (wrong < 5) {
        std::cerr << "  [" << i << "] gpu " << result[i] << " / " << pis[i] << ", want " << want
                  << " / " << want_pi << "\n";
      }
      ++wrong;
    }
  }
  if (wrong != 0) return std::to_string(wrong) + " of " + std::to_string(n) + " results wrong";
  if (!(ms >= 0.0) || !(ms <= wall_ms + 0.01)) {
    return std::string("timer (") + timer.method() + ") gave " + std::to_string(ms) +
           " ms for work inside " + std::to_string(wall_ms) + " ms of wall time";
  }
  std::cout << "compute: " << n << " invocations correct; timer (" << timer.method()
            << "): " << ms << " ms\n";
  return {};
}

std::string run_error_mapping_check() {
  // A compile error on line 3 of an included file must come back as that file's line 3.
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("vplkit_gl_check_" + std::to_string(getpid()));
  fs::create_directories(dir / "probe");
  { std::ofstream(dir / "probe" / "broken.glsl") << "// probe\nfloat probe_ok() { return 1.0; }\nfloat probe_bad() { return undeclared_thing; }\n"; }
  std::string problem = "no compile error reported";
  try {
    program::compute_with_includes(
        "#version 430\n#include \"vplkit/core/constants.glsl\"\n#include \"probe/broken.glsl\"\n"
        "layout(local_size_x = 1) in;\nvoid main() {}\n",
        "error_probe.comp", {dir.string(), vplkit::gl::glsl_source_dir()});
  } catch (const vplkit::gl::gl_error& e) {
    const std::string what = e.what();
    const std::string file = (dir / "probe" / "broken.glsl").string();
    if (what.find(file + ":3") != std::string::npos ||
        what.find(file + "(3)") != std::string::npos) {
      problem.clear();
    } else {
      problem = "compile error not reported as " + file + " line 3:\n" + what;
    }
  }
  std::error_code ec;
  fs::remove_all(dir, ec);
  if (problem.empty()) std::cout << "compile errors in included files map back to file:line\n";
  return problem;
}

int fail(const std::string& why) {
  std::cerr << "gl_context_check: FAILED: " << why << "\n";
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string expected = argc > 1 ? argv[1] : "";
  try {
    bool was_osmesa = false;
    {
      vplkit::gl::headless_context context;
      std::cout << "VPLKIT_GL=" << vplkit::gl::selection_from_environment() << "\n"
                << "GL_VERSION:  " << context.version() << "\n"
                << "GL_RENDERER: " << context.renderer() << "\n"
                << "GL_VENDOR:   " << context.vendor() << "\n"
                << "path:        " << context.path() << "\n";
      if (!context.earlier_failures().empty()) {
        std::cout << "tried first: " << context.earlier_failures() << "\n";
      }
      if (context.path().rfind(expected, 0) != 0) {
        return fail("expected a context via \"" + expected + "...\", got \"" + context.path() +
                    "\"");
      }
      was_osmesa = context.is_osmesa();
      if (auto e = run_compute_check(); !e.empty()) return fail(e);
      if (auto e = run_error_mapping_check(); !e.empty()) return fail(e);
    }
    {
      vplkit::gl::context_options other;
      other.selection = was_osmesa ? "egl" : "osmesa";
      vplkit::gl::headless_context second(other);
      std::cout << "then, in the same process: " << second.describe() << "\n";
      if (auto e = run_compute_check(); !e.empty()) return fail("second context: " + e);
    }
#if __has_include(<epoxy/egl.h>)
    // The teardown leaves no EGL context or display current on this thread. epoxy resolves an EGL
    // entry point on its first call against eglGetCurrentDisplay(): a display left current but
    // terminated made it abort every process at exit on NVIDIA's driver.
    if (eglGetCurrentContext() != EGL_NO_CONTEXT || eglGetCurrentDisplay() != EGL_NO_DISPLAY) {
      return fail("an EGL context or display is still current after the headless contexts closed");
    }
#endif
    std::cout << "OK\n";
    return 0;
  } catch (const std::exception& e) {
    return fail(e.what());
  }
}
