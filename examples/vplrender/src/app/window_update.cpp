// SPDX-License-Identifier: MIT
#include "app/window_update.hpp"

#include <algorithm>

namespace vplrender {

namespace {

// Keys 1-8 in this order; exact (8) only on a frame with exact rays (window_view::exact).
constexpr method kMethodOrder[] = {method::reference, method::global, method::local, method::gbg,
                                   method::gather, method::mis, method::mis_as_published, method::exact};
constexpr int kAllMethods = static_cast<int>(sizeof kMethodOrder / sizeof kMethodOrder[0]);

int method_count(const window_view& v) { return v.exact ? kAllMethods : kAllMethods - 1; }

bool uses_dirs(method m) {
  return m == method::gbg || m == method::gather || m == method::mis || m == method::mis_as_published ||
         m == method::exact;
}

bool set_samples(window_view& v, int vpls, int dirs) {
  const bool changed = vpls != v.vpls || dirs != v.dirs;
  v.vpls = vpls;
  v.dirs = dirs;
  return changed;
}

}  // namespace

bool apply_window_action(window_view& v, const std::string& a, bool* close) {
  if (a == "q") {
    *close = true;
    return false;
  }
  const int kMethods = method_count(v);
  if (a.size() == 1 && a[0] >= '1' && a[0] < '1' + kMethods) {
    const method m = kMethodOrder[a[0] - '1'];
    if (m == v.meth) return false;
    v.meth = m;
    return true;
  }
  if (a == "m") {
    int i = 0;
    while (i < kMethods && kMethodOrder[i] != v.meth) ++i;
    v.meth = kMethodOrder[(i + 1) % kMethods];
    return true;
  }
  const bool dirs = uses_dirs(v.meth);
  if (a == "+")
    return set_samples(v, std::min(v.vpls * 2, limits::max_vpls), dirs ? std::min(v.dirs * 2, limits::max_dirs) : v.dirs);
  if (a == "-") return set_samples(v, std::max(v.vpls / 2, 1), dirs ? std::max(v.dirs / 2, 1) : v.dirs);
  return false;
}

window_update plan_window_update(window_view& v, const std::vector<std::string>& actions, bool damaged, bool first) {
  window_update u;
  for (const std::string& a : actions) {
    u.rerender = apply_window_action(v, a, &u.close) || u.rerender;
    if (u.close) break;
  }
  if (u.close) u.rerender = false;  // closing: no image to show
  u.redraw = !u.close && (u.rerender || damaged || first);
  return u;
}

std::string window_samples_text(const window_view& v) {
  std::string s = std::string(to_string(v.meth)) + ", vpls " + std::to_string(v.vpls);
  if (uses_dirs(v.meth)) s += ", dirs " + std::to_string(v.dirs);
  return s;
}

}  // namespace vplrender
