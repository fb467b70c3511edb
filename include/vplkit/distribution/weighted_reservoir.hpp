// SPDX-License-Identifier: MIT
#pragma once
// Streaming weighted reservoir sampling, keep one (Chao 1982; the selection step of resampled
// importance sampling, Talbot et al. 2005, and of ReSTIR, Bitterli et al. 2020). Items arrive one
// at a time with weights w_i >= 0; after any prefix of the stream the kept item is item i with
// probability exactly
//     P(kept = i) = w_i / sum_j w_j                                   (docs/math.md section 13)
// with O(1) memory: the running sum and the kept item. Item i replaces the kept one when
// u_i * S_i < w_i, S_i = w_1 + ... + w_i, u_i uniform in [0, 1): probability w_i / S_i, and
// induction over the stream gives the closed form above (tests/statistical/ris_reservoir_test.cpp
// checks it by chi-square, one kept item and k kept items).
//
// Keep k (with replacement): feed the same items to k reservoirs, each with its own u. Each one
// keeps item i with probability w_i / sum w, independently of the others (the pairs are checked
// against the product distribution).
//
// Weights that are negative, NaN or infinite, and a weight that would carry the sum past the
// largest finite T, are ignored (as weight 0: the reservoir and its sum are unchanged), so the
// sum and every probability stay finite. The decision multiplies (u * S < w) instead of dividing:
// IEEE and GLSL 4.x round a product correctly, so the GPU mirror
// (glsl/vplkit/distribution/weighted_reservoir.glsl) decides alike on the same bits.
#include <cmath>
#include <cstdint>
#include <limits>

namespace vplkit {

// The index of a reservoir that has kept nothing (no item with a weight > 0 seen yet).
inline constexpr std::uint32_t reservoir_empty = 0xffffffffu;

template <class T>
struct weighted_reservoir {
  std::uint32_t index = reservoir_empty;  // the kept item, or reservoir_empty
  T weight_sum = T(0);                    // sum of the valid weights seen so far
  T weight = T(0);                        // the kept item's weight (0 while empty)
};

// True for a weight the reservoir takes into account: finite and > 0 (0 is valid but never kept).
template <class T>
inline bool reservoir_weight_usable(T w) noexcept {
  return w > T(0) && w <= std::numeric_limits<T>::max();  // NaN fails both
}

template <class T>
inline bool reservoir_empty_of(const weighted_reservoir<T>& r) noexcept {
  return r.index == reservoir_empty;
}

// Offers item `index` with weight w and the uniform number u in [0, 1) (any other u is clamped
// into it: NaN and negative to 0, >= 1 to just below 1). Returns true when the item is kept (it
// replaced the previous one). A weight that is not usable, or whose addition would overflow the
// sum, leaves the reservoir unchanged and returns false.
template <class T>
inline bool reservoir_update(weighted_reservoir<T>& r, std::uint32_t index, T w, T u) noexcept {
  if (!reservoir_weight_usable(w)) return false;
  const T sum = r.weight_sum + w;
  if (!(sum <= std::numeric_limits<T>::max())) return false;
  r.weight_sum = sum;
  const T uc = !(u >= T(0)) ? T(0) : (u < T(1) ? u : T(1) - std::numeric_limits<T>::epsilon() / T(2));
  // u * sum < w: probability w / sum for u uniform; the first usable item is always kept
  // (u * w < w for u < 1; u = 0 too).
  if (uc * sum < w || reservoir_empty_of(r)) {
    r.index = index;
    r.weight = w;
    return true;
  }
  return false;
}

}  // namespace vplkit
