// SPDX-License-Identifier: MIT
// --sampler share-tree on the command line: accepted with the methods that draw it (global, gbg, local) on
// both backends, refused with a usage_error naming the flag wherever the tree would not be drawn as
// documented (the other methods, the face roulette, the binary CDF search).
#include <catch2/catch.hpp>

#include "renderer_cli_parse.hpp"
#include "cli/options.hpp"
#include "io/errors.hpp"
#include "render/settings.hpp"

#include <string>
#include <vector>

using namespace vplrender;

using namespace vplrender_test;

TEST_CASE("The share-tree sampler is accepted with global, gbg and local on both backends") {
  for (const char* m : {"global", "gbg", "local"})
    for (const char* b : {"cpu", "gpu"}) {
      INFO(m << " " << b);
      const options o = parse({"--method", m, "--backend", b, "--sampler", "share-tree"});
      CHECK(o.sampler == sampler_choice::share_tree);
    }
  CHECK(std::string(to_string(sampler_choice::share_tree)) == "share-tree");
  CHECK(parse({}).sampler == sampler_choice::cdf);  // opt-in
}

TEST_CASE("The share-tree sampler is refused where the tree is not drawn") {
  for (const char* m : {"reference", "gather", "mis", "mis-as-published", "exact", "ris", "ris-mis"}) {
    INFO(m);
    const std::string e = error_of({"--method", m, "--sampler", "share-tree"});
    CHECK(starts_with(e, "--sampler share-tree: not supported with --method " + std::string(m)));
  }
  CHECK(starts_with(error_of({"--method", "global", "--sampler", "share-tree", "--face-selection", "roulette"}),
                    "--sampler share-tree: needs --face-selection joint"));
  CHECK(starts_with(error_of({"--method", "global", "--sampler", "share-tree", "--cdf-search", "binary"}), "--cdf-search binary: needs"));
  CHECK(starts_with(error_of({"--method", "global", "--sampler", "sharetree"}), "--sampler"));
}
