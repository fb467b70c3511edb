// SPDX-License-Identifier: MIT
#pragma once
// Global weights (BRSM, Ritschel et al. 2011; docs/math.md section 4): the mean luminance of every
// VPL's contribution to a subset S of gather points, without visibility:
//     w_t = (1 / |S|) sum_{g in S} luminance(L_t(g)),   L_t = vpl_contribution (docs/math.md
//     section 2).
// A texel that carries no VPL (invalid, saw nothing, or faces away from the light: vpl_at gives
// zero flux) gets exactly 0 without evaluating any contribution, so it can never be sampled.
//
// |S| counts the valid gather points of the subset only: background pixels in a caller's subset
// are skipped (they have no surface to receive light). An empty or all-background subset gives
// all-zero weights (an empty distribution), never NaN.
//
// Arithmetic: the per-texel sum runs in T over the subset in the order given, then is multiplied by
// T(1) / T(|S|) - the statement order of the GLSL mirror (one invocation per texel). A float sum
// of |S| positive terms is within about |S| * 2^-24 relative of exact (2.4e-4 at |S| = 4096, far
// less typically): the weights only shape the pmf, and every estimator divides by the pmf of the
// stored CDF, so this rounding costs no bias.
#include <vplkit/builders/detail/argument_checks.hpp>
#include <vplkit/core/error.hpp>
#include <vplkit/core/gather_point.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/luminance.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace vplkit {

// w_t for one texel from `count` gather points (all assumed valid). The per-invocation function of
// a GPU pass; never throws. 0 when count == 0 or the texel carries no VPL.
template <class T>
inline T global_weight_texel(const dprsm_view<T>& view, int texel, const gather_point<T>* points,
                             int count, T dmin) {
  const vpl<T> v = view.vpl_at(texel);
  if (count <= 0 || !vpl_has_flux(v)) return T(0);
  T sum = T(0);
  for (int i = 0; i < count; ++i) {
    const gather_point<T>& g = points[i];
    sum += luminance(vpl_contribution(g, v, dmin));
  }
  return sum * (T(1) / T(count));
}

namespace detail {

// The valid gather points among pixel indices `pixels` (throws for an index outside the image).
template <class T>
inline std::vector<gather_point<T>> collect_gather_points(const gbuffer_view<T>& gbuffer,
                                                          const int* pixels, std::size_t count,
                                                          const char* who) {
  if (count > 0 && pixels == nullptr)
    throw invalid_input(std::string(who) + ": null pixel index pointer");
  std::vector<gather_point<T>> points;
  points.reserve(count);
  const int n = gbuffer.pixel_count();
  for (std::size_t i = 0; i < count; ++i) {
    const int p = pixels[i];
    if (p < 0 || p >= n)
      throw invalid_input(std::string(who) + ": subset entry " + std::to_string(i) +
                          " is pixel " + std::to_string(p) + ", outside the " +
                          std::to_string(gbuffer.width) + " x " + std::to_string(gbuffer.height) +
                          " image");
    const gather_point<T> g = gbuffer.at(p);
    if (gather_point_valid(g)) points.push_back(g);
  }
  return points;
}

}  // namespace detail

// Global weights for all 2 R^2 texels into weights[0 .. 2 R^2), from the gather points at pixel
// indices subset[0 .. subset_size) (y * width + x; typically stratified_gather_subset over the
// whole image). Returns |S|, the number of valid gather points used.
// Throws invalid_input for a bad G-buffer or DPRSM view (validate()), dmin negative or not finite,
// a weights span of the wrong size, or a subset index outside the image.
// Cost: |S| x (number of texels carrying a VPL, <= 2 R^2) contribution evaluations.
template <class T>
inline int build_global_weights(const gbuffer_view<T>& gbuffer, const int* subset,
                                std::size_t subset_size, const dprsm_view<T>& view, T dmin,
                                T* weights, std::size_t weights_size) {
  const char* who = "build_global_weights";
  gbuffer.validate();
  view.validate();
  detail::check_dmin(dmin, who);
  detail::check_weights_span(view, weights, weights_size, who);
  const std::vector<gather_point<T>> points =
      detail::collect_gather_points(gbuffer, subset, subset_size, who);
  const int count = int(points.size());
  const int n = view.texel_count();
  for (int t = 0; t < n; ++t) weights[t] = global_weight_texel(view, t, points.data(), count, dmin);
  return count;
}

// Convenience: the same weights in a new vector of 2 R^2 entries.
template <class T>
inline std::vector<T> build_global_weights(const gbuffer_view<T>& gbuffer,
                                           const std::vector<int>& subset,
                                           const dprsm_view<T>& view, T dmin) {
  view.validate();  // before texel_count() sizes the vector
  std::vector<T> w(std::size_t(view.texel_count()), T(0));
  build_global_weights(gbuffer, subset.data(), subset.size(), view, dmin, w.data(), w.size());
  return w;
}

}  // namespace vplkit
