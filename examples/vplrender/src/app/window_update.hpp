// SPDX-License-Identifier: MIT
#pragma once
// The --window loop's decisions, apart from GLFW so they can be tested: what the key actions of one
// pass of the event loop change, and whether that pass re-renders, only redraws, or does nothing.
// The window renders on demand: a pass with no change and no damage to the window touches nothing.
#include "cli/options.hpp"
#include "render/settings.hpp"

#include <string>
#include <vector>

namespace vplrender {

// What the keys change (the rest of the options stay as the command line gave them).
struct window_view {
  method meth = method::mis;
  int vpls = 0;
  int dirs = 0;
  bool exact = false;  // the frame has exact rays (--method or --visibility exact): key 8 and M reach exact
  // ris-mis's presampled candidate pool (--candidate-pool; 0: every candidate drawn from the
  // distribution) and the size that key P turns it back on with (the command line's, or the
  // option's default where the command line turned it off).
  int pool = 0;
  int pool_on = options{}.candidate_pool;
};

struct window_update {
  bool rerender = false;  // the settings changed: run_estimator again, then draw
  bool redraw = false;    // draw the image we have (first pass, after a re-render, the window was damaged)
  bool close = false;     // 'q' (actions after it in the same pass are dropped)
};

// Applies one key action ("0"-"9", "m", "+", "-", "p", "q"; see docs/renderer.md, "Window"; "8",
// exact, only with window_view::exact, and "p", the pool on or off, only with ris-mis, else they
// change nothing). Returns true when the view changed; sets
// *close for "q".
bool apply_window_action(window_view& v, const std::string& action, bool* close);

// One pass: the actions in order, then the decision. `damaged`: the window was resized, exposed or
// asked to refresh (GLFW's framebuffer-size and refresh callbacks); `first`: nothing drawn yet.
window_update plan_window_update(window_view& v, const std::vector<std::string>& actions, bool damaged, bool first);

// "mis, vpls 4, dirs 16" (dirs only for the methods that use them; ris-mis adds "pool P" or
// "no pool").
std::string window_samples_text(const window_view& v);

}  // namespace vplrender
