// SPDX-License-Identifier: MIT
#pragma once
// The split of one u between the two components of a defensive mixture (docs/math.md, "Defensive
// mixing"): p(i) = (1 - eps) p_learned(i) + eps p_fallback(i). It is the part of
// defensive_mixture that does not depend on what the components are, so that a mixture over any
// sampler (discrete_cdf, alias_table, flat_face_roulette, or one that lives only on a GPU) picks
// the same component, with the same remapped u, and reports the same pmf, bit for bit.
//
// One u serves both decisions: u < eps picks the fallback and is remapped to u * (1 / eps),
// otherwise the learned component gets (u - eps) * (1 / (1 - eps)) (pbrt-v4's SampleDiscrete and
// Mitsuba 3's sample_reuse hand back a remapped u the same way). The reciprocals are computed
// once, in double, and rounded to T, so choose() uses only -, * and comparisons, which IEEE (and
// GLSL 4.x for highp) round correctly: a GPU given fallback_scale() and learned_scale() picks the
// same component and the same remapped u, where a GLSL division (2.5 ulp) would not. The
// remapping is monotone within each component, so stratification survives; it costs the low bits
// of u, as any reuse of u does.
#include <vplkit/core/error.hpp>
#include <vplkit/core/normal_range.hpp>
#include <vplkit/distribution/weights.hpp>

#include <string>

namespace vplkit {

// The mixture's pmf from its parts. sample() and pmf() of every mixture use it, so they agree bit
// for bit. A term below the smallest normal T while both its factors are > 0 becomes that value
// (see detail::probability_product): an index the mixture can return never reports pmf 0. Both
// terms are 0 or normal, so is their sum: the same bits on every device.
template <class T>
inline T defensive_mixture_pmf(T eps, T p_learned, T p_fallback) noexcept {
  return detail::probability_product(T(1) - eps, p_learned) +
         detail::probability_product(eps, p_fallback);
}

// Which component of a two-component mixture serves a u: mixture_learned or mixture_fallback.
enum mixture_component : unsigned { mixture_learned = 0u, mixture_fallback = 1u };

// The answer of mixture_split::choose: the component, and the u it is to be sampled with, in
// [0, 1) (the "sample_reuse" form: the part of u that the choice did not use, stretched back to
// the unit interval).
template <class T>
struct mixture_choice {
  mixture_component component = mixture_learned;
  T u = T(0);
};

namespace detail {

// eps must lie in [0, 1]; NaN is rejected. `who` names the caller in the message.
template <class T>
inline void check_mixture_eps(const char* who, T eps) {
  if (!(eps >= T(0) && eps <= T(1)))
    throw invalid_input(std::string(who) + ": eps = " + std::to_string(eps) + " is outside [0, 1]");
}

}  // namespace detail

template <class T>
class mixture_split {
public:
  using value_type = T;

  // No components: everything to the (empty) learned side, eps 0.
  mixture_split() = default;

  // eps in [0, 1] (NaN rejected: throws invalid_input). The effective eps, the weight actually
  // given to the fallback, is eps, except that an empty learned component sends all mass to the
  // fallback (1), an empty fallback all mass to the learned one (0; both empty gives 0), and an eps
  // below the smallest normal T counts as 0 (the normal-range contract of weights.hpp: a GPU may
  // read the uploaded value as 0).
  mixture_split(T eps, bool learned_empty, bool fallback_empty) {
    detail::check_mixture_eps("mixture_split", eps);
    effective_eps_ = learned_empty ? (fallback_empty ? T(0) : T(1))
                                   : (fallback_empty ? T(0) : flush_denormal(eps));
    fallback_scale_ = detail::reciprocal_or_zero(effective_eps_);
    learned_scale_ = detail::reciprocal_or_zero(T(1) - effective_eps_);
  }

  // The weight given to the fallback (see the constructor).
  T effective_eps() const noexcept { return effective_eps_; }
  // 1 / eps and 1 / (1 - eps) of the effective eps, as T (0 where undefined), for a GPU mirror.
  T fallback_scale() const noexcept { return fallback_scale_; }
  T learned_scale() const noexcept { return learned_scale_; }

  // The component that serves u, and the remapped u to sample it with. u is clamped to [0, 1)
  // first (discrete_clamp_u), and so is the remapped u. Effective eps 0: the learned component
  // with u itself ((u - 0) * 1 == u exactly), so eps = 0 is the learned component bit for bit;
  // effective eps 1: the fallback with u itself (u < 1 always holds and u * 1 == u). A zero scale
  // is never used. Within each component the remapped u is non-decreasing in u.
  mixture_choice<T> choose(T u) const noexcept {
    u = discrete_clamp_u(u);
    if (u < effective_eps_) return {mixture_fallback, discrete_clamp_u(u * fallback_scale_)};
    return {mixture_learned, discrete_clamp_u((u - effective_eps_) * learned_scale_)};
  }

  // The mixture's pmf of an index from its components' pmfs of it (defensive_mixture_pmf).
  T pmf(T p_learned, T p_fallback) const noexcept {
    return defensive_mixture_pmf(effective_eps_, p_learned, p_fallback);
  }

private:
  T effective_eps_ = T(0);
  T fallback_scale_ = T(0);
  T learned_scale_ = T(1);
};

}  // namespace vplkit
