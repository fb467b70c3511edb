// SPDX-License-Identifier: MIT
#pragma once
// The command line contract of vplrender: names, defaults, limits. Parsing produces a
// plain struct and touches nothing else, so it is tested without running anything.
#include "render/settings.hpp"

#include <glm/vec3.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace vplrender {

enum class progress_mode { automatic, always, never };

const char* to_string(progress_mode p);

// Limits: anything outside is "absurd" and refused with a message naming the flag.
struct limits {
  static constexpr int max_side = 16384;                 // --size, each side
  static constexpr long long max_pixels = 1LL << 26;     // --size, W * H (64 Mpixel)
  static constexpr int max_vpls = 1 << 20;               // --vpls
  static constexpr int max_dirs = 1 << 16;               // --dirs
  static constexpr int max_regions = 1024;               // --regions
  static constexpr int max_subset = 1 << 16;             // --global-subset, --local-subset (gather points)
  static constexpr long long max_subset_points = 1LL << 22;  // --regions x --local-subset (16 MiB of indices)
  static constexpr int min_voxels = 4, max_voxels = 1024;  // --voxels (per axis)
  static constexpr int min_dprsm = 8, max_dprsm = 4096;  // --dprsm (per face, per side)
  static constexpr int max_candidates = 1 << 16;         // --candidates (RIS candidates per sample)
  static constexpr int max_spatial = 16;                 // --spatial (vplkit::ris_max_neighbours)
  static constexpr int max_candidate_pool = 1 << 22;     // --candidate-pool (256 MiB of 64-byte entries)
  static constexpr int max_tiles = 1024;                 // --tiles
  static constexpr int max_tile_block = 64;              // --tile-block (texels per block side)
  static constexpr double max_exposure = 1e6;
  static constexpr int max_frames = 10000;           // --frames without --window (headless frames)
  static constexpr int max_window_frames = 1000000;  // --frames with --window
};

struct camera_option {
  glm::vec3 eye, target, up;
  float vfov_deg;
};

struct light_option {
  glm::vec3 position;
  std::optional<glm::vec3> intensity;  // W/sr; absent: keep the scene's (or the automatic) one
};

// The shared choices (render_choices: meth, vpls, dirs, regions_x/y, the switches, seed, direct)
// are the render settings' own, with their defaults; the rest is the command line's.
struct options : render_choices {
  std::string scene = "cornell";  // "cornell", "open" or an OBJ path
  backend back = backend::gpu;
  int width = 512, height = 512;
  std::string out = "vplrender.exr";
  int regions = 4;                // local CDF: number of image regions (regions_x * regions_y, the most
                                  // nearly square factorisation)
  int global_subset = 256;        // |S|: gather points of the global CDF's weights
  int local_subset = 256;         // |S_i|: gather points per region of the local CDFs' weights
  double eps = 0.05;              // defensive mixing weight (0 = the paper)
  double dmin_fraction = 0.01;    // VPL distance clamp / scene diagonal (0 = no clamp)
  // Absent: on with --backend cpu, off with gpu (whose estimate kernel does not have it yet).
  std::optional<clamp_compensation_choice> clamp_compensation;
  int candidates = 32;            // --method ris: candidates per sample
  ris_source_choice candidate_source = ris_source_choice::flux;  // --method ris: where they come from
  int spatial = 0;                // --method ris: spatial-reuse neighbours (0 = off)
  int candidate_pool = 16384;     // --method ris-mis: presampled candidates per frame (0 = off)
  int tiles = 64;                 // --candidate-source tiles: image tiles (the most nearly square grid)
  int tile_points = 8;            // gather points per tile
  int tile_block = 8;             // texel blocks' side
  int voxels = 128;               // voxel grid resolution per axis
  int dprsm = 512;                // paraboloid map resolution per face (2 faces)
  std::optional<camera_option> cam;
  std::optional<light_option> light;
  bool paper = false;
  bool window = false;            // show the result in a GLFW window (GPU backend)
  int frames = 0;                 // --window: close after this many frames (0 = when the user closes it);
                                  // without --window: render this many frames headless (0 = one render)
  std::vector<std::string> window_script;  // --window: key actions injected one per frame (1-7, m, +, -, q)
  float exposure = 1.0f;          // PNG preview only
  progress_mode progress = progress_mode::automatic;

  bool headless_frames() const { return frames > 0 && !window; }  // the frames benchmark (render/frames.hpp)
  std::string png_path() const;   // out with .exr replaced by .png
  std::string json_path() const;  // out with .exr replaced by .json
};

struct parse_result {
  enum class action { run, help };
  action what = action::run;
  options opts;
  std::string help;  // filled when what == help
};

// args[0] is the program name. Throws usage_error with a one-line message that names the flag.
// Explicit flags win over --paper whatever their order.
parse_result parse_command_line(const std::vector<std::string>& args);

// The --help text (every flag, its default and its limits).
std::string help_text(const std::string& program = "vplrender");

// A CLI11 parse error's message in the project's words: "--flag: needs a value", "--flag: given
// more than once", "unknown option: ... (see --help)"; other messages unchanged. speed_vs_error
// uses it for its own flags.
std::string explain_parse_error(const std::string& what);

// Grid for n regions: the factorisation x * y = n with x >= y and x - y smallest.
void region_grid(int n, int& x, int& y);

}  // namespace vplrender
