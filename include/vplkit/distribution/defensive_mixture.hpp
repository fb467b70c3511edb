// SPDX-License-Identifier: MIT
#pragma once
// Defensive sampling (docs/math.md section 3, defensive mixing):
//     p(i) = (1 - eps) p_learned(i) + eps p_fallback(i).
// With a fallback that covers every index that may contribute (typically uniform over the valid
// paraboloid texels: a discrete_cdf of 0/1 weights), p(i) > 0 wherever the learned CDF left a
// hole, so the estimator L_t / p(t) stays unbiased. eps = 0 reproduces the learned CDF exactly
// (same index, same pmf for every u).
//
// One u serves both decisions: u < eps picks the fallback and is rescaled to u * (1 / eps),
// otherwise the learned CDF gets (u - eps) * (1 / (1 - eps)). The reciprocals are computed once
// in double and rounded to T, so a sample uses only -, * and comparisons, which IEEE (and GLSL
// 4.x for highp) round correctly: a GPU mirror gets the same index bit for bit, where a GLSL
// division (2.5 ulp) would not. The rescaling is monotone, so stratification survives within
// each component. It costs the low bits of u (as any reuse of u does).
#include <vplkit/core/normal_range.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/distribution/discrete_sample.hpp>
#include <vplkit/distribution/weights.hpp>

#include <cstddef>
#include <string>
#include <utility>

namespace vplkit {

// The mixture's pmf from its parts; sample() and pmf() both use it, so they agree bit for bit.
// A term below the smallest normal T while both its factors are > 0 becomes that value (see
// detail::probability_product): an index the mixture can return never reports pmf 0. Both terms
// are 0 or normal, so is their sum: the same bits on every device.
template <class T>
inline T defensive_mixture_pmf(T eps, T p_learned, T p_fallback) noexcept {
  return detail::probability_product(T(1) - eps, p_learned) +
         detail::probability_product(eps, p_fallback);
}

template <class T>
class defensive_mixture {
public:
  using value_type = T;

  defensive_mixture() = default;

  // eps in [0, 1] (NaN rejected). The two distributions must have the same size, except that
  // either may be default-constructed (size 0). An empty learned distribution sends all mass to
  // the fallback (effective eps = 1), an empty fallback all mass to the learned one (effective
  // eps = 0); both empty gives an empty mixture.
  defensive_mixture(discrete_cdf<T> learned, discrete_cdf<T> fallback, T eps)
      : learned_(std::move(learned)), fallback_(std::move(fallback)), eps_(eps) {
    if (!(eps >= T(0) && eps <= T(1))) {
      throw invalid_input("defensive_mixture: eps = " + std::to_string(eps) +
                          " is outside [0, 1]");
    }
    if (learned_.size() != fallback_.size() && learned_.size() != 0 && fallback_.size() != 0) {
      throw invalid_input("defensive_mixture: learned distribution has " +
                          std::to_string(learned_.size()) + " entries, fallback has " +
                          std::to_string(fallback_.size()));
    }
    // An eps below the smallest normal T counts as 0 (the normal-range contract of weights.hpp:
    // a GPU may read the uploaded value as 0).
    effective_eps_ = learned_.empty() ? (fallback_.empty() ? T(0) : T(1))
                                      : (fallback_.empty() ? T(0) : flush_denormal(eps_));
    fallback_scale_ = detail::reciprocal_or_zero(effective_eps_);
    learned_scale_ = detail::reciprocal_or_zero(T(1) - effective_eps_);
  }

  std::size_t size() const noexcept {
    return learned_.size() > fallback_.size() ? learned_.size() : fallback_.size();
  }
  bool empty() const noexcept { return learned_.empty() && fallback_.empty(); }
  T eps() const noexcept { return eps_; }
  // The weight actually given to the fallback (see the constructor).
  T effective_eps() const noexcept { return effective_eps_; }
  const discrete_cdf<T>& learned() const noexcept { return learned_; }
  const discrete_cdf<T>& fallback() const noexcept { return fallback_; }

  T pmf(std::size_t i) const noexcept {
    return defensive_mixture_pmf(effective_eps_, learned_.pmf(i), fallback_.pmf(i));
  }

  // Returns the index and the mixture pmf (not the pmf of the component that produced it).
  discrete_sample<T> sample(T u) const noexcept {
    if (empty()) return {0, T(0)};
    const T e = effective_eps_;
    u = discrete_clamp_u(u);
    // e = 0: u < 0 never holds and (u - 0) * 1 == u exactly, so eps = 0 is the learned CDF bit
    // for bit. e = 1: u < 1 always holds and u * 1 == u. A zero scale is never used.
    const std::size_t i =
        u < e ? fallback_.sample(discrete_clamp_u(u * fallback_scale_)).index
              : learned_.sample(discrete_clamp_u((u - e) * learned_scale_)).index;
    return {i, pmf(i)};
  }

  // The same index and pmf as sample(u), with each component searched by a plain binary search
  // over its whole CDF (discrete_cdf::sample_binary_search) instead of the guide table: the
  // guided search returns exactly the binary search's index, so this exists to measure the guide
  // table's cost, not to change any result.
  discrete_sample<T> sample_binary_search(T u) const noexcept {
    if (empty()) return {0, T(0)};
    const T e = effective_eps_;
    u = discrete_clamp_u(u);
    const std::size_t i =
        u < e ? fallback_.sample_binary_search(discrete_clamp_u(u * fallback_scale_)).index
              : learned_.sample_binary_search(discrete_clamp_u((u - e) * learned_scale_)).index;
    return {i, pmf(i)};
  }

  // 1 / eps and 1 / (1 - eps) as T (0 where undefined), for a GPU mirror.
  T fallback_scale() const noexcept { return fallback_scale_; }
  T learned_scale() const noexcept { return learned_scale_; }

private:
  discrete_cdf<T> learned_;
  discrete_cdf<T> fallback_;
  T eps_ = T(0);
  T effective_eps_ = T(0);
  T fallback_scale_ = T(0);
  T learned_scale_ = T(1);
};

}  // namespace vplkit
