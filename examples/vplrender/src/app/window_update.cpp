// SPDX-License-Identifier: MIT
#include "app/window_update.hpp"

#include "render/method_traits.hpp"

#include <algorithm>
#include <iterator>
#include <vector>

namespace vplrender {

namespace {

// Keys 1-8: the methods the GPU backend runs (the window's), in the order of
// render/method_traits.cpp, those that trace the scene's triangles (exact) only on a frame with
// exact rays (window_view::exact). ris and ris-mis have the fixed keys 9 and 0: after exact in
// the table, they would take key 8 on a frame without exact rays, so one key would mean two methods.
bool on_numbered_key(const method_traits& t, const window_view& v) {
  return t.gpu && t.estimator != estimator_kind::ris && (!t.exact_rays || v.exact);
}

std::vector<method> window_methods(const window_view& v) {
  std::vector<method> out;
  for (const method_traits& t : all_method_traits())
    if (on_numbered_key(t, v)) out.push_back(t.id);
  return out;
}

// The methods of the fixed keys 9 and 0, in that order.
constexpr method k_fixed_key_methods[] = {method::ris, method::ris_mis};

// The order `m` cycles through: keys 1-8, then 9 (ris) and 0 (ris-mis).
std::vector<method> cycle_order(const window_view& v) {
  std::vector<method> out = window_methods(v);
  for (method m : k_fixed_key_methods)
    if (traits(m).gpu) out.push_back(m);
  return out;
}

bool uses_dirs(method m) { return traits(m).uses_dirs; }

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
  const std::vector<method> order = window_methods(v);
  const int kMethods = static_cast<int>(order.size());
  if (a.size() == 1 && a[0] >= '1' && a[0] < '1' + kMethods) {
    const method m = order[static_cast<std::size_t>(a[0] - '1')];
    if (m == v.meth) return false;
    v.meth = m;
    return true;
  }
  for (std::size_t k = 0; k < std::size(k_fixed_key_methods); ++k) {
    const method m = k_fixed_key_methods[k];
    if (a == (k == 0 ? "9" : "0") && traits(m).gpu) {
      if (v.meth == m) return false;
      v.meth = m;
      return true;
    }
  }
  if (a == "m") {
    const std::vector<method> cycle = cycle_order(v);
    const std::size_t n = cycle.size();
    std::size_t i = 0;
    while (i < n && cycle[i] != v.meth) ++i;
    v.meth = cycle[(i + 1) % n];
    return true;
  }
  if (a == "p") {
    if (v.meth != method::ris_mis) return false;  // the only method with a pool
    v.pool = v.pool > 0 ? 0 : std::max(v.pool_on, 1);
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
  if (v.meth == method::ris_mis) s += v.pool > 0 ? ", pool " + std::to_string(v.pool) : std::string(", no pool");
  return s;
}

}  // namespace vplrender
