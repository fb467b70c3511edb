// SPDX-License-Identifier: MIT
// --sampler share-tree on the command line: accepted with the VPL-sampling methods (global, gbg) on
// both backends, refused with a usage_error naming the flag wherever the tree would not be drawn as
// documented (the other methods, the face roulette, the binary CDF search).
#include <catch2/catch.hpp>

#include "cli/options.hpp"
#include "io/errors.hpp"
#include "render/settings.hpp"

#include <string>
#include <vector>

using namespace vplrender;

namespace {

options parse(std::vector<std::string> args) {
  args.insert(args.begin(), "vplrender");
  const parse_result r = parse_command_line(args);
  REQUIRE(r.what == parse_result::action::run);
  return r.opts;
}

// The message of the usage_error that parsing throws, or "" if it does not throw.
std::string error_of(std::vector<std::string> args) {
  args.insert(args.begin(), "vplrender");
  try {
    parse_command_line(args);
  } catch (const usage_error& e) {
    return e.what();
  }
  return "";
}

bool starts_with(const std::string& s, const std::string& p) { return s.rfind(p, 0) == 0; }

}  // namespace

TEST_CASE("The share-tree sampler is accepted with global and gbg on both backends") {
  for (const char* m : {"global", "gbg"})
    for (const char* b : {"cpu", "gpu"}) {
      INFO(m << " " << b);
      const options o = parse({"--method", m, "--backend", b, "--sampler", "share-tree"});
      CHECK(o.sampler == sampler_choice::share_tree);
    }
  CHECK(std::string(to_string(sampler_choice::share_tree)) == "share-tree");
  CHECK(parse({}).sampler == sampler_choice::cdf);  // opt-in
}

TEST_CASE("The share-tree sampler is refused where the tree is not drawn") {
  for (const char* m : {"reference", "local", "gather", "mis", "mis-as-published", "exact", "ris"}) {
    INFO(m);
    const std::string e = error_of({"--method", m, "--sampler", "share-tree"});
    CHECK(starts_with(e, "--sampler share-tree: not supported with --method " + std::string(m)));
  }
  CHECK(starts_with(error_of({"--method", "global", "--sampler", "share-tree", "--face-selection", "roulette"}),
                    "--sampler share-tree: needs --face-selection joint"));
  CHECK(starts_with(error_of({"--method", "global", "--sampler", "share-tree", "--cdf-search", "binary"}), "--cdf-search binary: needs"));
  CHECK(starts_with(error_of({"--method", "global", "--sampler", "sharetree"}), "--sampler"));
}
