// SPDX-License-Identifier: MIT
// speed_vs_error: for one scene, every requested method over a sweep of sample counts in one
// process. The scene, G-buffer, DPRSM and voxel grid are prepared once (prepare_buffers) and every
// run reuses them (run_estimator); each run is timed per stage and compared with three references
// (docs/math.md section 8): (a) the exhaustive VPL sum (method reference), (b) converged
// gathering (method gather at --ref-dirs directions) and (c) the ground truth (method exact at
// --ref-exact-dirs directions: exact visibility, no VPLs). Writes PREFIX.csv, PREFIX.md and PREFIX.svg.
#include "analysis_writer.hpp"
#include "replot.hpp"
#include "sve_options.hpp"
#include "sweep.hpp"

#include "io/errors.hpp"

#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  using namespace vplrender;
  using namespace speed_vs_error;
  namespace fs = std::filesystem;
  const std::vector<std::string> args(argv, argv + argc);
  sweep_options so;
  try {
    if (!parse_sweep_options(args, so)) {
      std::cout << k_help;
      return 0;
    }
  } catch (const usage_error& e) {
    std::cerr << "speed_vs_error: error: " << e.what() << "\n";
    return 2;
  }
  try {
    if (!so.replot.empty()) {
      const std::vector<std::string> files = replot(so.replot, so.out);
      std::cout << "wrote";
      for (std::size_t i = 0; i < files.size(); ++i) std::cout << (i ? ", " : " ") << files[i];
      std::cout << "\n";
      return 0;
    }
    {
      // Fail before the sweep, not after it.
      fs::path dir = fs::path(so.out).parent_path();
      std::error_code ec;
      if (!dir.empty() && !fs::is_directory(dir, ec))
        throw output_error("--out: directory '" + dir.string() + "' does not exist");
    }
    const prepared_scene p = prepare_scene(so.base);
    for (const std::string& w : p.s.warnings) std::cerr << "speed_vs_error: warning: " << w << "\n";
    const sweep_frame frame = prepare_sweep_frame(so, p);
    const sweep_references refs = get_references(so, p, frame);
    const sweep_result result = run_sweep(so, p, frame, refs);
    write_sweep_outputs(so, p, frame, refs, result);
    return 0;
  } catch (const usage_error& e) {
    std::cerr << "speed_vs_error: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "speed_vs_error: error: " << e.what() << "\n";
    return 1;
  }
}
