// SPDX-License-Identifier: MIT
// Command-line parsing of vplrender: every flag, its limits and its errors, without running
// anything.
#include <catch2/catch.hpp>

#include "renderer_cli_parse.hpp"
#include "cli/options.hpp"
#include "io/errors.hpp"

#include <string>
#include <vector>

using namespace vplrender;

using namespace vplrender_test;

TEST_CASE("defaults without any flag") {
  const options o = parse({});
  CHECK(o.scene == "cornell");
  CHECK(o.meth == method::mis);
  CHECK(o.back == backend::gpu);
  CHECK(o.width == 512);
  CHECK(o.height == 512);
  CHECK(o.vpls == 64);
  CHECK(o.seed == 1u);
  CHECK(o.out == "vplrender.exr");
  CHECK(o.png_path() == "vplrender.png");
  CHECK(o.json_path() == "vplrender.json");
  CHECK(o.regions == 4);
  CHECK(o.regions_x == 2);
  CHECK(o.regions_y == 2);
  CHECK(o.dirs == 16);
  CHECK(o.eps == Approx(0.05));
  CHECK(o.voxels == 128);
  CHECK(o.dprsm == 512);
  CHECK_FALSE(o.cam.has_value());
  CHECK_FALSE(o.light.has_value());
  CHECK_FALSE(o.paper);
  CHECK_FALSE(o.direct);
  CHECK_FALSE(o.window);
  CHECK(o.exposure == 1.0f);
  CHECK(o.progress == progress_mode::automatic);
}

TEST_CASE("every flag is parsed into the options struct") {
  const options o = parse({"--scene", "open", "--method", "gbg", "--backend", "cpu", "--size", "640x480", "--vpls",
                           "800", "--seed", "4294967295", "--out", "out/dir/img.EXR", "--regions", "6", "--dirs",
                           "32", "--eps", "0.25", "--voxels", "64", "--dprsm", "256", "--camera",
                           "1,2,3, 0,0,0, 0,1,0, 60", "--light", "0.5,1.5,-2,1,2,3", "--direct", "--exposure",
                           "2.5", "--progress", "never"});
  CHECK(o.scene == "open");
  CHECK(o.meth == method::gbg);
  CHECK(o.back == backend::cpu);
  CHECK(o.width == 640);
  CHECK(o.height == 480);
  CHECK(o.vpls == 800);
  CHECK(o.seed == 4294967295u);
  CHECK(o.out == "out/dir/img.EXR");
  CHECK(o.png_path() == "out/dir/img.png");
  CHECK(o.json_path() == "out/dir/img.json");
  CHECK(o.regions == 6);
  CHECK(o.regions_x == 3);
  CHECK(o.regions_y == 2);
  CHECK(o.dirs == 32);
  CHECK(o.eps == Approx(0.25));
  CHECK(o.voxels == 64);
  CHECK(o.dprsm == 256);
  REQUIRE(o.cam.has_value());
  CHECK(o.cam->eye == glm::vec3(1, 2, 3));
  CHECK(o.cam->target == glm::vec3(0, 0, 0));
  CHECK(o.cam->up == glm::vec3(0, 1, 0));
  CHECK(o.cam->vfov_deg == 60.0f);
  REQUIRE(o.light.has_value());
  CHECK(o.light->position == glm::vec3(0.5f, 1.5f, -2.0f));
  REQUIRE(o.light->intensity.has_value());
  CHECK(*o.light->intensity == glm::vec3(1, 2, 3));
  CHECK(o.direct);
  CHECK(o.exposure == 2.5f);
  CHECK(o.progress == progress_mode::never);
  CHECK(parse({"--window"}).window);
  CHECK(parse({"--progress", "always"}).progress == progress_mode::always);
  CHECK(parse({"--progress", "auto"}).progress == progress_mode::automatic);
  CHECK(parse({"--scene", "some/dir/file.obj"}).scene == "some/dir/file.obj");
  CHECK(parse({"--size=32X16"}).width == 32);
  CHECK(parse({"--seed", "0"}).seed == 0u);
}

TEST_CASE("every method name of the contract is accepted, and nothing else") {
  const std::pair<const char*, method> names[] = {
      {"reference", method::reference}, {"global", method::global}, {"local", method::local}, {"gbg", method::gbg},
      {"gather", method::gather},       {"mis", method::mis},       {"mis-as-published", method::mis_as_published},
      {"exact", method::exact}};
  for (const auto& [name, m] : names) {
    CHECK(parse({"--method", name}).meth == m);
    CHECK(std::string(to_string(m)) == name);
  }
  CHECK(starts_with(error_of({"--method", "MIS"}), "--method: unknown value 'MIS'"));
  CHECK(starts_with(error_of({"--backend", "vulkan"}), "--backend: unknown value 'vulkan'"));
  CHECK(starts_with(error_of({"--progress", "sometimes"}), "--progress:"));
}

TEST_CASE("a --light with a position only keeps the intensity open") {
  const options o = parse({"--light", "1,2,3"});
  REQUIRE(o.light.has_value());
  CHECK(o.light->position == glm::vec3(1, 2, 3));
  CHECK_FALSE(o.light->intensity.has_value());
}

TEST_CASE("the --paper flag sets the paper's parameters and explicit flags win in any order") {
  const options p = parse({"--paper"});
  CHECK(p.paper);
  CHECK(p.width == 512);
  CHECK(p.height == 512);
  CHECK(p.dprsm == 512);
  CHECK(p.voxels == 128);
  CHECK(p.vpls == 800);
  CHECK(p.regions == 4);
  CHECK(p.dirs == 800);
  const options a = parse({"--vpls", "100", "--paper", "--size", "64x32"});
  CHECK(a.vpls == 100);
  CHECK(a.width == 64);
  CHECK(a.height == 32);
  CHECK(a.voxels == 128);
  const options b = parse({"--paper", "--vpls", "100"});
  CHECK(b.vpls == 100);
}

TEST_CASE("unknown flags and stray arguments are refused, naming them") {
  CHECK(error_of({"--bogus"}) == "unknown option: --bogus (see --help)");
  CHECK(starts_with(error_of({"--vpls", "5", "stray"}), "unexpected argument: stray"));
  CHECK(starts_with(error_of({"-x"}), "unknown option: -x"));
}

TEST_CASE("a flag given twice or without its value is refused") {
  CHECK(error_of({"--vpls", "5", "--vpls", "6"}) == "--vpls: given more than once");
  CHECK(starts_with(error_of({"--vpls"}), "--vpls"));
  CHECK(starts_with(error_of({"--out"}), "--out"));
}

TEST_CASE("zero, negative, absurd and malformed counts are refused, naming the flag") {
  const char* count_flags[] = {"--vpls", "--regions", "--dirs", "--voxels", "--dprsm"};
  for (const char* f : count_flags) {
    INFO(f);
    CHECK(starts_with(error_of({f, "0"}), std::string(f) + ":"));
    CHECK(starts_with(error_of({f, "-3"}), std::string(f)));
    CHECK(starts_with(error_of({f, "12abc"}), std::string(f) + ":"));
    CHECK(starts_with(error_of({f, "1.5"}), std::string(f) + ":"));
    CHECK(starts_with(error_of({f, "99999999999999999999999"}), std::string(f) + ":"));
    CHECK(starts_with(error_of({f, ""}), std::string(f) + ":"));
  }
  CHECK(starts_with(error_of({"--vpls", "1048577"}), "--vpls: value 1048577 is outside 1..1048576"));
  CHECK(parse({"--vpls", "1048576"}).vpls == 1048576);
  CHECK(starts_with(error_of({"--voxels", "3"}), "--voxels:"));
  CHECK(starts_with(error_of({"--voxels", "1025"}), "--voxels:"));
  CHECK(starts_with(error_of({"--dprsm", "7"}), "--dprsm:"));
  CHECK(starts_with(error_of({"--dprsm", "4097"}), "--dprsm:"));
  CHECK(starts_with(error_of({"--dirs", "65537"}), "--dirs:"));
  CHECK(starts_with(error_of({"--regions", "1025"}), "--regions:"));
  CHECK(starts_with(error_of({"--seed", "4294967296"}), "--seed:"));
  CHECK(starts_with(error_of({"--seed", "-1"}), "--seed"));
}

TEST_CASE("zero, absurd and malformed sizes are refused") {
  for (const char* s : {"0x512", "512x0", "0x0", "512", "x512", "512x", "16385x1", "1x16385", "axb", "512x512x3",
                        "-5x5", "16384x16384"}) {
    INFO(s);
    CHECK(starts_with(error_of({"--size", s}), "--size:"));
  }
  CHECK(parse({"--size", "1x1", "--regions", "1"}).width == 1);
  CHECK(parse({"--size", "16384x4096"}).width == 16384);
}

TEST_CASE("ranges of --eps and --exposure") {
  CHECK(parse({"--eps", "0"}).eps == 0.0);
  CHECK(parse({"--eps", "1"}).eps == 1.0);
  CHECK(parse({"--eps", "1e-3"}).eps == Approx(1e-3));
  for (const char* e : {"-0.1", "1.5", "nan", "inf", "0x1p-3", "abc", ""}) {
    INFO(e);
    CHECK(starts_with(error_of({"--eps", e}), "--eps:"));
  }
  for (const char* e : {"0", "-1", "1e7", "nan"}) {
    INFO(e);
    CHECK(starts_with(error_of({"--exposure", e}), "--exposure:"));
  }
}

TEST_CASE("range of --dmin, a fraction of the scene diagonal") {
  CHECK(parse({}).dmin_fraction == 0.01);
  CHECK(parse({"--dmin", "0"}).dmin_fraction == 0.0);
  CHECK(parse({"--dmin", "1"}).dmin_fraction == 1.0);
  CHECK(parse({"--dmin", "2.5e-3"}).dmin_fraction == Approx(2.5e-3));
  for (const char* e : {"-0.01", "1.5", "nan", "inf", "abc", ""}) {
    INFO(e);
    CHECK(starts_with(error_of({"--dmin", e}), "--dmin:"));
  }
}

TEST_CASE("the --camera value must be ten finite numbers forming a usable camera") {
  CHECK(starts_with(error_of({"--camera", "1,2,3"}), "--camera: expected 10"));
  CHECK(starts_with(error_of({"--camera", "0,0,1,0,0,0,0,1,0,nan"}), "--camera:"));
  CHECK(starts_with(error_of({"--camera", "0,0,1,0,0,0,0,1,0,0"}), "--camera: field of view"));
  CHECK(starts_with(error_of({"--camera", "0,0,1,0,0,0,0,1,0,180"}), "--camera: field of view"));
  CHECK(starts_with(error_of({"--camera", "1,1,1,1,1,1,0,1,0,45"}), "--camera: camera eye and target coincide"));
  CHECK(starts_with(error_of({"--camera", "0,5,0,0,0,0,0,1,0,45"}), "--camera: camera up vector"));
  CHECK(starts_with(error_of({"--camera", "0,0,1,0,0,0,0,0,0,45"}), "--camera: camera up vector is zero"));
  CHECK(starts_with(error_of({"--camera", "0,0,1,0,0,0,0,1,0,45,"}), "--camera:"));
  CHECK(starts_with(error_of({"--camera", "0,0,1e39,0,0,0,0,1,0,45"}), "--camera:"));
}

TEST_CASE("the --light value must be 3 or 6 finite numbers with a non-negative intensity") {
  CHECK(starts_with(error_of({"--light", "1,2"}), "--light: expected 3"));
  CHECK(starts_with(error_of({"--light", "1,2,3,4"}), "--light: expected 3"));
  CHECK(starts_with(error_of({"--light", "1,2,3,1,-1,1"}), "--light: intensity must be >= 0"));
  CHECK(starts_with(error_of({"--light", "1,inf,3"}), "--light:"));
  CHECK(parse({"--light", "1,2,3,0,0,0"}).light->intensity == glm::vec3(0.0f));
}

TEST_CASE("the --out value must name an .exr file") {
  CHECK(starts_with(error_of({"--out", "image.png"}), "--out:"));
  CHECK(starts_with(error_of({"--out", ".exr"}), "--out:"));
  CHECK(starts_with(error_of({"--out", "dir/.exr"}), "--out:"));
  CHECK(starts_with(error_of({"--out", "exr"}), "--out:"));
  CHECK(parse({"--out", "a.exr"}).png_path() == "a.png");
}

TEST_CASE("regions are laid out as the most nearly square grid, and must fit the image") {
  int x = 0, y = 0;
  region_grid(1, x, y);
  CHECK((x == 1 && y == 1));
  region_grid(4, x, y);
  CHECK((x == 2 && y == 2));
  region_grid(12, x, y);
  CHECK((x == 4 && y == 3));
  region_grid(7, x, y);
  CHECK((x == 7 && y == 1));
  region_grid(1024, x, y);
  CHECK((x == 32 && y == 32));
  CHECK(starts_with(error_of({"--size", "4x4", "--regions", "7"}), "--regions: 7 regions (7x1) do not fit"));
  CHECK(parse({"--size", "7x1", "--regions", "7"}).regions_x == 7);
}

TEST_CASE("the gather subsets of the global and local CDFs: defaults, values, and limits naming the flag") {
  const options d = parse({});
  CHECK(d.global_subset == 256);
  CHECK(d.local_subset == 256);
  const options o = parse({"--global-subset", "32", "--local-subset", "16", "--regions", "64"});
  CHECK(o.global_subset == 32);
  CHECK(o.local_subset == 16);
  CHECK(o.regions == 64);
  CHECK(parse({"--global-subset", "65536"}).global_subset == 65536);
  for (const char* f : {"--global-subset", "--local-subset"}) {
    INFO(f);
    CHECK(parse({f, "1"}).regions == 4);
    CHECK(starts_with(error_of({f, "0"}), std::string(f) + ": value 0 is outside 1..65536"));
    CHECK(starts_with(error_of({f, "65537"}), std::string(f) + ":"));
    CHECK(starts_with(error_of({f, "-4"}), std::string(f)));
    CHECK(starts_with(error_of({f, "8x"}), std::string(f) + ":"));
  }
  // Every region's points are indices of one buffer: 2^22 in all.
  CHECK(parse({"--regions", "1024", "--local-subset", "4096", "--size", "64x64"}).local_subset == 4096);
  CHECK(starts_with(error_of({"--regions", "1024", "--local-subset", "4097", "--size", "64x64"}),
                    "--local-subset: 4097 gather points in each of 1024 regions exceed 4194304 in all"));
}

TEST_CASE("the --window flag needs the GPU backend") {
  CHECK(error_of({"--window", "--backend", "cpu"}) == "--window: needs --backend gpu");
}

TEST_CASE("the --frames and --window-script flags go with --window and are checked") {
  const options o = parse({"--window", "--frames", "5", "--window-script", "2,+,M,-,7,q"});
  CHECK(o.frames == 5);
  CHECK_FALSE(o.headless_frames());
  CHECK(o.window_script == std::vector<std::string>{"2", "+", "m", "-", "7", "q"});
  CHECK(parse({"--window"}).frames == 0);
  CHECK(parse({"--window"}).window_script.empty());
  CHECK(error_of({"--window-script", "1"}) == "--window-script: needs --window");
  CHECK(error_of({"--window", "--frames", "0"}) == "--frames: value 0 is outside 1..1000000");
  CHECK(parse({"--window", "--frames", "1000000"}).frames == 1000000);
  CHECK(parse({"--window", "--window-script", "1,0"}).window_script == std::vector<std::string>{"1", "0"});
  CHECK(parse({"--window", "--window-script", "0,P,p"}).window_script == std::vector<std::string>{"0", "p", "p"});
  CHECK(error_of({"--window", "--window-script", "1,x"}) ==
        "--window-script: unknown key action 'x' (expected 0-9, m, +, -, p, q)");
  CHECK(error_of({"--window", "--window-script", "1,,2"}) ==
        "--window-script: unknown key action '' (expected 0-9, m, +, -, p, q)");
}

TEST_CASE("frames without a window (--frames alone): the headless frames benchmark, 1..10000 frames") {
  const options o = parse({"--frames", "5"});
  CHECK(o.frames == 5);
  CHECK(o.headless_frames());
  CHECK_FALSE(parse({}).headless_frames());
  CHECK(parse({"--frames", "10000", "--backend", "cpu"}).frames == 10000);
  CHECK(error_of({"--frames", "0"}) == "--frames: value 0 is outside 1..10000");
  CHECK(error_of({"--frames", "10001"}) == "--frames: value 10001 is outside 1..10000");
  CHECK(error_of({"--frames", "-1"}).find("--frames") == 0);
  CHECK(error_of({"--frames", "1.5"}) == "--frames: expected a whole number in 1..10000, got '1.5'");
  CHECK(error_of({"--frames", ""}) == "--frames: expected a whole number in 1..10000, got ''");
}

TEST_CASE("the --help flag returns the help text, which documents every flag") {
  const parse_result r = parse_command_line({"vplrender", "--help"});
  CHECK(r.what == parse_result::action::help);
  CHECK(r.help == help_text("vplrender"));
  for (const char* flag : {"--scene", "--method", "--backend", "--size", "--vpls", "--seed", "--out", "--regions",
                           "--global-subset", "--local-subset", "--dirs", "--eps", "--voxels", "--dprsm", "--camera", "--light", "--paper", "--direct",
                           "--window", "--frames", "--window-script", "--exposure", "--progress", "--vpl-mode", "--help"}) {
    INFO(flag);
    CHECK(r.help.find(flag) != std::string::npos);
  }
  for (const char* m : {"reference", "global", "local", "gbg", "gather", "mis-as-published"}) CHECK(r.help.find(m) != std::string::npos);
  CHECK(parse_command_line({"vplrender", "--vpls", "3", "-h"}).what == parse_result::action::help);
}

TEST_CASE("the estimator switches (local combination, GBG accumulator, CDF search): defaults, every value, and bad values naming the flag") {
  const options d = parse({});
  CHECK(d.local_combination == local_combination_choice::balance);
  CHECK(d.gbg_accumulator == gbg_accumulator_choice::gathering);
  CHECK(d.cdf_search == cdf_search_choice::guide);
  CHECK(parse({"--local-combination", "average"}).local_combination == local_combination_choice::average);
  CHECK(parse({"--local-combination", "balance"}).local_combination == local_combination_choice::balance);
  CHECK(parse({"--gbg-accumulator", "paper"}).gbg_accumulator == gbg_accumulator_choice::paper);
  CHECK(parse({"--gbg-accumulator", "gathering"}).gbg_accumulator == gbg_accumulator_choice::gathering);
  CHECK(parse({"--cdf-search", "binary"}).cdf_search == cdf_search_choice::binary);
  CHECK(parse({"--cdf-search", "guide"}).cdf_search == cdf_search_choice::guide);
  CHECK(d.face_selection == face_selection_choice::joint);
  CHECK(d.sampler == sampler_choice::automatic);
  CHECK(parse({"--sampler", "auto"}).sampler == sampler_choice::automatic);
  CHECK(parse({"--face-selection", "roulette"}).face_selection == face_selection_choice::roulette);
  CHECK(parse({"--face-selection", "joint"}).face_selection == face_selection_choice::joint);
  CHECK(parse({"--sampler", "alias"}).sampler == sampler_choice::alias);
  CHECK(parse({"--sampler", "cdf"}).sampler == sampler_choice::cdf);
  CHECK(std::string(to_string(face_selection_choice::roulette)) == "roulette");
  CHECK(std::string(to_string(sampler_choice::alias)) == "alias");
  CHECK(starts_with(error_of({"--face-selection", "front"}), "--face-selection: unknown value 'front'"));
  CHECK(starts_with(error_of({"--sampler", "walker"}), "--sampler: unknown value 'walker'"));
  CHECK(starts_with(error_of({"--sampler", ""}), "--sampler: "));
  // The combinations that have no meaning are refused, naming the flag.
  CHECK(starts_with(error_of({"--sampler", "alias", "--face-selection", "roulette"}), "--sampler alias: needs"));
  CHECK(starts_with(error_of({"--cdf-search", "binary", "--sampler", "alias"}), "--cdf-search binary: needs"));
  CHECK(starts_with(error_of({"--cdf-search", "binary", "--face-selection", "roulette"}), "--cdf-search binary: needs"));
  // Independent of each other and of --paper (which sets sizes and counts only).
  const options all = parse({"--paper", "--cdf-search", "binary", "--gbg-accumulator", "paper", "--local-combination",
                             "average"});
  CHECK(all.local_combination == local_combination_choice::average);
  CHECK(all.gbg_accumulator == gbg_accumulator_choice::paper);
  CHECK(all.cdf_search == cdf_search_choice::binary);
  CHECK(parse({"--paper"}).cdf_search == cdf_search_choice::guide);
  CHECK(std::string(to_string(local_combination_choice::average)) == "average");
  CHECK(std::string(to_string(gbg_accumulator_choice::paper)) == "paper");
  CHECK(std::string(to_string(cdf_search_choice::binary)) == "binary");

  const std::string e1 = error_of({"--local-combination", "mean"});
  CHECK(starts_with(e1, "--local-combination: "));
  CHECK(e1.find("'mean'") != std::string::npos);
  CHECK(e1.find("balance|average") != std::string::npos);
  const std::string e2 = error_of({"--gbg-accumulator", "Paper"});
  CHECK(starts_with(e2, "--gbg-accumulator: "));
  CHECK(e2.find("'Paper'") != std::string::npos);
  CHECK(e2.find("gathering|paper") != std::string::npos);
  const std::string e3 = error_of({"--cdf-search", "linear"});
  CHECK(starts_with(e3, "--cdf-search: "));
  CHECK(e3.find("'linear'") != std::string::npos);
  CHECK(e3.find("guide|binary") != std::string::npos);
  CHECK(starts_with(error_of({"--cdf-search", ""}), "--cdf-search: "));
  CHECK(error_of({"--cdf-search"}).find("--cdf-search") != std::string::npos);
  CHECK(error_of({"--cdf-search", "guide", "--cdf-search", "binary"}).find("--cdf-search") != std::string::npos);

  // The help wraps lines: compare with runs of whitespace collapsed to one space.
  std::string help;
  for (char c : help_text("vplrender")) {
    const bool space = c == ' ' || c == '\n';
    if (!(space && !help.empty() && help.back() == ' ')) help += space ? ' ' : c;
  }
  for (const char* s : {"--local-combination", "balance|average", "--gbg-accumulator", "gathering|paper",
                        "--cdf-search", "guide|binary", "default balance", "default gathering", "default guide"}) {
    INFO(s);
    CHECK(help.find(s) != std::string::npos);
  }
}

TEST_CASE("the visibility flag is exact (GPU default), voxels (CPU default), paper-voxels (--paper), and the window offers the exact method") {
  // The default follows the backend: exact on the GPU (the BVH costs less than the voxel march
  // there), voxels on the CPU; the shadow-ray lit test comes with exact.
  CHECK(parse({}).visibility == visibility_choice::exact);
  CHECK(parse({}).lit_test == lit_test_choice::shadow_ray);
  CHECK(parse({"--backend", "gpu"}).visibility == visibility_choice::exact);
  CHECK(parse({"--backend", "cpu"}).visibility == visibility_choice::voxels);
  CHECK(parse({"--backend", "cpu"}).lit_test == lit_test_choice::shadow_map);
  CHECK(parse({"--backend", "gpu", "--paper"}).visibility == visibility_choice::paper_voxels);
  CHECK(parse({"--visibility", "exact"}).visibility == visibility_choice::exact);
  CHECK(parse({"--visibility", "voxels"}).visibility == visibility_choice::voxels);
  CHECK(parse({"--visibility", "paper-voxels"}).visibility == visibility_choice::paper_voxels);
  CHECK(parse({"--paper"}).visibility == visibility_choice::paper_voxels);
  CHECK(parse({"--paper", "--visibility", "exact"}).visibility == visibility_choice::exact);
  CHECK(parse({"--paper", "--visibility", "voxels"}).visibility == visibility_choice::voxels);
  CHECK(std::string(to_string(visibility_choice::exact)) == "exact");
  CHECK(std::string(to_string(visibility_choice::paper_voxels)) == "paper-voxels");
  CHECK(std::string(to_string(visibility_choice::voxels)) == "voxels");
  CHECK(starts_with(error_of({"--visibility", "bvh"}),
                    "--visibility: unknown value 'bvh' (expected voxels|paper-voxels|exact)"));
  CHECK(parse({"--window", "--method", "exact"}).meth == method::exact);
  CHECK(parse({"--window", "--window-script", "8,m"}).window_script == std::vector<std::string>{"8", "m"});
  CHECK(parse({"--window", "--window-script", "9"}).window_script == std::vector<std::string>{"9"});
  CHECK(error_of({"--vpls"}) == "--vpls: needs a value");
  CHECK(error_of({"--size", "8x8", "--scene"}) == "--scene: needs a value");
  CHECK(help_text().find("--visibility") != std::string::npos);
  CHECK(help_text().find("the GLSL pack's BVH on the GPU backend") != std::string::npos);
}

TEST_CASE("the VPL mode flag is patch (default) or point, --paper selects point, and an explicit flag wins") {
  CHECK(parse({}).vpl_mode == vpl_mode_choice::patch);
  CHECK(parse({"--vpl-mode", "point"}).vpl_mode == vpl_mode_choice::point);
  CHECK(parse({"--vpl-mode", "patch"}).vpl_mode == vpl_mode_choice::patch);
  CHECK(parse({"--vpl-mode=point", "--method", "reference"}).vpl_mode == vpl_mode_choice::point);
  CHECK(parse({"--paper"}).vpl_mode == vpl_mode_choice::point);
  CHECK(parse({"--paper", "--vpl-mode", "patch"}).vpl_mode == vpl_mode_choice::patch);
  CHECK(parse({"--vpl-mode", "patch", "--paper"}).vpl_mode == vpl_mode_choice::patch);
  CHECK(std::string(to_string(vpl_mode_choice::point)) == "point");
  CHECK(std::string(to_string(vpl_mode_choice::patch)) == "patch");
  CHECK(library_vpl_mode(vpl_mode_choice::patch) == vplkit::vpl_mode::patch);
  CHECK(library_vpl_mode(vpl_mode_choice::point) == vplkit::vpl_mode::point);
  // It applies to every method with VPLs; gather and exact have none.
  for (method m : {method::reference, method::global, method::local, method::gbg, method::mis, method::mis_as_published})
    CHECK(uses_vpls(m));
  CHECK_FALSE(uses_vpls(method::gather));
  CHECK_FALSE(uses_vpls(method::exact));
  CHECK(starts_with(error_of({"--vpl-mode", "area"}), "--vpl-mode: unknown value 'area' (expected point|patch)"));
  CHECK(starts_with(error_of({"--vpl-mode"}), "--vpl-mode"));
  CHECK(help_text().find("--vpl-mode") != std::string::npos);
}

TEST_CASE("the lit test flag follows --visibility (shadow ray with exact) and a shadow ray needs exact visibility") {
  CHECK(parse({"--visibility", "voxels"}).lit_test == lit_test_choice::shadow_map);
  CHECK(parse({"--visibility", "exact"}).lit_test == lit_test_choice::shadow_ray);
  CHECK(parse({"--visibility", "exact", "--lit-test", "shadow-map"}).lit_test == lit_test_choice::shadow_map);
  CHECK(parse({"--lit-test", "shadow-ray", "--visibility", "exact"}).lit_test == lit_test_choice::shadow_ray);
  CHECK(parse({"--paper"}).lit_test == lit_test_choice::shadow_map);
  CHECK(std::string(to_string(lit_test_choice::shadow_map)) == "shadow-map");
  CHECK(std::string(to_string(lit_test_choice::shadow_ray)) == "shadow-ray");
  CHECK(starts_with(error_of({"--backend", "cpu", "--lit-test", "shadow-ray"}),
                    "--lit-test shadow-ray: needs --visibility exact"));
  CHECK(starts_with(error_of({"--visibility", "voxels", "--lit-test", "shadow-ray"}),
                    "--lit-test shadow-ray: needs --visibility exact"));
  CHECK(starts_with(error_of({"--lit-test", "ray"}), "--lit-test: unknown value 'ray' (expected shadow-map|shadow-ray)"));
  CHECK(help_text().find("--lit-test") != std::string::npos);
}

TEST_CASE("voxel contract option: plane-rule by default, exact on the CPU backend's voxels, and the lit test it allows") {
  const options plain = parse({"--backend", "cpu"});
  CHECK(plain.voxel_contract == voxel_contract_choice::plane_rule);
  CHECK(plain.lit_test == lit_test_choice::shadow_map);
  const options e = parse({"--backend", "cpu", "--voxel-contract", "exact"});
  CHECK(e.voxel_contract == voxel_contract_choice::exact);
  CHECK(e.lit_test == lit_test_choice::shadow_ray);  // the default, as with --visibility exact
  CHECK(parse({"--backend", "cpu", "--voxel-contract", "exact", "--lit-test", "shadow-map"}).lit_test ==
        lit_test_choice::shadow_map);
  CHECK(parse({"--backend", "cpu", "--voxel-contract", "plane-rule"}).voxel_contract == voxel_contract_choice::plane_rule);
  CHECK(std::string(to_string(voxel_contract_choice::exact)) == "exact");
  CHECK(std::string(to_string(voxel_contract_choice::plane_rule)) == "plane-rule");
  CHECK(starts_with(error_of({"--backend", "cpu", "--lit-test", "shadow-ray"}), "--lit-test shadow-ray: needs"));
  CHECK(error_of({"--backend", "cpu", "--lit-test", "shadow-ray"}).find("--voxel-contract exact") != std::string::npos);
  CHECK(starts_with(error_of({"--visibility", "voxels", "--voxel-contract", "exact"}), "--voxel-contract exact: the GPU"));
  CHECK(starts_with(error_of({"--backend", "cpu", "--visibility", "exact", "--voxel-contract", "exact"}),
                    "--voxel-contract: needs --visibility voxels"));
  CHECK(starts_with(error_of({"--backend", "cpu", "--voxel-contract", "offset"}), "--voxel-contract"));
}
