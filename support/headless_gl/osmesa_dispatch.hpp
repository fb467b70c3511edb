// SPDX-License-Identifier: MIT
#pragma once
// Serving OSMesa through libepoxy.
//
// Why this exists: epoxy resolves GL entry points with glXGetProcAddress/eglGetProcAddress and
// dlsym on libGL/libOpenGL (glvnd). OSMesa is neither GLX nor EGL and sits outside glvnd, so with
// only an OSMesa context current epoxy's glGetString returns NULL and the first extension-level
// call aborts ("Couldn't find current GLX or EGL context", checked with epoxy 1.5.10).
// On ELF platforms epoxy's dispatch is a public, writable function pointer per entry point
// (`extern PFN... epoxy_glFoo;`, which glFoo is #defined to). We assign every one of them from
// OSMesaGetProcAddress("glFoo") while the OSMesa context lives and restore the previous values
// afterwards. The list of pointers is generated at configure time from epoxy's own
// gl_generated.h (epoxy_gl_entries.cmake), so it is complete for the installed epoxy.
namespace vplkit::gl::detail {

using generic_proc = void (*)();
using proc_resolver = generic_proc (*)(const char* name);

// Points epoxy's GL dispatch at `resolve` (entries it returns NULL for keep their old value).
// Returns how many entry points were redirected.
int redirect_epoxy_gl(proc_resolver resolve);
// Puts back what redirect_epoxy_gl() replaced.
void restore_epoxy_gl();

}  // namespace vplkit::gl::detail
