// SPDX-License-Identifier: MIT
// render/method_traits.cpp: every --method described once. The table's rows must follow the enum,
// name every method once, and agree with what the rest of the renderer derives from them: the
// command line accepts exactly the table's names (and its help lists them), the window cycles
// through the GPU backend's rows in table order, and each trait matches the estimator it names.
#include "cli/options.hpp"
#include "app/window_update.hpp"
#include "render/method_traits.hpp"
#include "render/settings.hpp"

#include <catch2/catch.hpp>

#include <set>
#include <utility>
#include <string>
#include <vector>

using namespace vplrender;

TEST_CASE("method traits: one row per method, in enum order, names unique and round-tripping") {
  const std::vector<method_traits>& all = all_method_traits();
  REQUIRE(all.size() == 10);
  std::set<std::string> names;
  for (std::size_t i = 0; i < all.size(); ++i) {
    const method_traits& t = all[i];
    INFO(t.name);
    CHECK(static_cast<std::size_t>(t.id) == i);
    CHECK(&traits(t.id) == &t);
    CHECK(std::string(to_string(t.id)) == t.name);
    CHECK(method_from_name(t.name) == t.id);
    CHECK(names.insert(t.name).second);
    CHECK(std::string(t.help).size() > 0);
  }
  CHECK_FALSE(method_from_name("Global").has_value());
  CHECK_FALSE(method_from_name("").has_value());
  CHECK(method_names() == "reference|global|local|gbg|gather|mis|mis-as-published|exact|ris|ris-mis");
}

TEST_CASE("method traits: each row's traits agree with its estimator and builder") {
  for (const method_traits& t : all_method_traits()) {
    INFO(t.name);
    // A distribution over the VPLs comes from a builder; the estimators that draw from one.
    const bool draws = t.estimator == estimator_kind::vpl_sampling || t.estimator == estimator_kind::local ||
                       t.estimator == estimator_kind::mis || t.estimator == estimator_kind::ris;
    CHECK(has_distribution(t.id) == draws);
    CHECK((t.builder != builder_kind::none) == draws);
    CHECK((t.estimator == estimator_kind::local) == (t.builder == builder_kind::local));
    // RIS takes its candidates from the distribution --candidate-source names; the others' builder
    // is their own.
    CHECK((t.estimator == estimator_kind::ris) == (t.builder == builder_kind::candidate_source));
    CHECK(t.builder != builder_kind::flux);
    // The GPU backend has a kernel for every estimator (RIS: estimate_ris.comp).
    CHECK(t.gpu);
    // VPLs: every estimator but gathering and the ground truth.
    CHECK(uses_vpls(t.id) == (t.estimator != estimator_kind::gather && t.estimator != estimator_kind::exact));
    CHECK(t.uses_vpls == uses_vpls(t.id));
    // Directions: the gathering estimators (ris's variant 1, ris-mis, gathers), and the GBG builder's rays.
    const bool ris_gathers = t.estimator == estimator_kind::ris && t.variant == 1;
    const bool rays = t.estimator == estimator_kind::gather || t.estimator == estimator_kind::mis ||
                      t.estimator == estimator_kind::exact || ris_gathers;
    CHECK(t.uses_dirs == (rays || t.builder == builder_kind::gbg));
    CHECK(t.gathers == (t.estimator == estimator_kind::gather || t.estimator == estimator_kind::mis || ris_gathers));
    CHECK(t.exact_rays == (t.estimator == estimator_kind::exact));
    // speed_vs_error's sample count sets the samples the estimator takes (gbg's --dirs are its
    // builder's, not swept).
    const sweep_count sweep = !t.uses_vpls                         ? sweep_count::dirs
                              : t.estimator == estimator_kind::mis || ris_gathers ? sweep_count::vpls_and_dirs
                                                                                  : sweep_count::vpls;
    CHECK(t.sweep == sweep);
    CHECK((!t.swept_by_default || t.swept));
    CHECK((t.variant == 0 || t.estimator == estimator_kind::mis || t.estimator == estimator_kind::ris));
    // The clamp: the VPL methods that divide by max(d^2, dmin^2); MIS-weighted ones have none.
    CHECK(t.clamped == (t.estimator == estimator_kind::reference || t.estimator == estimator_kind::vpl_sampling ||
                        t.estimator == estimator_kind::local || (t.estimator == estimator_kind::ris && !ris_gathers)));
  }
  CHECK(traits(method::mis).variant == 0);               // vplkit::mis_mode::solid_angle
  CHECK(traits(method::mis_as_published).variant == 1);  // vplkit::mis_mode::as_published
  CHECK_FALSE(traits(method::reference).swept);          // speed_vs_error's reference, not a swept method
  CHECK(traits(method::ris).variant == 0);               // vplkit::estimate_ris (clamped)
  CHECK(traits(method::ris_mis).variant == 1);           // vplkit::estimate_ris_mis (unclamped)
  CHECK_FALSE(method_has_clamp(method::ris_mis));
  CHECK(traits(method::ris_mis).swept);
  CHECK_FALSE(traits(method::ris_mis).swept_by_default);
}

TEST_CASE("method traits: distribution_builder resolves ris's --candidate-source, other methods keep theirs") {
  render_settings s;
  for (const method_traits& t : all_method_traits()) {
    s.meth = t.id;
    if (t.builder != builder_kind::candidate_source) CHECK(distribution_builder(s) == t.builder);
  }
  const std::pair<ris_source_choice, builder_kind> cases[] = {{ris_source_choice::global, builder_kind::global},
                                                              {ris_source_choice::local, builder_kind::local},
                                                              {ris_source_choice::gbg, builder_kind::gbg},
                                                              {ris_source_choice::flux, builder_kind::flux}};
  for (const method m : {method::ris, method::ris_mis})
    for (const auto& [source, builder] : cases) {
      s.meth = m;
      s.ris_source = source;
      CHECK(distribution_builder(s) == builder);
    }
}

TEST_CASE("method traits: the command line takes exactly the table's names") {
  for (const method_traits& t : all_method_traits()) {
    INFO(t.name);
    const parse_result r = parse_command_line({"vplrender", "--method", t.name, "--backend", "cpu"});
    CHECK(r.opts.meth == t.id);
    // The GPU backend (the default) takes exactly the rows it has kernels for.
    if (t.gpu)
      CHECK(parse_command_line({"vplrender", "--method", t.name}).opts.meth == t.id);
    else
      CHECK_THROWS_WITH(parse_command_line({"vplrender", "--method", t.name}),
                        Catch::Contains("--method " + std::string(t.name) + ": runs on --backend cpu only"));
  }
  CHECK_THROWS_WITH(parse_command_line({"vplrender", "--method", "RIS"}),
                    Catch::Contains("--method: unknown value 'RIS' (expected " + method_names() + ")"));
  // The help text, its wrapping undone.
  std::string help;
  for (char c : parse_command_line({"vplrender", "--help"}).help) {
    const bool space = c == ' ' || c == '\n';
    if (!(space && !help.empty() && help.back() == ' ')) help += space ? ' ' : c;
  }
  for (const method_traits& t : all_method_traits())
    CHECK_THAT(help, Catch::Contains(std::string(t.name) + " = " + t.help));
}

TEST_CASE("method traits: the window's keys 1-8 follow the table's GPU rows, exact only with exact rays") {
  for (const bool exact : {false, true}) {
    window_view v;
    v.exact = exact;
    std::vector<method> seen;
    for (int k = 0; k < 8; ++k) {
      v.meth = method::reference;
      bool close = false;
      const std::string key(1, static_cast<char>('1' + k));
      apply_window_action(v, key, &close);
      if (v.meth != method::reference || k == 0) seen.push_back(v.meth);
    }
    std::vector<method> expected;
    // ris has its own key 9 (app/window_update.cpp says why), checked below.
    for (const method_traits& t : all_method_traits())
      if (t.gpu && t.estimator != estimator_kind::ris && (!t.exact_rays || exact)) expected.push_back(t.id);
    CHECK(seen == expected);
  }
}

TEST_CASE("method traits: keys 9 and 0 are ris and ris-mis, and m cycles through keys 1-8, then 9, then 0") {
  for (const bool exact : {false, true}) {
    window_view v;
    v.exact = exact;
    v.meth = method::global;
    bool close = false;
    CHECK(apply_window_action(v, "9", &close));
    CHECK(v.meth == method::ris);
    CHECK_FALSE(apply_window_action(v, "9", &close));  // already ris: nothing to re-render
    CHECK(apply_window_action(v, "0", &close));
    CHECK(v.meth == method::ris_mis);
    CHECK_FALSE(apply_window_action(v, "0", &close));
    // From ris-mis, m wraps to key 1's method; pressing m as often as there are methods comes back.
    std::vector<method> cycle{v.meth};
    for (int k = 0; k < 20; ++k) {
      apply_window_action(v, "m", &close);
      if (v.meth == method::ris_mis) break;
      cycle.push_back(v.meth);
    }
    CHECK(v.meth == method::ris_mis);
    std::vector<method> expected{method::ris_mis};
    for (const method_traits& t : all_method_traits())
      if (t.gpu && t.estimator != estimator_kind::ris && (!t.exact_rays || exact)) expected.push_back(t.id);
    expected.push_back(method::ris);
    CHECK(cycle == expected);
    CHECK_FALSE(close);
  }
}
