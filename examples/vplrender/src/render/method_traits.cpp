// SPDX-License-Identifier: MIT
#include "render/method_traits.hpp"

#include <stdexcept>

namespace vplrender {

namespace {

using ek = estimator_kind;
using bk = builder_kind;
using sc = sweep_count;

// One row per method, in enum order (checked below).
// clang-format off
const std::vector<method_traits> k_methods = {
  //  id                         name                help
  //  estimator         variant builder   vpls   dirs   gathers exact  swept  default sweep  gpu  clamped
  {method::reference, "reference", "exhaustive VPL sum with visibility",
   ek::reference,    0, bk::none,   true,  false, false, false, false, false, sc::vpls, true, true},
  {method::global, "global", "BRSM global CDF",
   ek::vpl_sampling, 0, bk::global, true,  false, false, false, true,  true,  sc::vpls, true, true},
  {method::local, "local", "per-region CDFs (balance heuristic)",
   ek::local,        0, bk::local,  true,  false, false, false, true,  true,  sc::vpls, true, true},
  {method::gbg, "gbg", "gathering-based global CDF",
   ek::vpl_sampling, 0, bk::gbg,    true,  true,  false, false, true,  true,  sc::vpls, true, true},
  {method::gather, "gather", "cosine gathering only",
   ek::gather,       0, bk::none,   false, true,  true,  false, true,  true,  sc::dirs, true, false},
  {method::mis, "mis", "gathering + GBG CDF with solid-angle balance heuristic",
   ek::mis,          0, bk::gbg,    true,  true,  true,  false, true,  true,  sc::vpls_and_dirs, true, false},
  {method::mis_as_published, "mis-as-published", "the paper's mixed-measure MIS weights (biased, for comparison)",
   ek::mis,          1, bk::gbg,    true,  true,  true,  false, true,  false, sc::vpls_and_dirs, true, false},
  {method::exact, "exact",
   "ground truth: --dirs cosine-distributed rays per gather point traced against the triangles, the light's direct "
   "light at each hit with an exact shadow ray, no VPLs (Embree on the CPU backend, the GLSL pack's BVH on the GPU "
   "backend; the two agree per pixel up to ties at creases)",
   ek::exact,        0, bk::none,   false, true,  false, true,  true,  false, sc::dirs, true, false},
  {method::ris, "ris",
   "resampled importance sampling: per sample --candidates VPLs from --candidate-source, one kept by their "
   "unshadowed contribution, one visibility query, optionally --spatial reuse",
   ek::ris,          0, bk::candidate_source, true, false, false, false, true, false, sc::vpls, true, true},
  {method::ris_mis, "ris-mis",
   "RIS as the VPL strategy of mis: --vpls RIS samples of --candidates VPLs from --candidate-source, balanced "
   "against --dirs gathering directions; unclamped (no compensation)",
   ek::ris,          1, bk::candidate_source, true, true,  true,  false, true, false, sc::vpls_and_dirs, true, false},
};
// clang-format on

bool rows_in_enum_order() {
  for (std::size_t i = 0; i < k_methods.size(); ++i)
    if (static_cast<std::size_t>(k_methods[i].id) != i) return false;
  return true;
}

}  // namespace

const std::vector<method_traits>& all_method_traits() {
  static const bool ok = rows_in_enum_order();
  if (!ok) throw std::logic_error("method_traits.cpp: the rows must follow render/settings.hpp's method enum");
  return k_methods;
}

const method_traits& traits(method m) {
  const auto& all = all_method_traits();
  const auto i = static_cast<std::size_t>(m);
  if (i >= all.size()) throw std::logic_error("traits: a method without a row in method_traits.cpp");
  return all[i];
}

builder_kind distribution_builder(const render_settings& s) {
  const builder_kind b = traits(s.meth).builder;
  if (b != builder_kind::candidate_source) return b;
  switch (s.ris_source) {
    case ris_source_choice::local: return builder_kind::local;
    case ris_source_choice::gbg: return builder_kind::gbg;
    case ris_source_choice::flux: return builder_kind::flux;
    case ris_source_choice::tiles: return builder_kind::flux;  // the tiles are built on its weights
    case ris_source_choice::global: break;
  }
  return builder_kind::global;
}

bool draws_share_tree(estimator_kind k) {
  return k == estimator_kind::vpl_sampling || k == estimator_kind::local || k == estimator_kind::mis;
}

sampler_choice resolved_sampler(const render_choices& c) {
  if (c.sampler != sampler_choice::automatic) return c.sampler;
  return draws_share_tree(traits(c.meth).estimator) && c.face_selection == face_selection_choice::joint &&
                 c.cdf_search == cdf_search_choice::guide
             ? sampler_choice::share_tree
             : sampler_choice::cdf;
}

std::optional<method> method_from_name(const std::string& name) {
  for (const method_traits& t : all_method_traits())
    if (name == t.name) return t.id;
  return std::nullopt;
}

std::string method_names(const char* separator) {
  std::string s;
  for (const method_traits& t : all_method_traits()) s += (s.empty() ? "" : separator) + std::string(t.name);
  return s;
}

}  // namespace vplrender
