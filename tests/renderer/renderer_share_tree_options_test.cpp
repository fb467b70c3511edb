// SPDX-License-Identifier: MIT
// --sampler share-tree on the command line: accepted with the methods that draw it (global, gbg, local, mis) on
// both backends, refused with a usage_error naming the flag wherever the tree would not be drawn as
// documented (the other methods, the face roulette, the binary CDF search).
#include <catch2/catch.hpp>

#include "renderer_cli_parse.hpp"
#include "cli/options.hpp"
#include "io/errors.hpp"
#include "render/method_traits.hpp"
#include "render/settings.hpp"

#include <string>
#include <vector>

using namespace vplrender;

using namespace vplrender_test;

TEST_CASE("The share-tree sampler is accepted with global, gbg, local and mis on both backends") {
  for (const char* m : {"global", "gbg", "local", "mis", "mis-as-published"})
    for (const char* b : {"cpu", "gpu"}) {
      INFO(m << " " << b);
      const options o = parse({"--method", m, "--backend", b, "--sampler", "share-tree"});
      CHECK(o.sampler == sampler_choice::share_tree);
    }
  CHECK(std::string(to_string(sampler_choice::share_tree)) == "share-tree");
}

TEST_CASE("The default sampler is the share tree where the method draws it, the CDF elsewhere") {
  CHECK(parse({}).sampler == sampler_choice::automatic);
  CHECK(std::string(to_string(sampler_choice::automatic)) == "auto");
  for (const char* m : {"global", "gbg", "local", "mis", "mis-as-published"}) {
    INFO(m);
    CHECK(resolved_sampler(parse({"--method", m})) == sampler_choice::share_tree);
    // The face roulette and the binary search sample CDFs: the default gives way to them.
    CHECK(resolved_sampler(parse({"--method", m, "--face-selection", "roulette"})) == sampler_choice::cdf);
    CHECK(resolved_sampler(parse({"--method", m, "--cdf-search", "binary"})) == sampler_choice::cdf);
    CHECK(resolved_sampler(parse({"--method", m, "--sampler", "cdf"})) == sampler_choice::cdf);
  }
  for (const char* m : {"reference", "gather", "exact", "ris", "ris-mis"}) {
    INFO(m);
    CHECK(resolved_sampler(parse({"--method", m})) == sampler_choice::cdf);
  }
}

TEST_CASE("The share-tree sampler is refused where the tree is not drawn") {
  for (const char* m : {"reference", "gather", "exact", "ris", "ris-mis"}) {
    INFO(m);
    const std::string e = error_of({"--method", m, "--sampler", "share-tree"});
    CHECK(starts_with(e, "--sampler share-tree: not supported with --method " + std::string(m)));
  }
  CHECK(starts_with(error_of({"--method", "global", "--sampler", "share-tree", "--face-selection", "roulette"}),
                    "--sampler share-tree: needs --face-selection joint"));
  CHECK(starts_with(error_of({"--method", "global", "--sampler", "share-tree", "--cdf-search", "binary"}), "--cdf-search binary: needs"));
  CHECK(starts_with(error_of({"--method", "global", "--sampler", "sharetree"}), "--sampler"));
}
