// SPDX-License-Identifier: MIT
// gl_context_check <expected path prefix>
// Creates the headless context the way VPLKIT_GL asks (ctest sets it: gl_context_egl,
// gl_context_osmesa), prints GL_VERSION / GL_RENDERER, checks that the path taken is the one
// asked for, runs a compute shader that writes SSBOs through an #include of the pack, checks the
// timer and that a compile error inside an included file names that file and line, and builds
// vertex + fragment programs (raster_program.hpp) from strings and from files. Then it
// closes the context and opens one through the other path in the same process (OSMesa re-points
// epoxy's dispatch and must put it back). Any failure, "no context" included, exits non-zero:
// CI always has Mesa, so a missing context is a broken machine, not a reason to skip.
#include <headless_gl/compute.hpp>
#include <headless_gl/context.hpp>
#include <headless_gl/raster_program.hpp>

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
#include <functional>
#include <iostream>
#include <string>
#include <utility>
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

// Empty string when `what` holds every piece of `pieces`; else the first missing one and `what`.
std::string missing_from(const std::string& what, const std::vector<std::string>& pieces) {
  for (const std::string& piece : pieces)
    if (what.find(piece) == std::string::npos) return "\"" + piece + "\" not in:\n" + what;
  return {};
}

// Runs `build`, which must throw gl_error; empty string when its message holds every piece of
// `pieces` and, when `file` is given, that file's line 3 ("<file>:3" from Mesa and glslang,
// "<file>(3)" from NVIDIA); else what is wrong.
std::string expect_gl_error(const std::function<void()>& build, const std::vector<std::string>& pieces,
                            const std::string& file = {}) {
  try {
    build();
  } catch (const vplkit::gl::gl_error& e) {
    const std::string what = e.what();
    if (!file.empty() && what.find(file + ":3") == std::string::npos && what.find(file + "(3)") == std::string::npos)
      return "compile error not reported as " + file + " line 3:\n" + what;
    return missing_from(what, pieces);
  }
  return "no error reported (expected \"" + pieces.front() + "\")";
}

// Vertex + fragment programs: one from strings through the pack's include path, and errors that
// name the program, the stage and the included file's line (a file pair's quoted #include found
// beside it), or the failed link. A program that cached_raster_program builds lives until the
// process exits, past this check's context, so only its failures are exercised here; the
// renderer's G-buffer and DPRSM passes build theirs on every run.
std::string run_raster_program_check() {
  namespace fs = std::filesystem;
  using vplkit::gl::cached_raster_program;
  using vplkit::gl::raster_program;
  const fs::path dir = fs::temp_directory_path() / ("vplkit_gl_raster_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string broken = (dir / "broken.glsl").string();
  { std::ofstream(dir / "broken.glsl") << "// probe\nfloat probe_ok() { return 1.0; }\nfloat probe_bad() { return undeclared_thing; }\n"; }
  { std::ofstream(dir / "inputs.glsl") << "layout(location = 0) in vec3 a_position;\n"; }
  { std::ofstream(dir / "probe.vert") << "#include \"inputs.glsl\"\nvoid main() { gl_Position = vec4(a_position, 1.0); }\n"; }
  { std::ofstream(dir / "bad.frag") << "#include \"broken.glsl\"\nout vec4 o_colour;\nvoid main() { o_colour = vec4(probe_bad()); }\n"; }
  const std::string vs = "#version 430 core\n#include \"vplkit/core/constants.glsl\"\n"
                         "layout(location = 0) in vec3 a_position;\n"
                         "void main() { gl_Position = vec4(a_position * vplkit_PI, 1.0); }\n";
  const std::string fs_ok = "#version 430 core\nuniform vec3 u_colour;\nout vec4 o_colour;\n"
                            "void main() { o_colour = vec4(u_colour, 1.0); }\n";
  std::string problem;
  try {
    const program p = raster_program("probe", vs, fs_ok);
    if (p.id() == 0 || p.uniform_location("u_colour") < 0) problem = "raster_program: no uniform u_colour";
  } catch (const std::exception& e) {
    problem = std::string("a valid raster program failed: ") + e.what();
  }
  struct expected_error {
    std::function<void()> build;
    std::vector<std::string> pieces;
    std::string file_at_line_3;
  };
  const std::vector<expected_error> errors = {
      {[&] { raster_program("probe_compile", vs, "#version 430 core\n#include \"broken.glsl\"\nout vec4 o;\nvoid main() { o = vec4(probe_bad()); }\n",
                        {dir.string(), vplkit::gl::glsl_source_dir()}); },
       {"probe_compile: fragment shader failed to compile"}, broken},
      {[&] { raster_program("probe_vertex", "#version 430 core\nvoid main() { gl_Position = undeclared_thing; }\n", fs_ok); },
       {"probe_vertex: vertex shader failed to compile", "probe_vertex.vert"}, ""},
      {[&] { raster_program("probe_link", vs, "#version 430 core\nout vec4 o;\nvoid not_main() { o = vec4(1.0); }\n"); },
       {"probe_link: program failed to link"}, ""},
      {[&] { cached_raster_program((dir / "probe.vert").string(), (dir / "bad.frag").string()); },
       {"probe+bad: fragment shader failed to compile"}, broken},
      {[&] { cached_raster_program((dir / "probe.vert").string(), (dir / "absent.frag").string()); },
       {"cannot read " + (dir / "absent.frag").string()}, ""}};
  for (const expected_error& e : errors) {
    if (!problem.empty()) break;
    problem = expect_gl_error(e.build, e.pieces, e.file_at_line_3);
  }
  std::error_code ec;
  fs::remove_all(dir, ec);
  if (problem.empty()) std::cout << "raster programs build; their errors name the program, the stage and file:line\n";
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
      if (auto e = run_raster_program_check(); !e.empty()) return fail(e);
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
