// SPDX-License-Identifier: MIT
#pragma once
// Defensive sampling (docs/math.md, "Defensive mixing"):
//     p(i) = (1 - eps) p_learned(i) + eps p_fallback(i).
// With a fallback that covers every index that may contribute (typically uniform over the valid
// paraboloid texels: a discrete_cdf of 0/1 weights), p(i) > 0 wherever the learned distribution
// left a hole, so the estimator L_t / p(t) stays unbiased. eps = 0 reproduces the learned
// distribution exactly (same index, same pmf for every u).
//
// The mixture is generic over its component type: any sampler with size(), empty(), pmf(i) and
// sample(u) -> discrete_sample<T> (discrete_cdf, the default; alias_table; flat_face_roulette).
// How one u is shared between the two components, and the pmf of the mixture, are the
// mixture_split's (mixture_split.hpp): every mixture over the same totals and eps picks its
// component with the same remapped u, whatever the components are.
#include <vplkit/core/normal_range.hpp>
#include <vplkit/core/prefetch.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/distribution/discrete_sample.hpp>
#include <vplkit/distribution/mixture_split.hpp>
#include <vplkit/distribution/weights.hpp>

#include <cstddef>
#include <string>
#include <utility>

namespace vplkit {

template <class T, class Component = discrete_cdf<T>>
class defensive_mixture {
public:
  using value_type = T;
  using component_type = Component;

  defensive_mixture() = default;

  // eps in [0, 1] (NaN rejected: throws invalid_input). The two components must have the same
  // size, except that either may have size 0 (default-constructed). An empty learned component
  // sends all mass to the fallback (effective eps = 1), an empty fallback all mass to the learned
  // one (effective eps = 0); both empty gives an empty mixture (see mixture_split).
  defensive_mixture(Component learned, Component fallback, T eps)
      : learned_(std::move(learned)), fallback_(std::move(fallback)), eps_(eps) {
    detail::check_mixture_eps("defensive_mixture", eps);
    if (learned_.size() != fallback_.size() && learned_.size() != 0 && fallback_.size() != 0) {
      throw invalid_input("defensive_mixture: learned distribution has " +
                          std::to_string(learned_.size()) + " entries, fallback has " +
                          std::to_string(fallback_.size()));
    }
    split_ = mixture_split<T>(eps_, learned_.empty(), fallback_.empty());
  }

  std::size_t size() const noexcept {
    return learned_.size() > fallback_.size() ? learned_.size() : fallback_.size();
  }
  bool empty() const noexcept { return learned_.empty() && fallback_.empty(); }
  // The eps asked for.
  T eps() const noexcept { return eps_; }
  // The weight actually given to the fallback (see the constructor).
  T effective_eps() const noexcept { return split_.effective_eps(); }
  const Component& learned() const noexcept { return learned_; }
  const Component& fallback() const noexcept { return fallback_; }
  // The split of u and the pmf rule; with it, a mixture can be rebuilt elsewhere (a GPU, other
  // components) that makes the same choices.
  const mixture_split<T>& split() const noexcept { return split_; }

  T pmf(std::size_t i) const noexcept { return split_.pmf(learned_.pmf(i), fallback_.pmf(i)); }

  // Returns the index and the mixture pmf (not the pmf of the component that produced it);
  // {0, 0} when empty.
  discrete_sample<T> sample(T u) const noexcept {
    if (empty()) return {0, T(0)};
    const mixture_choice<T> c = split_.choose(u);
    const std::size_t i = component(c.component).sample(c.u).index;
    return {i, pmf(i)};
  }

  // The component's prefetch_sample for the u it gets (distribution_prefetch: nothing for a
  // component without one).
  VPLKIT_PREFETCH_INLINE void prefetch_sample(T u) const noexcept {
    if (empty()) return;
    const mixture_choice<T> c = split_.choose(u);
    distribution_prefetch(component(c.component), c.u);
  }

  // discrete_cdf components only: the same index and pmf as sample(u), with each component
  // searched by a plain binary search over its whole CDF (discrete_cdf::sample_binary_search)
  // instead of the guide table: the guided search returns exactly the binary search's index, so
  // this exists to measure the guide table's cost, not to change any result.
  discrete_sample<T> sample_binary_search(T u) const noexcept {
    if (empty()) return {0, T(0)};
    const mixture_choice<T> c = split_.choose(u);
    const std::size_t i = component(c.component).sample_binary_search(c.u).index;
    return {i, pmf(i)};
  }

  // 1 / eps and 1 / (1 - eps) of the effective eps as T (0 where undefined), for a GPU mirror.
  T fallback_scale() const noexcept { return split_.fallback_scale(); }
  T learned_scale() const noexcept { return split_.learned_scale(); }

private:
  const Component& component(mixture_component c) const noexcept {
    return c == mixture_fallback ? fallback_ : learned_;
  }

  Component learned_;
  Component fallback_;
  T eps_ = T(0);
  mixture_split<T> split_;
};

}  // namespace vplkit
