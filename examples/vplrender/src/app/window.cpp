// SPDX-License-Identifier: MIT
#include "app/window.hpp"

#include "app/window_update.hpp"

#include "io/errors.hpp"
#include "io/png_preview.hpp"

#if VPLRENDER_HAVE_GLFW
// epoxy before GLFW: it replaces GL/gl.h, and GLFW_INCLUDE_NONE keeps GLFW from including it.
#include <epoxy/gl.h>
#include <headless_gl/compute.hpp>
#include <headless_gl/raster_program.hpp>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#endif

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <functional>
#include <future>
#include <iostream>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>

namespace vplrender {

#if VPLRENDER_HAVE_GLFW

namespace {

// One thread that owns the pipeline's headless context: every pipeline call runs on it, so that
// context stays current there and the window's context stays current on the main thread.
class gl_worker {
public:
  gl_worker() : thread_([this] { loop(); }) {}
  ~gl_worker() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      quit_ = true;
    }
    cv_.notify_all();
    thread_.join();
  }
  std::future<void> submit(std::function<void()> f) {
    auto task = std::make_shared<std::packaged_task<void()>>(std::move(f));
    std::future<void> result = task->get_future();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      jobs_.push_back([task] { (*task)(); });
    }
    cv_.notify_all();
    return result;
  }

private:
  void loop() {
    for (;;) {
      std::function<void()> job;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        cv_.wait(lock, [this] { return quit_ || !jobs_.empty(); });
        if (jobs_.empty()) return;
        job = std::move(jobs_.front());
        jobs_.pop_front();
      }
      job();
    }
  }
  std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<std::function<void()>> jobs_;
  bool quit_ = false;
  std::thread thread_;
};

const char* kVertex = R"(#version 430 core
out vec2 uv;
void main() {
  // One triangle covering the viewport: (0,0), (2,0), (0,2) in uv.
  uv = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  gl_Position = vec4(uv * 2.0 - 1.0, 0.0, 1.0);
}
)";
// The texture holds the PNG preview's bytes (already tone-mapped and sRGB-encoded), row 0 = top.
const char* kFragment = R"(#version 430 core
in vec2 uv;
out vec4 color;
uniform sampler2D image;
void main() { color = vec4(texture(image, vec2(uv.x, 1.0 - uv.y)).rgb, 1.0); }
)";

std::string glfw_error_text() {
  const char* d = nullptr;
  const int code = glfwGetError(&d);
  return code == GLFW_NO_ERROR ? std::string("unknown error") : std::string(d ? d : "no description");
}

}  // namespace

struct window_session::impl {
  options o;
  const prepared_scene& p;
  GLFWwindow* win = nullptr;
  vplkit::gl::program program;  // deleted with the window's context current (see ~impl)
  GLuint vao = 0, tex = 0;
  std::unique_ptr<frame_buffers> buffers;  // voxel_grid has no default constructor
  std::unique_ptr<gl_worker> worker;
  std::deque<std::string> pending;  // key actions from the keyboard
  bool damaged = false;             // resized, exposed or asked to refresh: draw again
  double last_ms = 0.0;
  // The pool size key P turns ris-mis's pool back on with: the command line's, or the default.
  int pool_on = 0;

  impl(const options& opts, const prepared_scene& ps) : o(opts), p(ps), pool_on(opts_pool_on(opts)) {}

  static int opts_pool_on(const options& opts) {
    return opts.candidate_pool > 0 ? opts.candidate_pool : options{}.candidate_pool;
  }

  ~impl() {
    worker.reset();  // the headless context's thread ends before the window goes
    if (win) {
      glfwMakeContextCurrent(win);
      if (tex) glDeleteTextures(1, &tex);
      if (vao) glDeleteVertexArrays(1, &vao);
      program = vplkit::gl::program();
      glfwDestroyWindow(win);
    }
    glfwTerminate();
  }

  void open() {
    if (!glfwInit()) throw input_error("--window: cannot open a window (GLFW: " + glfw_error_text() + ")");
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    // Small images are shown enlarged by an integer factor (nearest texels), up to ~512 pixels.
    const int scale = std::max(1, 512 / std::max(o.width, o.height));
    win = glfwCreateWindow(o.width * scale, o.height * scale, "vplrender", nullptr, nullptr);
    if (!win) throw input_error("--window: cannot open a window (GLFW: " + glfw_error_text() + ")");
    glfwSetWindowUserPointer(win, this);
    glfwSetKeyCallback(win, [](GLFWwindow* w, int key, int, int action, int) {
      if (action != GLFW_PRESS && action != GLFW_REPEAT) return;
      auto* self = static_cast<impl*>(glfwGetWindowUserPointer(w));
      std::string a;
      if (key >= GLFW_KEY_0 && key <= GLFW_KEY_9) a = std::string(1, static_cast<char>('0' + key - GLFW_KEY_0));
      else if (key >= GLFW_KEY_KP_0 && key <= GLFW_KEY_KP_9) a = std::string(1, static_cast<char>('0' + key - GLFW_KEY_KP_0));
      else if (key == GLFW_KEY_M) a = "m";
      else if (key == GLFW_KEY_P) a = "p";
      else if (key == GLFW_KEY_EQUAL || key == GLFW_KEY_KP_ADD) a = "+";
      else if (key == GLFW_KEY_MINUS || key == GLFW_KEY_KP_SUBTRACT) a = "-";
      else if (key == GLFW_KEY_ESCAPE || key == GLFW_KEY_Q) a = "q";
      if (!a.empty()) self->pending.push_back(a);
    });
    // Resizing or exposing the window only needs the image drawn again, not rendered.
    glfwSetFramebufferSizeCallback(win, [](GLFWwindow* w, int, int) {
      static_cast<impl*>(glfwGetWindowUserPointer(w))->damaged = true;
    });
    glfwSetWindowRefreshCallback(win, [](GLFWwindow* w) { static_cast<impl*>(glfwGetWindowUserPointer(w))->damaged = true; });
    glfwMakeContextCurrent(win);
    glfwSwapInterval(1);
    program = vplkit::gl::raster_program("--window display", kVertex, kFragment);
    glGenVertexArrays(1, &vao);  // core profile: a draw needs a bound VAO, even without attributes
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGB8, o.width, o.height);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    glfwSwapBuffers(win);
    worker = std::make_unique<gl_worker>();
  }

  // Runs f on the worker, keeping the window's event queue drained while it works (keys pressed
  // meanwhile are queued and applied afterwards). Rethrows what f threw.
  void on_worker(std::function<void()> f) {
    std::future<void> done = worker->submit(std::move(f));
    while (done.wait_for(std::chrono::milliseconds(30)) != std::future_status::ready) glfwPollEvents();
    done.get();
  }

  void upload(const image_rgb& img) {
    const std::vector<std::uint8_t> bytes = tonemap_reinhard(img, o.exposure);
    glBindTexture(GL_TEXTURE_2D, tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, o.width, o.height, GL_RGB, GL_UNSIGNED_BYTE, bytes.data());
  }

  window_view view() const {
    window_view v{o.meth, o.vpls, o.dirs, buffers && buffers->rays};
    v.pool = o.candidate_pool;
    v.pool_on = pool_on;
    return v;
  }
  void set_view(const window_view& v) {
    o.meth = v.meth;
    o.vpls = v.vpls;
    o.dirs = v.dirs;
    o.candidate_pool = v.pool;
  }

  void set_title() {
    char ms[32];
    std::snprintf(ms, sizeof ms, "%.0f ms", last_ms);
    const std::string t = "vplrender - " + window_samples_text(view()) + " - " + ms;
    glfwSetWindowTitle(win, t.c_str());
  }

  void rerender() {
    render_result r;
    const auto t0 = std::chrono::steady_clock::now();
    on_worker([&] {
      stage_timer timer;
      nlohmann::json det;
      r = run_estimator(o, p, *buffers, timer, {}, det);
    });
    last_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    upload(r.image);
  }

  void draw() {
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(win, &fw, &fh);
    glViewport(0, 0, fw, fh);
    glClear(GL_COLOR_BUFFER_BIT);
    // Letterbox: keep the image's aspect ratio inside whatever size the window has now.
    const double s = std::min(static_cast<double>(fw) / o.width, static_cast<double>(fh) / o.height);
    const int w = std::max(1, static_cast<int>(o.width * s)), h = std::max(1, static_cast<int>(o.height * s));
    glViewport((fw - w) / 2, (fh - h) / 2, w, h);
    program.use();
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, tex);
    glUniform1i(program.uniform_location("image"), 0);
    glBindVertexArray(vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glfwSwapBuffers(win);
  }
};

window_session::window_session(const options& o, const prepared_scene& p) : impl_(std::make_unique<impl>(o, p)) {
  impl_->open();
}

window_session::~window_session() = default;

pipeline_result window_session::first_render(stage_timer& timer, const progress_fn& progress) {
  impl& d = *impl_;
  pipeline_result r;
  const auto t0 = std::chrono::steady_clock::now();
  d.on_worker([&] {
    d.buffers = std::make_unique<frame_buffers>(prepare_buffers(d.o, d.p, timer, r.details));
    r.gl_renderer = d.buffers->gl_renderer;
    r.image = std::move(run_estimator(d.o, d.p, *d.buffers, timer, progress, r.details).image);
  });
  d.last_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  d.upload(r.image);
  d.set_title();
  return r;
}

void window_session::run() {
  impl& d = *impl_;
  std::size_t next_script = 0;
  int pass = 0, rerenders = 0, redraws = 0;
  for (;;) {
    ++pass;
    // One injected action per pass from the second pass on, then what the keyboard queued.
    if (pass > 1 && next_script < d.o.window_script.size()) d.pending.push_back(d.o.window_script[next_script++]);
    const std::vector<std::string> actions(d.pending.begin(), d.pending.end());
    d.pending.clear();
    window_view v = d.view();
    const window_update u = plan_window_update(v, actions, std::exchange(d.damaged, false), pass == 1);
    if (u.close || glfwWindowShouldClose(d.win)) break;
    if (u.rerender) {
      d.set_view(v);
      d.rerender();
      d.set_title();
      ++rerenders;
      std::cout << "window re-render " << rerenders << ": " << window_samples_text(v) << ", "
                << static_cast<long long>(d.last_ms + 0.5) << " ms (pass " << pass << ")" << std::endl;
    }
    if (u.redraw) {
      d.draw();
      ++redraws;
    }
    if (d.o.frames > 0 && pass >= d.o.frames) break;
    // On demand: sleep until an event unless work is queued (keys pressed during a render, a
    // damage event) or scheduled (script actions, a pass limit).
    if (d.o.frames > 0 || next_script < d.o.window_script.size() || !d.pending.empty() || d.damaged)
      glfwPollEvents();
    else
      glfwWaitEvents();
  }
  std::cout << "window closed after " << pass << " passes: " << rerenders << " re-renders, " << redraws << " redraws"
            << std::endl;
}

#else  // no GLFW in this build

struct window_session::impl {};

window_session::window_session(const options&, const prepared_scene&) {
  throw not_implemented_error("--window: this build has no GLFW (install libglfw3-dev and reconfigure)");
}
window_session::~window_session() = default;
pipeline_result window_session::first_render(stage_timer&, const progress_fn&) { return {}; }
void window_session::run() {}

#endif

}  // namespace vplrender
