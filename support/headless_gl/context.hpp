// SPDX-License-Identifier: MIT
#pragma once
// A windowless OpenGL 4.3+ core context for tests and tools (not part of the installed library).
//
// Paths, tried in this order by VPLKIT_GL=auto (the default):
//   1. EGL device platform (EGL_EXT_platform_device), hardware devices only — the NVIDIA driver
//      on a GPU machine. Tried first because glvnd hands Mesa's surfaceless platform to Mesa even
//      when a GPU is present, which would silently give llvmpipe.
//   2. EGL on Mesa's surfaceless platform (EGL_MESA_platform_surfaceless): llvmpipe on a CPU box.
//   3. EGL_DEFAULT_DISPLAY.
//   4. OSMesa (libOSMesa.so.8, loaded at run time).
// VPLKIT_GL=egl tries 1-3, egl-device 1 (any device, software included), egl-surfaceless 2,
// osmesa 4. When nothing works the exception lists every path tried and why each failed.
//
// GL calls go through libepoxy (<epoxy/gl.h>) on every path. Epoxy only knows GLX/EGL/WGL
// contexts, so for OSMesa this library points epoxy's public dispatch pointers at
// OSMesaGetProcAddress() while the context lives (see osmesa_dispatch.hpp). Do not call
// epoxy_is_desktop_gl()/epoxy_has_gl_extension() etc. under OSMesa; use the methods below.
//
// One context per process at a time; it is made current on the creating thread.
#include <memory>
#include <string>

namespace vplkit::gl {

struct context_options {
  // "auto", "egl", "egl-device", "egl-surfaceless", "osmesa"; empty: read VPLKIT_GL (else auto).
  std::string selection;
  int major = 4;  // minimum core version required
  int minor = 3;
  bool verbose = false;  // print each attempt to stderr as it happens
};

class headless_context {
public:
  explicit headless_context(const context_options& options = {});
  ~headless_context();
  headless_context(const headless_context&) = delete;
  headless_context& operator=(const headless_context&) = delete;

  const std::string& version() const;   // GL_VERSION
  const std::string& renderer() const;  // GL_RENDERER
  const std::string& vendor() const;    // GL_VENDOR
  const std::string& path() const;      // e.g. "EGL surfaceless", "EGL device 0 (/dev/dri/card0)", "OSMesa"
  bool is_osmesa() const;
  // One line: "OpenGL <version> | <renderer> via <path>".
  std::string describe() const;
  // Everything tried before the path that worked (empty when the first try worked).
  const std::string& earlier_failures() const;
  void make_current();

  struct impl;

private:
  std::unique_ptr<impl> impl_;
};

// The value of VPLKIT_GL, lower-cased, or "auto" when unset or empty.
std::string selection_from_environment();

}  // namespace vplkit::gl
