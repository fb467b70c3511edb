// SPDX-License-Identifier: MIT
#pragma once
// Argument checks shared by the weight builders; each names the calling function (`who`).
#include <vplkit/core/error.hpp>
#include <vplkit/vpl/dprsm_view.hpp>

#include <cmath>
#include <cstddef>
#include <string>

namespace vplkit {
namespace detail {

template <class T>
inline void check_dmin(T dmin, const char* who) {
  if (!(dmin >= T(0)) || !std::isfinite(dmin))
    throw invalid_input(std::string(who) + ": dmin = " + std::to_string(dmin) +
                        " must be finite and >= 0");
}

template <class T>
inline void check_weights_span(const dprsm_view<T>& view, const T* weights,
                               std::size_t weights_size, const char* who) {
  const std::size_t n = std::size_t(view.texel_count());
  if (weights_size != n)
    throw invalid_input(std::string(who) + ": weights span has " + std::to_string(weights_size) +
                        " entries, the DPRSM has 2 R^2 = " + std::to_string(n) + " texels");
  if (weights == nullptr) throw invalid_input(std::string(who) + ": null weights pointer");
}

}  // namespace detail
}  // namespace vplkit
