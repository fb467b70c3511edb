// vplrender: the example renderer's command line. This build parses the options, builds or loads
// the scene, frames and lights it, prints a summary and checks the output location; the
// rendering pipelines are not in this build yet, so it stops there with exit status 3 rather than
// write an image it did not render.
#include "errors.hpp"
#include "options.hpp"
#include "scene_setup.hpp"
#include "stage_timer.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>
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
    std::cout << describe(p, o) << std::flush;
    throw not_implemented_error(std::string("method '") + to_string(o.meth) + "' on the " + to_string(o.back) +
                                " backend is not implemented yet in this build; no image was written");
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
  } catch (const std::bad_alloc&) {
    std::cerr << "vplrender: error: out of memory\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "vplrender: internal error: " << e.what() << "\n";
    return 1;
  }
}
