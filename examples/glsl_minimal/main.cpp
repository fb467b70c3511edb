// SPDX-License-Identifier: MIT
// docs/glsl.md's complete minimal example: EGL (surfaceless, no window) and GL both through libepoxy, the
// vplkit include resolver, the pack's cdf_build.comp building a CDF from VPL weights on the GPU, and
// one compute shader of ours that picks VPLs from it as the C++ does. Exits 0 when every GPU pick
// equals the CPU pick (up to the ties the CDF build allows). Built and run by the ctest
// `glsl_minimal_example`.
#include <vplkit/distribution/cdf_build_params.h>  // bindings, block size, parameter struct, passes
#include <vplkit/glsl/include_resolver.hpp>
#include <vplkit/vplkit.hpp>

#include <epoxy/egl.h>  // libepoxy loads EGL and GL entry points alike
#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

static int fail(const char* what) {
  std::fprintf(stderr, "glsl_minimal: %s\n", what);
  return 1;
}

int main() {
  // 1. A headless OpenGL 4.3 core context on Mesa's surfaceless platform (or any EGL driver).
  auto get_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  EGLDisplay dpy = get_display ? get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr)
                               : EGL_NO_DISPLAY;
  if (dpy == EGL_NO_DISPLAY) dpy = eglGetDisplay(EGL_DEFAULT_DISPLAY);
  if (!eglInitialize(dpy, nullptr, nullptr)) return fail("eglInitialize failed");
  if (!eglBindAPI(EGL_OPENGL_API)) return fail("eglBindAPI(EGL_OPENGL_API) failed");
  const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 3,
                            EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  EGLContext ctx = eglCreateContext(dpy, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
  if (ctx == EGL_NO_CONTEXT || !eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx))
    return fail("no OpenGL 4.3 core context (needs EGL_KHR_no_config_context + surfaceless_context)");
  std::printf("%s | %s\n", glGetString(GL_VERSION), glGetString(GL_RENDERER));

  // 2. VPL weights, uploaded: the GPU builds their CDF (the CPU builds it too, for the check).
  std::vector<float> weights(1000);
  for (std::size_t i = 0; i < weights.size(); ++i) weights[i] = (i % 7 == 0) ? 0.0f : float(i % 13);
  const vplkit::discrete_cdf<float> cdf(weights);

  // 3. Two programs: the pack's cdf_build.comp and this example's pick_vpls.comp. #version first,
  //    then the pack's includes inlined from VPLKIT_GLSL_DIR (neither file has a #version line, so
  //    that OpenGL (430) and Vulkan (450) builds share them).
  auto compile = [](const std::string& source, const char* name) -> GLuint {
    const vplkit::glsl::resolved_source src = vplkit::glsl::resolve_includes(source, name, {VPLKIT_GLSL_DIR});
    const char* text = src.text.c_str();
    const GLuint shader = glCreateShader(GL_COMPUTE_SHADER);
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
      char log[4096];
      glGetShaderInfoLog(shader, sizeof log, nullptr, log);
      std::fprintf(stderr, "%s\n", src.map_log(log).c_str());
      return 0;
    }
    const GLuint program = glCreateProgram();
    glAttachShader(program, shader);
    glLinkProgram(program);
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    return ok ? program : 0;
  };
  std::ifstream file(VPLKIT_EXAMPLE_DIR "/pick_vpls.comp");
  if (!file) return fail("cannot read " VPLKIT_EXAMPLE_DIR "/pick_vpls.comp");
  const std::string body((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const GLuint build = compile("#version 430\n#include \"vplkit/distribution/cdf_build.comp\"\n", "cdf_build");
  const GLuint pick = compile("#version 430\n" + body, "pick_vpls.comp");
  if (build == 0 || pick == 0) return fail("a compute program did not compile or link");

  // 4. Buffers at the bindings of cdf_build_params.h (pick_vpls.comp reads the same ones), and
  //    pick_vpls.comp's own: the picks at 6, its parameters at 7.
  const std::uint32_t n = std::uint32_t(weights.size()), count = 4096;
  const std::size_t m = vplkit::discrete_guide_size(n);
  const std::size_t blocks = (n + VPLKIT_CDF_BUILD_BLOCK - 1) / VPLKIT_CDF_BUILD_BLOCK;
  GLuint buffers[8];
  glGenBuffers(8, buffers);
  auto make = [&](GLenum target, GLuint binding, const void* data, std::size_t bytes) {
    glBindBuffer(target, buffers[binding]);
    glBufferData(target, GLsizeiptr(bytes), data, GL_DYNAMIC_DRAW);
    glBindBufferBase(target, binding, buffers[binding]);
  };
  make(GL_SHADER_STORAGE_BUFFER, VPLKIT_CDF_BUILD_BINDING_WEIGHTS, weights.data(), n * sizeof(float));
  make(GL_SHADER_STORAGE_BUFFER, VPLKIT_CDF_BUILD_BINDING_CDF, nullptr, (n + 1) * sizeof(float));
  make(GL_SHADER_STORAGE_BUFFER, VPLKIT_CDF_BUILD_BINDING_GUIDE, nullptr, (m + 1) * sizeof(std::uint32_t));
  make(GL_SHADER_STORAGE_BUFFER, VPLKIT_CDF_BUILD_BINDING_BLOCKS, nullptr, blocks * sizeof(vplkit::gpu::cdf_build_block));
  make(GL_SHADER_STORAGE_BUFFER, VPLKIT_CDF_BUILD_BINDING_INFO, nullptr, sizeof(vplkit::gpu::cdf_build_info));
  vplkit::gpu::cdf_build_params params{};
  params.n = n;
  make(GL_UNIFORM_BUFFER, VPLKIT_CDF_BUILD_BINDING_PARAMS, &params, sizeof params);
  make(GL_SHADER_STORAGE_BUFFER, 6, nullptr, count * sizeof(std::uint32_t));
  const std::uint32_t pick_params[4] = {n, count, 0, 0};  // std140 block { uint n; uint count; }
  make(GL_UNIFORM_BUFFER, 7, pick_params, sizeof pick_params);

  // 5. The CDF: the passes cdf_build_pass_needed names (1, 3, 5 up to 2^20 weights), one dispatch
  //    each, with a shader-storage barrier after each: every pass reads what the previous wrote.
  //    Passes 2 and 4 run one work group, the others a work group per block of weights.
  glUseProgram(build);
  for (std::uint32_t pass = 1; pass <= 6; ++pass) {
    if (!vplkit::gpu::cdf_build_pass_needed(pass, n)) continue;
    params.pass = pass;
    glBindBuffer(GL_UNIFORM_BUFFER, buffers[VPLKIT_CDF_BUILD_BINDING_PARAMS]);
    glBufferSubData(GL_UNIFORM_BUFFER, 0, sizeof params, &params);
    glDispatchCompute(pass == 2 || pass == 4 ? 1 : GLuint(blocks), 1, 1);  // z: one distribution
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  }

  // 6. The picks, from the CDF where the GPU left it; then read back (a buffer-update barrier).
  glUseProgram(pick);
  glDispatchCompute((count + 63) / 64, 1, 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  std::vector<std::uint32_t> gpu(count);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffers[6]);
  glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, GLsizeiptr(count * sizeof(std::uint32_t)), gpu.data());
  if (glGetError() != GL_NO_ERROR) return fail("GL error during dispatch or read-back");

  // 7. The same picks on the CPU: same RNG bits, the CPU's CDF of the same weights. cdf_build.comp
  //    promises each cdf value equal to the CPU's or a float neighbour, so a pick may differ only
  //    where u lies on the CPU's cdf value k = max(both picks) or one float below it (a tie).
  std::uint32_t mismatches = 0, ties = 0;
  for (std::uint32_t i = 0; i < count; ++i) {
    vplkit::counter_rng rng = vplkit::make_counter_rng(42u, i);
    const float u = vplkit::rng_next_float(rng);
    const std::size_t cpu = cdf.sample(u).index;
    if (gpu[i] == cpu) continue;
    const float edge = cdf.cdf()[std::max<std::size_t>(gpu[i], cpu)];
    if (gpu[i] < n && u <= edge && u >= std::nextafter(edge, 0.0f)) ++ties;
    else ++mismatches;
  }
  std::printf("%u picks from the GPU-built CDF, %u differ from the CPU's (+ %u at a tie)\n", count, mismatches, ties);
  eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(dpy, ctx);
  eglTerminate(dpy);
  return mismatches == 0 ? 0 : 1;
}
