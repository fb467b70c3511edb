// SPDX-License-Identifier: MIT
// The command line of --method ris and ris-mis: the three flags (--candidates, --candidate-source, --spatial),
// their defaults, limits and errors, and the GPU backend's acceptance (clamp compensation refused
// there as for every method).
#include <catch2/catch.hpp>

#include "renderer_cli_parse.hpp"
#include "cli/options.hpp"
#include "io/errors.hpp"
#include "render/settings.hpp"

#include <string>
#include <vector>

using namespace vplrender;

using namespace vplrender_test;

TEST_CASE("ris options: the method, its defaults and its three flags") {
  const options d = parse({"--method", "ris", "--backend", "cpu"});
  CHECK(d.meth == method::ris);
  CHECK(std::string(to_string(method::ris)) == "ris");
  CHECK(d.candidates == 32);
  CHECK(d.candidate_source == ris_source_choice::flux);
  CHECK(d.spatial == 0);
  CHECK(has_distribution(method::ris));
  CHECK(uses_vpls(method::ris));
  const std::pair<const char*, ris_source_choice> sources[] = {{"global", ris_source_choice::global},
                                                               {"local", ris_source_choice::local},
                                                               {"gbg", ris_source_choice::gbg},
                                                               {"flux", ris_source_choice::flux}};
  for (const auto& [name, value] : sources) {
    const options o = parse({"--method", "ris", "--backend", "cpu", "--candidate-source", name, "--candidates", "7",
                             "--spatial", "5"});
    CHECK(o.candidate_source == value);
    CHECK(std::string(to_string(value)) == name);
    CHECK(o.candidates == 7);
    CHECK(o.spatial == 5);
  }
  // The flags are accepted with other methods too (speed_vs_error passes them for a sweep).
  CHECK(parse({"--candidates", "4"}).candidates == 4);
}

TEST_CASE("ris options: limits and bad values name the flag") {
  CHECK(starts_with(error_of({"--candidates", "0"}), "--candidates: value 0 is outside 1..65536"));
  CHECK(starts_with(error_of({"--candidates", "65537"}), "--candidates: value 65537 is outside 1..65536"));
  CHECK(starts_with(error_of({"--candidates", "x"}), "--candidates: expected a whole number"));
  CHECK(starts_with(error_of({"--spatial", "17"}), "--spatial: value 17 is outside 0..16"));
  CHECK(starts_with(error_of({"--spatial", "-1"}), "--spatial: expected a whole number"));
  CHECK(parse({"--spatial", "0"}).spatial == 0);
  CHECK(parse({"--spatial", "16"}).spatial == 16);
  CHECK(starts_with(error_of({"--candidate-source", "mis"}),
                    "--candidate-source: unknown value 'mis' (expected global|local|gbg|flux|tiles)"));
}

TEST_CASE("ris options: tile candidates for ris-mis on the CPU backend, their flags and their limits") {
  const options d = parse({"--method", "ris-mis", "--backend", "cpu", "--candidate-source", "tiles"});
  CHECK(d.candidate_source == ris_source_choice::tiles);
  CHECK(std::string(to_string(ris_source_choice::tiles)) == "tiles");
  CHECK(d.tiles == 64);
  CHECK(d.tile_points == 8);
  CHECK(d.tile_block == 8);
  CHECK(d.candidate_pool == 2048);  // per tile, unless given
  const options o = parse({"--method", "ris-mis", "--backend", "cpu", "--candidate-source", "tiles", "--tiles", "12",
                           "--tile-points", "3", "--tile-block", "4", "--candidate-pool", "500"});
  CHECK(o.tiles == 12);
  CHECK(o.tile_points == 3);
  CHECK(o.tile_block == 4);
  CHECK(o.candidate_pool == 500);
  // Other sources keep the pool's default.
  CHECK(parse({"--method", "ris-mis", "--backend", "cpu"}).candidate_pool == 16384);
  CHECK(starts_with(error_of({"--tiles", "0"}), "--tiles: value 0 is outside 1..1024"));
  CHECK(starts_with(error_of({"--tile-points", "0"}), "--tile-points: value 0 is outside 1..65536"));
  CHECK(starts_with(error_of({"--tile-block", "65"}), "--tile-block: value 65 is outside 1..64"));
  CHECK(starts_with(error_of({"--method", "ris-mis", "--backend", "cpu", "--candidate-source", "tiles", "--size",
                              "16x2", "--tiles", "64"}),
                    "--tiles: 64 tiles (8x8) do not fit a 16x2 image"));
  CHECK(starts_with(error_of({"--method", "ris-mis", "--backend", "cpu", "--candidate-source", "tiles", "--tiles",
                              "1024", "--tile-points", "4097"}),
                    "--tile-points: 4097 gather points in each of 1024 tiles exceed 4194304 in all"));
  // ris has no tiles: refused, naming the flag, on either backend; ris-mis takes them on both.
  CHECK(starts_with(error_of({"--method", "ris", "--backend", "cpu", "--candidate-source", "tiles"}),
                    "--candidate-source: tiles is for --method ris-mis"));
  CHECK(starts_with(error_of({"--method", "ris", "--candidate-source", "tiles"}),
                    "--candidate-source: tiles is for --method ris-mis"));
  CHECK(parse({"--method", "ris-mis", "--candidate-source", "tiles"}).back == backend::gpu);
  CHECK(parse({"--method", "ris-mis", "--candidate-source", "tiles"}).candidate_pool == 2048);
  // Methods without candidates ignore the source (speed_vs_error passes it to every method of a sweep).
  CHECK(parse({"--method", "gather", "--candidate-source", "tiles"}).meth == method::gather);
}

TEST_CASE("ris options: the GPU backend runs it, with the clamp compensation as the CPU's") {
  const options o = parse({"--method", "ris", "--spatial", "2", "--clamp-compensation", "on"});  // the default backend is gpu
  CHECK(o.back == backend::gpu);
  CHECK(o.meth == method::ris);
  CHECK(o.spatial == 2);
  CHECK(o.clamp_compensation == clamp_compensation_choice::on);
}

TEST_CASE("ris options: --help documents the method and its flags") {
  const std::string h = help_text();
  for (const char* s : {"--candidates", "--candidate-source", "--spatial", "global|local|gbg|flux", "|ris"}) {
    INFO(s);
    CHECK(h.find(s) != std::string::npos);
  }
}

TEST_CASE("ris options: ris-mis takes --dirs, --vpls, the candidate flags and --spatial") {
  const options o = parse({"--method", "ris-mis", "--backend", "cpu", "--dirs", "6", "--vpls", "5", "--candidates",
                           "8", "--candidate-source", "local"});
  CHECK(o.meth == method::ris_mis);
  CHECK(std::string(to_string(method::ris_mis)) == "ris-mis");
  CHECK(o.dirs == 6);
  CHECK(o.vpls == 5);
  CHECK(o.candidates == 8);
  CHECK(o.candidate_source == ris_source_choice::local);
  CHECK(o.spatial == 0);
  CHECK(has_distribution(method::ris_mis));
  CHECK(uses_vpls(method::ris_mis));
  CHECK(parse({"--method", "ris-mis", "--backend", "cpu", "--spatial", "0"}).spatial == 0);
  // Spatial reuse over its MIS-weighted target, on both backends.
  CHECK(parse({"--method", "ris-mis", "--backend", "cpu", "--spatial", "4"}).spatial == 4);
  CHECK(parse({"--method", "ris-mis", "--backend", "gpu", "--spatial", "4"}).spatial == 4);
  CHECK(starts_with(error_of({"--method", "ris-mis", "--spatial", "17"}), "--spatial"));
  // No clamp: the compensation never applies to it, whatever --clamp-compensation says.
  render_settings s;
  s.meth = method::ris_mis;
  s.dmin = 0.05f;
  s.clamp_compensation = clamp_compensation_choice::on;
  CHECK_FALSE(uses_clamp_compensation(s));
  s.meth = method::ris;
  CHECK(uses_clamp_compensation(s));
}

TEST_CASE("ris options: --candidate-pool takes 0..4194304 entries, 16384 by default") {
  CHECK(parse({"--method", "ris-mis", "--backend", "cpu"}).candidate_pool == 16384);
  CHECK(parse({"--method", "ris-mis", "--backend", "cpu", "--candidate-pool", "0"}).candidate_pool == 0);
  CHECK(parse({"--method", "ris-mis", "--backend", "cpu", "--candidate-pool", "16384"}).candidate_pool == 16384);
  CHECK(parse({"--method", "ris-mis", "--backend", "cpu", "--candidate-pool", "4194304"}).candidate_pool == 4194304);
  CHECK(starts_with(error_of({"--method", "ris-mis", "--candidate-pool", "4194305"}),
                    "--candidate-pool: value 4194305 is outside 0..4194304"));
  CHECK(starts_with(error_of({"--method", "ris-mis", "--candidate-pool", "-1"}), "--candidate-pool: expected a whole number"));
  CHECK(help_text().find("--candidate-pool") != std::string::npos);
}

TEST_CASE("ris options: --help documents ris-mis") {
  std::string h;  // the help text, its wrapping undone
  for (const char c : help_text()) {
    const bool space = c == ' ' || c == '\n';
    if (!(space && !h.empty() && h.back() == ' ')) h += space ? ' ' : c;
  }
  for (const char* s : {"|ris-mis", "ris-mis = RIS as the VPL strategy of mis", "--method ris and ris-mis: neighbours",
                        "ris-mis: over its MIS-weighted target", "global|local|gbg|flux|tiles", "--tiles N",
                        "--tile-points N", "--tile-block B", "--candidate-source tiles: image tiles"}) {
    INFO(s);
    CHECK(h.find(s) != std::string::npos);
  }
}
