// SPDX-License-Identifier: MIT
#include "osmesa_dispatch.hpp"

#include <epoxy/gl.h>

#include <vector>

namespace vplkit::gl::detail {
namespace {
std::vector<generic_proc>& saved() {
  static std::vector<generic_proc> values;
  return values;
}

// One entry point, out of line: the generated lists below become a few thousand plain calls.
// Inlined, the push_back and the branch made redirect_epoxy_gl one function of ~3000 copies, which
// GCC took 79 s to optimise at -O3 (10 s this way). One instantiation per dispatch pointer type.
// Function-pointer to function-pointer reinterpret_casts: well defined as long as each pointer is
// called only through its own type, which epoxy's macros guarantee.
template <class Proc>
[[gnu::noinline]] void redirect_one(Proc& slot, const char* name, proc_resolver resolve,
                                    std::vector<generic_proc>& old, int& redirected) {
  old.push_back(reinterpret_cast<generic_proc>(slot));
  if (generic_proc p = resolve(name)) {
    slot = reinterpret_cast<Proc>(p);
    ++redirected;
  }
}

template <class Proc>
[[gnu::noinline]] void restore_one(Proc& slot, generic_proc value) {
  slot = reinterpret_cast<Proc>(value);
}
}  // namespace

int redirect_epoxy_gl(proc_resolver resolve) {
  auto& old = saved();
  old.clear();
  int redirected = 0;
#define VPLKIT_EPOXY_GL(name) redirect_one(epoxy_##name, #name, resolve, old, redirected);
#include "vplkit_epoxy_gl_entries.inc"
#undef VPLKIT_EPOXY_GL
  return redirected;
}

void restore_epoxy_gl() {
  auto& old = saved();
  if (old.empty()) return;
  std::size_t i = 0;
#define VPLKIT_EPOXY_GL(name) restore_one(epoxy_##name, old[i++]);
#include "vplkit_epoxy_gl_entries.inc"
#undef VPLKIT_EPOXY_GL
  old.clear();
}

}  // namespace vplkit::gl::detail
