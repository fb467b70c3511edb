// SPDX-License-Identifier: MIT
#pragma once
// --face-selection roulette and --sampler alias: the defensive mixtures of both backends, sampled
// through other components than their discrete CDFs. A mixture keeps its split (docs/math.md,
// "Defensive mixing": vplkit::mixture_split, the same for every component type); each part is
// sampled by
//   roulette: vplkit::face_roulette over the two paraboloids' halves of its weights, seen through
//             vplkit::flat_face_roulette (the paper's Alg. 1);
//   alias:    vplkit::alias_table over its weights.
// Both have the joint CDF's pmf up to its rounding: w_t / sum w. The components are built on the
// host from the builders' weights, by both backends (the GPU reads its weights back, then uploads
// the components in the layout of the estimate kernels' components buffer).
#include "render/settings.hpp"

#include <vplkit/distribution/alias_table.hpp>
#include <vplkit/distribution/defensive_mixture.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/distribution/face_roulette.hpp>
#include <vplkit/distribution/flat_face_roulette.hpp>
#include <vplkit/distribution/mixture_split.hpp>
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace vplrender {

// The two components (learned, fallback) of each of D mixtures: component 2d + c, c = 0 the
// learned part, 1 the fallback. Only the vector of s.sampler / s.face_selection is filled.
struct mixture_components {
  int resolution = 0;                                       // R: a face has R^2 texels
  std::vector<vplkit::alias_table<float>> alias;            // --sampler alias
  std::vector<vplkit::face_roulette<float>> roulette;       // --face-selection roulette
  std::vector<vplkit::flat_face_roulette<float>> flat;      // views of `roulette`, same order

  // True when s asks for alias tables or face roulettes (--sampler share-tree builds its trees
  // elsewhere: render/share_tree_mixture.hpp, gpu_share_tree.hpp).
  static bool wanted(const render_settings& s) {
    return s.sampler == sampler_choice::alias || s.face_selection != face_selection_choice::joint;
  }
};

// weights: D arrays of 2 R^2 (region-major), the builders' weights. The fallback's weights are
// make_vpl_fallback's (1 on the texels that carry a VPL) when eps > 0, else all 0 (eps = 0 builds
// no fallback: its component then has pmf 0 everywhere, as the missing fallback). Throws
// vplkit::invalid_input as the library's builders for bad weights.
inline mixture_components build_mixture_components(const float* weights, int D, const vplkit::dprsm_view<float>& view,
                                                   const render_settings& s) {
  mixture_components out;
  out.resolution = view.resolution;
  const std::size_t n = static_cast<std::size_t>(view.texel_count());
  const std::size_t face = n / 2;
  std::vector<float> fallback(n, 0.0f);
  if (s.eps > 0.0f)
    for (std::size_t t = 0; t < n; ++t) fallback[t] = vplkit::vpl_has_flux(view.vpl_at(static_cast<int>(t))) ? 1.0f : 0.0f;
  for (int d = 0; d < D; ++d) {
    for (const float* w : {weights + static_cast<std::size_t>(d) * n, static_cast<const float*>(fallback.data())}) {
      if (s.sampler == sampler_choice::alias) {
        out.alias.emplace_back(w, n);
      } else {
        out.roulette.emplace_back(vplkit::discrete_cdf<float>(w, face), vplkit::discrete_cdf<float>(w + face, face));
      }
    }
  }
  out.flat.reserve(out.roulette.size());
  for (const auto& r : out.roulette) out.flat.emplace_back(r, view.resolution);
  return out;
}

// The D mixtures over `components` (learned 2d, fallback 2d + 1), each with the eps of the joint
// mixture joint[d]: vplkit::defensive_mixture over alias_table or flat_face_roulette, the
// estimators' Distribution interface. The components' totals are the joint CDFs' (the same
// sanitised weights), so each mixture's split is joint[d]'s (checked): both pick the same component
// with the same remapped u for every u, as the estimate kernels do with the joint mixture's split.
// Components are taken by value: move alias tables in; flat_face_roulette is a view.
template <class Component>
std::vector<vplkit::defensive_mixture<float, Component>> component_mixtures(
    const std::vector<vplkit::defensive_mixture<float>>& joint, std::vector<Component> components) {
  if (components.size() != 2 * joint.size())
    throw std::logic_error("component_mixtures: " + std::to_string(components.size()) + " components for " +
                           std::to_string(joint.size()) + " mixtures");
  std::vector<vplkit::defensive_mixture<float, Component>> out;
  out.reserve(joint.size());
  for (std::size_t d = 0; d < joint.size(); ++d) {
    out.emplace_back(std::move(components[2 * d]), std::move(components[2 * d + 1]), joint[d].eps());
    const vplkit::mixture_split<float>& a = out.back().split();
    const vplkit::mixture_split<float>& b = joint[d].split();
    if (a.effective_eps() != b.effective_eps() || a.fallback_scale() != b.fallback_scale() ||
        a.learned_scale() != b.learned_scale())
      throw std::logic_error("component_mixtures: mixture " + std::to_string(d) +
                             " splits u otherwise than its joint CDF mixture");
  }
  return out;
}

}  // namespace vplrender
