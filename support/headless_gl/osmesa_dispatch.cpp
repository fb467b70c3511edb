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
}  // namespace

int redirect_epoxy_gl(proc_resolver resolve) {
  auto& old = saved();
  old.clear();
  int redirected = 0;
  // Function-pointer to function-pointer reinterpret_casts: well defined as long as each pointer
  // is called only through its own type, which epoxy's macros guarantee.
#define VPLKIT_EPOXY_GL(name)                                            \
  old.push_back(reinterpret_cast<generic_proc>(epoxy_##name));           \
  if (generic_proc p = resolve(#name)) {                                 \
    epoxy_##name = reinterpret_cast<decltype(epoxy_##name)>(p);          \
    ++redirected;                                                        \
  }
#include "vplkit_epoxy_gl_entries.inc"
#undef VPLKIT_EPOXY_GL
  return redirected;
}

void restore_epoxy_gl() {
  auto& old = saved();
  if (old.empty()) return;
  std::size_t i = 0;
#define VPLKIT_EPOXY_GL(name) epoxy_##name = reinterpret_cast<decltype(epoxy_##name)>(old[i++]);
#include "vplkit_epoxy_gl_entries.inc"
#undef VPLKIT_EPOXY_GL
  old.clear();
}

}  // namespace vplkit::gl::detail
