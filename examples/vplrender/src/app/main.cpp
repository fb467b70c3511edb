// SPDX-License-Identifier: MIT
// vplrender: the example renderer's command line. Parses the options, builds or loads the scene,
// frames and lights it, checks the output location, runs the pipeline (render/pipeline.hpp; with
// --frames and no window, N frames with a moving light: render/frames.hpp) and writes the EXR, the
// PNG preview and the JSON report.
#include "app/lighting_check.hpp"
#include "cli/options.hpp"
#include "app/progress.hpp"
#include "cli/render_options.hpp"
#include "app/report.hpp"
#include "cli/scene_setup.hpp"
#include "app/window.hpp"
#include "io/errors.hpp"
#include "io/exr_io.hpp"
#include "io/json_file.hpp"
#include "io/output_set.hpp"
#include "io/png_preview.hpp"
#include "render/frames.hpp"
#include "render/light_path.hpp"
#include "render/running_stage.hpp"
#include "render/stage_timer.hpp"

#include <headless_gl/compute.hpp>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include <unistd.h>

namespace {

using namespace vplrender;

// Fail before a long render, not after it: the output directory must exist and be writable.
void check_output_location(const options& o) {
  namespace fs = std::filesystem;
  fs::path dir = fs::path(o.out).parent_path();
  if (dir.empty()) dir = ".";
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw output_error("--out: directory '" + dir.string() + "' does not exist");
  if (::access(dir.c_str(), W_OK) != 0)
    throw output_error("--out: directory '" + dir.string() + "' is not writable (" + std::strerror(errno) + ")");
  for (const std::string& f : {o.out, o.png_path(), o.json_path()})
    if (fs::is_directory(f, ec)) throw output_error("--out: '" + f + "' is a directory");
}

std::string stage_or_setup(const std::string& stage) { return stage.empty() ? "setup" : stage; }

// Every position of the light's path must be a valid light (not inside a solid or on a surface),
// checked before the first frame; the message names --frames and the frame.
void check_light_path(const scene& s, const light_path& path) {
  scene moved = s;
  for (int k = 0; k < path.count; ++k) {
    moved.light.position = path.at(k);
    try {
      check_light_position(moved, "light of frame " + std::to_string(k));
    } catch (const input_error& e) {
      throw input_error(std::string("--frames: the light's path (") + path.rule() + ") leaves the free space: " + e.what() +
                        "; move the light with --light");
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv, argv + argc);
  options o;
  try {
    parse_result r = parse_command_line(args);
    if (r.what == parse_result::action::help) {
      std::cout << r.help;
      return 0;
    }
    o = r.opts;
  } catch (const usage_error& e) {
    std::cerr << "vplrender: error: " << e.what() << "\n";
    return 2;
  }

  try {
    stage_timer timer;
    prepared_scene p;
    {
      auto t = timer.scoped("scene");
      p = prepare_scene(o);
    }
    for (const std::string& w : p.s.warnings) std::cerr << "vplrender: warning: " << w << "\n";
    check_output_location(o);
    // The three outputs are one set: temporaries beside them from now on (removed on an error or
    // SIGINT/SIGTERM), renamed into place together once all three are written.
    output_set outputs;
    for (const std::string& f : {o.out, o.png_path(), o.json_path()}) outputs.reserve(f);
    std::cout << describe(p, o);
    if (o.back == backend::cpu)
      std::cout << "estimator backend: cpu (C++ templates)\n";
    else if (has_distribution(o.meth))
      std::cout << "estimator backend: gpu (compute shader from the GLSL pack; builder weights, CDFs and direct "
                   "light on the GPU)\nbuilders backend: gpu\n";
    else
      std::cout << "estimator backend: gpu (compute shader from the GLSL pack; no builders; direct light on the "
                   "GPU)\n";
    std::cout << std::flush;
    // The window opens before the render so that a missing display fails fast.
    std::unique_ptr<window_session> win;
    if (o.window) win = std::make_unique<window_session>(o, p);

    const bool show = progress_enabled(o.progress);
    std::unique_ptr<progress_bar> bar;
    std::string bar_label;
    const progress_fn progress = [&](const std::string& label, std::uint64_t done, std::uint64_t total) {
      if (!bar || label != bar_label) {
        if (bar) bar->finish();
        bar = std::make_unique<progress_bar>(label, total, show, std::cerr);
        bar_label = label;
      }
      bar->update(done);
    };
    pipeline_result res;
    nlohmann::json frames;  // --frames without --window: the per-frame times
    if (o.headless_frames()) {
      const light_path path = make_light_path(p.s, o.frames);
      check_light_path(p.s, path);
      const frames_run fr = run_frames(p.s, make_frame_settings(o), make_render_settings(o, p.s), path, timer);
      double sum = 0.0;
      for (double ms : fr.frame_ms) sum += ms;
      timer.add("frames (" + std::to_string(fr.frame_ms.size()) + " timed)", sum, "cpu-wall");
      res.image = fr.last_image;
      res.details = fr.last_details;
      res.gl_renderer = fr.gl_renderer;
      frames = frames_report(fr, path);
      std::cout << "frames    " << fr.frame_ms.size() << " timed after 1 warm-up, median "
                << frames["median_ms"].get<double>() << " ms (" << frames["fps"].get<double>()
                << " frames/s), light on a circle of radius " << path.radius << "; writing frame "
                << path.count - 1 << "'s image\n";
    } else {
      res = win ? win->first_render(timer, progress) : run_pipeline(o, p, timer, progress);
    }
    if (bar) bar->finish();
    bar.reset();

    run_info run;
    run.gl_renderer = res.gl_renderer;
    run.warnings = p.s.warnings;
    {
      const nlohmann::json& g = res.details.at("gbuffer");
      lighting_facts facts;
      facts.pixels = res.image.rgb.size() / 3;
      facts.visible_pixels = g.at("valid_pixels").get<std::size_t>();
      facts.directly_lit_pixels = g.at("directly_lit_pixels").get<std::size_t>();
      facts.image_black = image_is_black(res.image);
      for (const std::string& w : lighting_warnings(p, o, facts)) {
        std::cerr << "vplrender: warning: " << w << "\n";
        run.warnings.push_back(w);
      }
    }
    {
      auto t = timer.scoped("write outputs");
      write_exr(outputs, o.out, res.image,
                {{"vplrender:method", to_string(o.meth)}, {"vplrender:scene", p.s.name},
                 {"vplrender:seed", std::to_string(o.seed)}});
      write_png_preview(outputs, o.png_path(), res.image, o.exposure);
    }
    run.outputs = {o.out, o.png_path(), o.json_path()};
    run.stages = timer.stages();
    nlohmann::json report = make_report(o, p, run);
    report["pipeline"] = res.details;
    if (!frames.is_null()) report["frames"] = frames;
    report["host_peak_rss_bytes"] = host_peak_rss_bytes();
    write_json(outputs, o.json_path(), report);
    outputs.publish();
    double total = 0.0;
    for (const stage_time& st : run.stages) total += st.ms;
    std::cout << "wrote " << o.out << ", " << o.png_path() << ", " << o.json_path() << " (" << static_cast<long long>(total)
              << " ms)\n";
    if (win) {
      std::cout << std::flush;
      win->run();
    }
    return 0;
  } catch (const not_implemented_error& e) {
    std::cerr << "vplrender: error: " << e.what() << "\n";
    return 3;
  } catch (const usage_error& e) {
    std::cerr << "vplrender: error: " << e.what() << "\n";
    return 2;
  } catch (const input_error& e) {
    std::cerr << "vplrender: error: " << e.what() << "\n";
    return 1;
  } catch (const output_error& e) {
    std::cerr << "vplrender: error: " << e.what() << "\n";
    return 1;
  } catch (const out_of_memory_error& e) {
    std::cerr << "vplrender: error: " << e.what() << "\n";
    return 1;
  } catch (const vplkit::gl::gl_out_of_memory& e) {
    // A GL buffer made outside allocating(): the stage it failed in, the size when known.
    std::cerr << "vplrender: error: " << stage_or_setup(failed_stage()) << ": out of memory on the GPU"
              << (e.bytes() > 0 ? " allocating " + mebibytes(e.bytes()) + " for a buffer" : std::string()) << " ("
              << e.what() << ")\n";
    return 1;
  } catch (const vplkit::gl::gl_error& e) {
    std::cerr << "vplrender: error: OpenGL: " << e.what() << "\n";
    return 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "vplrender: error: " << stage_or_setup(failed_stage()) << ": out of memory (host)\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "vplrender: internal error: " << e.what() << "\n";
    return 1;
  }
}
