// SPDX-License-Identifier: MIT
// docs/glsl.md's complete minimal example: EGL (surfaceless, no window) and GL both through libepoxy, the
// vplkit include resolver, and one compute shader from the GLSL pack that picks VPLs exactly as
// the C++ does. Exits 0 when every GPU pick equals the CPU pick. Built and run by the ctest
// `glsl_minimal_example`.
#include <vplkit/glsl/include_resolver.hpp>
#include <vplkit/vplkit.hpp>

#include <epoxy/egl.h>  // libepoxy loads EGL and GL entry points alike
#include <epoxy/gl.h>

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

  // 2. VPL weights -> CDF on the CPU (the library), uploaded as-is.
  std::vector<float> weights(1000);
  for (std::size_t i = 0; i < weights.size(); ++i) weights[i] = (i % 7 == 0) ? 0.0f : float(i % 13);
  const vplkit::discrete_cdf<float> cdf(weights);

  // 3. The shader: #version first, then the pack's includes inlined from VPLKIT_GLSL_DIR.
  //    The .comp file has no #version so that OpenGL (430) and Vulkan (450) builds share it.
  std::ifstream file(VPLKIT_EXAMPLE_DIR "/pick_vpls.comp");
  if (!file) return fail("cannot read " VPLKIT_EXAMPLE_DIR "/pick_vpls.comp");
  const std::string body((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const vplkit::glsl::resolved_source src = vplkit::glsl::resolve_includes(
      "#version 430\n" + body, "pick_vpls.comp", {VPLKIT_GLSL_DIR});
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
    return fail("compute shader did not compile");
  }
  const GLuint program = glCreateProgram();
  glAttachShader(program, shader);
  glLinkProgram(program);
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) return fail("compute program did not link");

  // 4. Buffers, dispatch, read back.
  const std::uint32_t count = 4096;
  struct params { std::uint32_t n, guide_size; float total; std::uint32_t count; } p{
      std::uint32_t(cdf.size()), std::uint32_t(cdf.guide_size()), cdf.total(), count};
  GLuint buffers[4];
  glGenBuffers(4, buffers);
  auto upload = [&](int binding, const void* data, std::size_t bytes) {
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffers[binding]);
    glBufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(bytes), data, GL_STATIC_DRAW);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GLuint(binding), buffers[binding]);
  };
  upload(0, cdf.cdf().data(), cdf.cdf().size() * sizeof(float));
  upload(1, cdf.guide().data(), cdf.guide().size() * sizeof(std::uint32_t));
  upload(2, nullptr, count * sizeof(std::uint32_t));
  upload(3, &p, sizeof p);
  glUseProgram(program);
  glDispatchCompute((count + 63) / 64, 1, 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  std::vector<std::uint32_t> gpu(count);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffers[2]);
  glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, GLsizeiptr(count * sizeof(std::uint32_t)), gpu.data());
  if (glGetError() != GL_NO_ERROR) return fail("GL error during dispatch or read-back");

  // 5. The same picks on the CPU: same RNG bits, same CDF, same index.
  std::uint32_t mismatches = 0;
  for (std::uint32_t i = 0; i < count; ++i) {
    vplkit::counter_rng rng = vplkit::make_counter_rng(42u, i);
    const std::size_t cpu = cdf.sample(vplkit::rng_next_float(rng)).index;
    if (gpu[i] != cpu) ++mismatches;
  }
  std::printf("%u picks, %u differ between GPU and CPU\n", count, mismatches);
  eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(dpy, ctx);
  eglTerminate(dpy);
  return mismatches == 0 ? 0 : 1;
}
