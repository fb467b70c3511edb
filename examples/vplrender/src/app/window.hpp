// SPDX-License-Identifier: MIT
#pragma once
// vplrender --window: an interactive GLFW view of the rendered image (docs/renderer.md, "Window").
// The pipeline keeps its own headless GL context on a worker thread (a context is current on one
// thread only, and keeping one per thread avoids switching between EGL and GLX on one thread);
// the window's context on the main thread only displays the tone-mapped image.
#include "cli/options.hpp"
#include "app/progress.hpp"
#include "cli/scene_setup.hpp"
#include "cli/render_options.hpp"
#include "render/stage_timer.hpp"

#include <memory>

namespace vplrender {

class window_session {
public:
  // Opens the window (throws input_error when there is no display or no GL 4.3 window context,
  // not_implemented_error when this build has no GLFW) and starts the pipeline's worker thread.
  window_session(const options& o, const prepared_scene& p);
  ~window_session();
  window_session(const window_session&) = delete;
  window_session& operator=(const window_session&) = delete;

  // The first image: prepare_buffers + run_estimator on the worker thread (what run_pipeline does).
  pipeline_result first_render(stage_timer& timer, const progress_fn& progress);
  // Shows the image and handles keys until closed (Esc, Q, the close button or o.frames passes of
  // the event loop). On demand: re-renders with run_estimator only when a key changes the settings,
  // redraws only then or when the window is resized or exposed, and otherwise sleeps in
  // glfwWaitEvents. Prints one line per re-render and a summary at the end on stdout.
  void run();

  struct impl;

private:
  std::unique_ptr<impl> impl_;
};

}  // namespace vplrender
