// SPDX-License-Identifier: MIT
#include "context.hpp"

#include "osmesa_dispatch.hpp"

// epoxy first: it must precede (or replace) GL/gl.h and EGL/egl.h.
#include <epoxy/gl.h>
#if VPLKIT_HAVE_EGL
#include <epoxy/egl.h>
#endif
#if VPLKIT_HAVE_OSMESA
#include <GL/osmesa.h>
#endif

#include <dlfcn.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace vplkit::gl {
namespace {

std::atomic<bool> g_context_alive{false};

bool has_extension(const char* list, const char* name) {
  if (list == nullptr) return false;
  const std::string needle(name);
  std::istringstream words(list);
  std::string word;
  while (words >> word) {
    if (word == needle) return true;
  }
  return false;
}

bool verbose_from_environment() {
  const char* v = std::getenv("VPLKIT_GL_VERBOSE");
  return v != nullptr && *v != '\0' && std::string(v) != "0";
}

// What the context actually is, checked after it is current: a driver may hand out less than
// was asked for (or a compatibility context), and GL_VERSION alone is easy to misparse.
std::string check_gl_version(int want_major, int want_minor) {
  GLint major = 0, minor = 0, profile = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  if (major * 100 + minor < want_major * 100 + want_minor) {
    const GLubyte* v = glGetString(GL_VERSION);
    return "got OpenGL " + std::to_string(major) + "." + std::to_string(minor) + " (\"" +
           (v ? reinterpret_cast<const char*>(v) : "GL_VERSION unavailable") + "\"), need " +
           std::to_string(want_major) + "." + std::to_string(want_minor) + " core";
  }
  if ((profile & GL_CONTEXT_CORE_PROFILE_BIT) == 0) {
    return "context is not a core profile context";
  }
  return {};
}

std::string gl_string(GLenum name) {
  const GLubyte* s = glGetString(name);
  return s ? reinterpret_cast<const char*>(s) : std::string("(null)");
}

#if VPLKIT_HAVE_EGL
const char* egl_error_name(EGLint e) {
  switch (e) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_CURRENT_SURFACE: return "EGL_BAD_CURRENT_SURFACE";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_NATIVE_PIXMAP: return "EGL_BAD_NATIVE_PIXMAP";
    case EGL_BAD_NATIVE_WINDOW: return "EGL_BAD_NATIVE_WINDOW";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
    case EGL_CONTEXT_LOST: return "EGL_CONTEXT_LOST";
    default: return "unknown EGL error";
  }
}

std::string egl_failure(const char* what) {
  const EGLint e = eglGetError();
  std::ostringstream s;
  s << what << " failed (" << egl_error_name(e) << ", 0x" << std::hex << e << ")";
  return s.str();
}
#endif

}  // namespace

struct headless_context::impl {
  context_options options;
  std::string selection;
  std::string version, renderer, vendor, path;
  std::string earlier_failures;
  std::vector<std::string> failures;  // "path: reason"
  bool osmesa = false;

#if VPLKIT_HAVE_EGL
  EGLDisplay egl_display = EGL_NO_DISPLAY;
  EGLContext egl_context = EGL_NO_CONTEXT;
  EGLSurface egl_surface = EGL_NO_SURFACE;
#endif
#if VPLKIT_HAVE_OSMESA
  OSMesaContext osmesa_context = nullptr;
  std::vector<unsigned char> osmesa_pixels;
  decltype(&OSMesaMakeCurrent) osmesa_make_current = nullptr;
  decltype(&OSMesaDestroyContext) osmesa_destroy = nullptr;
#endif

  void note(const std::string& where, const std::string& why) {
    failures.push_back(where + ": " + why);
    if (options.verbose) std::cerr << "[vplkit gl] " << where << ": " << why << "\n";
  }

  // ---- EGL ------------------------------------------------------------------------------------
#if VPLKIT_HAVE_EGL
  bool egl_loaded(const std::string& where) {
    // epoxy dlopen()s libEGL itself and abort()s when it is missing; look first so that a machine
    // without EGL gets a reason instead of a crash.
    static void* handle = dlopen("libEGL.so.1", RTLD_NOW | RTLD_GLOBAL);
    if (handle == nullptr) {
      const char* e = dlerror();
      note(where, std::string("cannot load libEGL.so.1 (") + (e ? e : "?") +
                      "); install libegl1 and a vendor library (libegl-mesa0 or the GPU driver)");
      return false;
    }
    return true;
  }

  // eglReleaseThread straight from libEGL.so.1 (already loaded by egl_loaded), or null.
  static EGLBoolean (*egl_release_thread())() {
    using release_fn = EGLBoolean (*)();
    static const release_fn fn = [] {
      void* lib = dlopen("libEGL.so.1", RTLD_NOW | RTLD_NOLOAD);
      release_fn f = nullptr;
      if (lib != nullptr) {
        void* sym = dlsym(lib, "eglReleaseThread");
        static_assert(sizeof(sym) == sizeof(f), "function and object pointers differ in size");
        std::memcpy(&f, &sym, sizeof(f));
        dlclose(lib);  // RTLD_NOLOAD took a reference; egl_loaded's handle keeps the library
      }
      return f;
    }();
    return fn;
  }

  const char* egl_client_extensions() {
    const char* ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (ext == nullptr) eglGetError();  // EGL_EXT_client_extensions missing: clear the error
    return ext;
  }

  // Teardown order: unbind, destroy, release the thread's EGL state, terminate. eglReleaseThread
  // must come before eglTerminate and must not go through epoxy: epoxy resolves an EGL 1.2 entry
  // point on its first call by reading EGL_VERSION of the display eglGetCurrentDisplay reports,
  // and a terminated display answers that query with nothing. NVIDIA's driver (580.159) still
  // reported the display there, so epoxy aborted every process at exit ("No provider of
  // eglReleaseThread found. Requires one of: EGL 12", status 134). eglReleaseThread also releases
  // a context that the eglMakeCurrent above failed to unbind. The pointer comes from libEGL itself
  // (egl_loaded opened it), where no EGL version gates it.
  void egl_release() {
    if (egl_display == EGL_NO_DISPLAY) return;
    eglMakeCurrent(egl_display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (egl_context != EGL_NO_CONTEXT) eglDestroyContext(egl_display, egl_context);
    if (egl_surface != EGL_NO_SURFACE) eglDestroySurface(egl_display, egl_surface);
    if (auto release_thread = egl_release_thread()) release_thread();
    eglTerminate(egl_display);
    egl_display = EGL_NO_DISPLAY;
    egl_context = EGL_NO_CONTEXT;
    egl_surface = EGL_NO_SURFACE;
  }

  // Initialises `display`, creates a core context and makes it current; on failure records why,
  // cleans up and returns false.
  bool egl_try_display(EGLDisplay display, const std::string& where) {
    if (display == EGL_NO_DISPLAY) {
      note(where, egl_failure("eglGetPlatformDisplay"));
      return false;
    }
    EGLint egl_major = 0, egl_minor = 0;
    if (!eglInitialize(display, &egl_major, &egl_minor)) {
      note(where, egl_failure("eglInitialize"));
      return false;
    }
    egl_display = display;
    auto fail = [&](const std::string& why) {
      note(where, why);
      egl_release();
      return false;
    };
    if (!eglBindAPI(EGL_OPENGL_API)) return fail(egl_failure("eglBindAPI(EGL_OPENGL_API)"));

    const char* ext = eglQueryString(display, EGL_EXTENSIONS);
    const bool configless = has_extension(ext, "EGL_KHR_no_config_context") ||
                            has_extension(ext, "EGL_MESA_configless_context");
    const bool surfaceless = has_extension(ext, "EGL_KHR_surfaceless_context");
    EGLConfig config = EGL_NO_CONFIG_KHR;
    if (!configless || !surfaceless) {
      // Without those two extensions a context needs a config and something to draw to: a 1x1
      // pbuffer, never used for rendering (tests draw into their own framebuffers).
      const EGLint config_attribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                                       EGL_OPENGL_BIT, EGL_NONE};
      EGLint count = 0;
      if (!eglChooseConfig(display, config_attribs, &config, 1, &count) || count < 1) {
        return fail("no EGL config with EGL_OPENGL_BIT and EGL_PBUFFER_BIT (and the display "
                    "lacks EGL_KHR_no_config_context or EGL_KHR_surfaceless_context)");
      }
    }
    const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION, options.major,
                                      EGL_CONTEXT_MINOR_VERSION, options.minor,
                                      EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                      EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    egl_context = eglCreateContext(display, config, EGL_NO_CONTEXT, context_attribs);
    if (egl_context == EGL_NO_CONTEXT) {
      return fail(egl_failure(("eglCreateContext(OpenGL " + std::to_string(options.major) + "." +
                               std::to_string(options.minor) + " core)")
                                  .c_str()));
    }
    if (!surfaceless) {
      const EGLint pbuffer_attribs[] = {EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE};
      egl_surface = eglCreatePbufferSurface(display, config, pbuffer_attribs);
      if (egl_surface == EGL_NO_SURFACE) return fail(egl_failure("eglCreatePbufferSurface"));
    }
    if (!eglMakeCurrent(display, egl_surface, egl_surface, egl_context)) {
      return fail(egl_failure("eglMakeCurrent"));
    }
    const std::string bad = check_gl_version(options.major, options.minor);
    if (!bad.empty()) return fail(bad);
    path = where + " (EGL " + std::to_string(egl_major) + "." + std::to_string(egl_minor) + ")";
    return true;
  }

  bool try_egl_device(bool hardware_only) {
    const std::string where = hardware_only ? "EGL device (hardware)" : "EGL device";
    if (!egl_loaded(where)) return false;
    const char* client = egl_client_extensions();
    if (!has_extension(client, "EGL_EXT_platform_device") ||
        !(has_extension(client, "EGL_EXT_device_enumeration") ||
          has_extension(client, "EGL_EXT_device_base"))) {
      note(where, "EGL_EXT_platform_device / EGL_EXT_device_enumeration not offered");
      return false;
    }
    EGLint count = 0;
    if (!eglQueryDevicesEXT(0, nullptr, &count)) {
      note(where, egl_failure("eglQueryDevicesEXT"));
      return false;
    }
    std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(std::max<EGLint>(count, 0)));
    if (count > 0 && !eglQueryDevicesEXT(count, devices.data(), &count)) {
      note(where, egl_failure("eglQueryDevicesEXT"));
      return false;
    }
    if (count <= 0) {
      note(where, "no EGL devices");
      return false;
    }
    int skipped = 0;
    for (EGLint i = 0; i < count; ++i) {
      const EGLDeviceEXT device = devices[static_cast<std::size_t>(i)];
      const char* dev_ext = eglQueryDeviceStringEXT(device, EGL_EXTENSIONS);
      if (dev_ext == nullptr) eglGetError();
      if (hardware_only && has_extension(dev_ext, "EGL_MESA_device_software")) {
        ++skipped;
        continue;
      }
      std::string name = "EGL device " + std::to_string(i);
      if (has_extension(dev_ext, "EGL_EXT_device_drm")) {
        if (const char* file = eglQueryDeviceStringEXT(device, EGL_DRM_DEVICE_FILE_EXT)) {
          name += std::string(" (") + file + ")";
        }
      }
      const EGLDisplay display = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, device, nullptr);
      if (egl_try_display(display, name)) return true;
    }
    if (skipped == count) {
      note(where, std::to_string(count) + " device(s), all software renderers (skipped here; "
                                          "the surfaceless platform serves them)");
    }
    return false;
  }

  bool try_egl_surfaceless() {
    const std::string where = "EGL surfaceless";
    if (!egl_loaded(where)) return false;
    if (!has_extension(egl_client_extensions(), "EGL_MESA_platform_surfaceless")) {
      note(where, "EGL_MESA_platform_surfaceless not offered (is libegl-mesa0 installed?)");
      return false;
    }
    const EGLDisplay display =
        eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    return egl_try_display(display, where);
  }

  bool try_egl_default() {
    const std::string where = "EGL default display";
    if (!egl_loaded(where)) return false;
    const EGLDisplay display = eglGetDisplay(EGL_DEFAULT_DISPLAY);
    if (display == EGL_NO_DISPLAY) {
      note(where, egl_failure("eglGetDisplay(EGL_DEFAULT_DISPLAY)"));
      return false;
    }
    return egl_try_display(display, where);
  }
#else
  bool egl_unavailable(const char* where) {
    note(where, "this build of vplkit_headless_gl has no EGL support (EGL headers not found)");
    return false;
  }
  bool try_egl_device(bool hardware_only) {
    return egl_unavailable(hardware_only ? "EGL device (hardware)" : "EGL device");
  }
  bool try_egl_surfaceless() { return egl_unavailable("EGL surfaceless"); }
  bool try_egl_default() { return egl_unavailable("EGL default display"); }
#endif

  // ---- OSMesa ---------------------------------------------------------------------------------
#if VPLKIT_HAVE_OSMESA
  static decltype(&OSMesaGetProcAddress)& osmesa_get_proc() {
    static decltype(&OSMesaGetProcAddress) fn = nullptr;
    return fn;
  }
  static detail::generic_proc osmesa_resolve(const char* name) {
    return reinterpret_cast<detail::generic_proc>(osmesa_get_proc()(name));
  }

  bool try_osmesa() {
    const std::string where = "OSMesa";
    // Loaded at run time (RTLD_LOCAL: its gl* exports must not shadow glvnd's) so that a machine
    // without libOSMesa still gets EGL and a clear reason here.
    void* lib = nullptr;
    std::string dl_errors;
    for (const char* name : {"libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so"}) {
      lib = dlopen(name, RTLD_NOW | RTLD_LOCAL);
      if (lib != nullptr) break;
      const char* e = dlerror();
      dl_errors += std::string(dl_errors.empty() ? "" : "; ") + (e ? e : name);
    }
    if (lib == nullptr) {
      note(where, "cannot load libOSMesa (" + dl_errors + "); install libosmesa6");
      return false;
    }
    auto create = reinterpret_cast<decltype(&OSMesaCreateContextAttribs)>(
        dlsym(lib, "OSMesaCreateContextAttribs"));
    osmesa_make_current =
        reinterpret_cast<decltype(&OSMesaMakeCurrent)>(dlsym(lib, "OSMesaMakeCurrent"));
    osmesa_destroy =
        reinterpret_cast<decltype(&OSMesaDestroyContext)>(dlsym(lib, "OSMesaDestroyContext"));
    osmesa_get_proc() =
        reinterpret_cast<decltype(&OSMesaGetProcAddress)>(dlsym(lib, "OSMesaGetProcAddress"));
    if (!create || !osmesa_make_current || !osmesa_destroy || !osmesa_get_proc()) {
      note(where, "libOSMesa lacks OSMesaCreateContextAttribs (needs Mesa >= 11.2)");
      return false;
    }
    const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA,
                           OSMESA_DEPTH_BITS, 24,
                           OSMESA_STENCIL_BITS, 8,
                           OSMESA_ACCUM_BITS, 0,
                           OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION, options.major,
                           OSMESA_CONTEXT_MINOR_VERSION, options.minor,
                           0};
    osmesa_context = create(attribs, nullptr);
    if (osmesa_context == nullptr) {
      note(where, "OSMesaCreateContextAttribs(OpenGL " + std::to_string(options.major) + "." +
                      std::to_string(options.minor) + " core) returned NULL");
      return false;
    }
    // OSMesa renders into client memory; a 1x1 RGBA buffer satisfies MakeCurrent, and tests draw
    // into their own framebuffer objects.
    osmesa_pixels.assign(4, 0);
    if (!osmesa_make_current(osmesa_context, osmesa_pixels.data(), GL_UNSIGNED_BYTE, 1, 1)) {
      note(where, "OSMesaMakeCurrent failed");
      osmesa_release();
      return false;
    }
    const int redirected = detail::redirect_epoxy_gl(&osmesa_resolve);
    osmesa = true;
    if (redirected == 0) {
      note(where, "OSMesaGetProcAddress resolved no GL entry point");
      osmesa_release();
      return false;
    }
    const std::string bad = check_gl_version(options.major, options.minor);
    if (!bad.empty()) {
      note(where, bad);
      osmesa_release();
      return false;
    }
    path = where;
    return true;
  }

  void osmesa_release() {
    if (osmesa) detail::restore_epoxy_gl();
    osmesa = false;
    if (osmesa_context != nullptr) {
      osmesa_make_current(nullptr, nullptr, 0, 0, 0);
      osmesa_destroy(osmesa_context);
      osmesa_context = nullptr;
    }
    // libOSMesa stays loaded: unloading LLVM-based drivers mid-process is a known source of
    // crashes at exit.
  }
#else
  bool try_osmesa() {
    note("OSMesa", "this build of vplkit_headless_gl has no OSMesa support (GL/osmesa.h not "
                   "found at configure time; install libosmesa6-dev)");
    return false;
  }
  void osmesa_release() {}
#endif

  void release() {
    if (osmesa) {
      osmesa_release();
      return;
    }
#if VPLKIT_HAVE_EGL
    egl_release();
#endif
  }

  bool create() {
    const std::string& s = selection;
    if (s == "auto") {
      return try_egl_device(true) || try_egl_surfaceless() || try_egl_default() || try_osmesa();
    }
    if (s == "egl") return try_egl_device(true) || try_egl_surfaceless() || try_egl_default();
    if (s == "egl-device") return try_egl_device(false);
    if (s == "egl-surfaceless") return try_egl_surfaceless();
    if (s == "osmesa") return try_osmesa();
    throw std::runtime_error("vplkit headless GL: VPLKIT_GL=\"" + s +
                             "\" is not one of auto, egl, egl-device, egl-surfaceless, osmesa");
  }
};

std::string selection_from_environment() {
  const char* v = std::getenv("VPLKIT_GL");
  std::string s = v ? v : "";
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s.empty() ? "auto" : s;
}

headless_context::headless_context(const context_options& options)
    : impl_(std::make_unique<impl>()) {
  if (g_context_alive.exchange(true)) {
    throw std::runtime_error(
        "vplkit headless GL: a headless_context already exists in this process (one at a time)");
  }
  impl& d = *impl_;
  d.options = options;
  d.options.verbose = options.verbose || verbose_from_environment();
  d.selection = options.selection.empty() ? selection_from_environment() : options.selection;
  bool ok = false;
  try {
    ok = d.create();
  } catch (...) {
    g_context_alive = false;
    throw;
  }
  if (!ok) {
    g_context_alive = false;
    std::ostringstream msg;
    msg << "vplkit headless GL: no OpenGL " << options.major << "." << options.minor
        << " core context could be created (VPLKIT_GL=" << d.selection << "). Tried:";
    for (const auto& f : d.failures) msg << "\n  - " << f;
    msg << "\nOn Debian: apt-get install libegl1 libegl-mesa0 libgl1-mesa-dri (EGL, llvmpipe) or "
           "libosmesa6 (OSMesa); set VPLKIT_GL=auto|egl|egl-device|egl-surfaceless|osmesa and "
           "VPLKIT_GL_VERBOSE=1 to trace.";
    throw std::runtime_error(msg.str());
  }
  for (const auto& f : d.failures) d.earlier_failures += (d.earlier_failures.empty() ? "" : "; ") + f;
  d.version = gl_string(GL_VERSION);
  d.renderer = gl_string(GL_RENDERER);
  d.vendor = gl_string(GL_VENDOR);
  if (d.options.verbose) std::cerr << "[vplkit gl] " << describe() << "\n";
}

headless_context::~headless_context() {
  impl_->release();
  g_context_alive = false;
}

const std::string& headless_context::version() const { return impl_->version; }
const std::string& headless_context::renderer() const { return impl_->renderer; }
const std::string& headless_context::vendor() const { return impl_->vendor; }
const std::string& headless_context::path() const { return impl_->path; }
const std::string& headless_context::earlier_failures() const { return impl_->earlier_failures; }
bool headless_context::is_osmesa() const { return impl_->osmesa; }

std::string headless_context::describe() const {
  return "OpenGL " + impl_->version + " | " + impl_->renderer + " via " + impl_->path;
}

void headless_context::make_current() {
  [[maybe_unused]] impl& d = *impl_;
#if VPLKIT_HAVE_OSMESA
  if (d.osmesa) {
    if (!d.osmesa_make_current(d.osmesa_context, d.osmesa_pixels.data(), GL_UNSIGNED_BYTE, 1, 1)) {
      throw std::runtime_error("vplkit headless GL: OSMesaMakeCurrent failed");
    }
    return;
  }
#endif
#if VPLKIT_HAVE_EGL
  if (!eglMakeCurrent(d.egl_display, d.egl_surface, d.egl_surface, d.egl_context)) {
    throw std::runtime_error("vplkit headless GL: " + egl_failure("eglMakeCurrent"));
  }
#endif
}

}  // namespace vplkit::gl
