// SPDX-License-Identifier: MIT
// --window renders on demand (app/window_update.hpp): which passes of the event loop re-render,
// which only redraw, and which do nothing at all.
#include "app/window_update.hpp"

#include <catch2/catch.hpp>

using namespace vplrender;

namespace {
window_view view(method m, int vpls, int dirs) { return window_view{m, vpls, dirs, false}; }
}  // namespace

TEST_CASE("a pass with no key and no damage does nothing", "[renderer][window]") {
  window_view v = view(method::mis, 4, 16);
  const window_update u = plan_window_update(v, {}, false, false);
  CHECK_FALSE(u.rerender);
  CHECK_FALSE(u.redraw);
  CHECK_FALSE(u.close);
}

TEST_CASE("the first pass draws the image it has without rendering it again", "[renderer][window]") {
  window_view v = view(method::mis, 4, 16);
  const window_update u = plan_window_update(v, {}, false, true);
  CHECK_FALSE(u.rerender);
  CHECK(u.redraw);
}

TEST_CASE("a resize or expose redraws, never re-renders", "[renderer][window]") {
  window_view v = view(method::gbg, 4, 16);
  const window_update u = plan_window_update(v, {}, true, false);
  CHECK_FALSE(u.rerender);
  CHECK(u.redraw);
}

TEST_CASE("a key that changes the settings re-renders and redraws", "[renderer][window]") {
  window_view v = view(method::mis, 4, 16);
  window_update u = plan_window_update(v, {"+"}, false, false);
  CHECK(u.rerender);
  CHECK(u.redraw);
  CHECK(v.vpls == 8);
  CHECK(v.dirs == 32);
  u = plan_window_update(v, {"2"}, false, false);
  CHECK(u.rerender);
  CHECK(v.meth == method::global);
  CHECK(window_samples_text(v) == "global, vpls 8");
}

TEST_CASE("a key that changes nothing does not re-render", "[renderer][window]") {
  window_view v = view(method::global, 1, 16);
  CHECK_FALSE(plan_window_update(v, {"-"}, false, false).rerender);  // already 1 VPL; global has no dirs
  CHECK(v.dirs == 16);
  CHECK_FALSE(plan_window_update(v, {"2"}, false, false).rerender);  // already global
  v = view(method::gather, limits::max_vpls, limits::max_dirs);
  CHECK_FALSE(plan_window_update(v, {"+"}, false, false).rerender);  // both at their caps
}

TEST_CASE("several keys in one pass re-render once, with their combined effect", "[renderer][window]") {
  window_view v = view(method::reference, 4, 2);
  const window_update u = plan_window_update(v, {"m", "m", "+", "-", "-"}, false, false);
  CHECK(u.rerender);
  CHECK(v.meth == method::local);
  CHECK(v.vpls == 2);
  CHECK(v.dirs == 2);  // local has no dirs
  // "+" then "-" changed the settings twice: the pass re-renders (once) even though they end
  // where they started (a change is a change; comparing with the displayed image is not worth it).
  window_view w = view(method::mis, 4, 16);
  CHECK(plan_window_update(w, {"+", "-"}, false, false).rerender);
}

TEST_CASE("q closes: no render, and the keys after it are dropped", "[renderer][window]") {
  window_view v = view(method::mis, 4, 16);
  const window_update u = plan_window_update(v, {"+", "q", "m"}, true, false);
  CHECK(u.close);
  CHECK_FALSE(u.rerender);
  CHECK_FALSE(u.redraw);
  CHECK(v.meth == method::mis);
}

TEST_CASE("m goes from the seventh method to ris (key 9), ris-mis (key 0), then wraps", "[renderer][window]") {
  window_view v = view(method::mis_as_published, 4, 16);
  CHECK(plan_window_update(v, {"m"}, false, false).rerender);
  CHECK(v.meth == method::ris);
  CHECK(plan_window_update(v, {"m"}, false, false).rerender);
  CHECK(v.meth == method::ris_mis);
  CHECK(plan_window_update(v, {"m"}, false, false).rerender);
  CHECK(v.meth == method::reference);
}

TEST_CASE("0 selects ris-mis, whose dirs follow + and - with its vpls", "[renderer][window]") {
  window_view v = view(method::global, 4, 16);
  CHECK(plan_window_update(v, {"0"}, false, false).rerender);
  CHECK(v.meth == method::ris_mis);
  CHECK_FALSE(plan_window_update(v, {"0"}, false, false).rerender);  // already ris-mis
  CHECK(plan_window_update(v, {"+"}, false, false).rerender);
  CHECK(v.vpls == 8);
  CHECK(v.dirs == 32);
  CHECK(window_samples_text(v) == "ris-mis, vpls 8, dirs 32, no pool");  // view(): pool 0
}

TEST_CASE("8 and m reach exact only on a frame with exact rays, and exact's dirs follow + and -", "[renderer][window]") {
  window_view v = view(method::mis_as_published, 4, 16);
  CHECK_FALSE(plan_window_update(v, {"8"}, false, false).rerender);  // no exact rays: 8 changes nothing
  CHECK(v.meth == method::mis_as_published);
  v.exact = true;
  CHECK(plan_window_update(v, {"m"}, false, false).rerender);
  CHECK(v.meth == method::exact);
  CHECK(plan_window_update(v, {"+"}, false, false).rerender);
  CHECK(v.dirs == 32);
  CHECK(window_samples_text(v) == "exact, vpls 8, dirs 32");
  CHECK(plan_window_update(v, {"m"}, false, false).rerender);
  CHECK(v.meth == method::ris);
  CHECK(plan_window_update(v, {"m", "m"}, false, false).rerender);
  CHECK(v.meth == method::reference);
  CHECK(plan_window_update(v, {"8"}, false, false).rerender);
  CHECK(v.meth == method::exact);
}

TEST_CASE("p turns ris-mis's candidate pool off and back on to its size, and does nothing elsewhere",
          "[renderer][window]") {
  window_view v = view(method::ris_mis, 4, 4);
  v.pool = 4096;
  v.pool_on = 4096;
  CHECK(window_samples_text(v) == "ris-mis, vpls 4, dirs 4, pool 4096");
  window_update u = plan_window_update(v, {"p"}, false, false);
  CHECK(u.rerender);
  CHECK(v.pool == 0);
  CHECK(window_samples_text(v) == "ris-mis, vpls 4, dirs 4, no pool");
  u = plan_window_update(v, {"p"}, false, false);
  CHECK(u.rerender);
  CHECK(v.pool == 4096);
  // Twice in one pass: back where it was, still one render (the settings went through a change).
  u = plan_window_update(v, {"p", "p"}, false, false);
  CHECK(v.pool == 4096);
  // Started without a pool (--candidate-pool 0): on at pool_on.
  v.pool = 0;
  v.pool_on = 16384;
  plan_window_update(v, {"p"}, false, false);
  CHECK(v.pool == 16384);
  // Another method has no pool: nothing changes, no render.
  window_view g = view(method::gather, 4, 16);
  g.pool = 16384;
  u = plan_window_update(g, {"p"}, false, false);
  CHECK_FALSE(u.rerender);
  CHECK(g.pool == 16384);
  CHECK(window_samples_text(g) == "gather, vpls 4, dirs 16");
  // After switching to ris-mis (key 0) the key acts.
  u = plan_window_update(g, {"0", "p"}, false, false);
  CHECK(u.rerender);
  CHECK(g.meth == method::ris_mis);
  CHECK(g.pool == 0);
}
