// SPDX-License-Identifier: MIT
// vplkit GLSL pack: the split of one u between the two components of a defensive mixture,
// p(i) = (1 - eps) p_learned(i) + eps p_fallback(i) (docs/math.md, "Defensive mixing"; mirrors
// include/vplkit/distribution/mixture_split.hpp, T = float).
//
// It is all of a defensive mixture that does not depend on what its components are: GLSL has no
// templates, so a mixture over any sampler (vplkit_discrete_cdf, vplkit_alias_table,
// vplkit_flat_face_roulette, ...) is written as
//     vplkit_mixture_choice c = vplkit_mixture_split_choose(s, u);
//     uint i = <sample component c.component with c.u>.index;
//     float p = vplkit_mixture_split_pmf(s, <learned pmf of i>, <fallback pmf of i>);
// and returns the C++ defensive_mixture<float, Component>'s index and pmf bit for bit.
//
// u < eps picks the fallback and is remapped to u * fallback_scale, otherwise the learned
// component gets (u - eps) * learned_scale. The scales are constants of the split (the C++
// computes them in double and rounds once), so choosing uses only -, * and comparisons, which
// GLSL 4.x rounds correctly: given the C++ scales, the same component and remapped u bit for bit.
#ifndef VPLKIT_DISTRIBUTION_MIXTURE_SPLIT_GLSL
#define VPLKIT_DISTRIBUTION_MIXTURE_SPLIT_GLSL

#include "vplkit/distribution/weights.glsl"

// C++ mixture_component.
const uint VPLKIT_MIXTURE_LEARNED = 0u;
const uint VPLKIT_MIXTURE_FALLBACK = 1u;

// The C++ mixture_split<float> after construction: effective_eps() and the two scales
// fallback_scale() = 1 / effective_eps and learned_scale() = 1 / (1 - effective_eps) (0 where
// undefined). Fill it from those accessors or with vplkit_make_mixture_split.
struct vplkit_mixture_split {
  float effective_eps;
  float fallback_scale;
  float learned_scale;
};

// C++ mixture_choice<float>: the component (VPLKIT_MIXTURE_LEARNED or VPLKIT_MIXTURE_FALLBACK)
// and the u to sample it with, in [0, 1).
struct vplkit_mixture_choice {
  uint component;
  float u;
};

// The C++ constructor, for components known only on the GPU (say built by cdf_build.comp), with
// the reciprocals of the requested eps supplied by the host: eps_scale = float(1.0 / double(eps))
// and one_minus_eps_scale = float(1.0 / double(1.0f - eps)) (the C++ reciprocal_or_zero of eps and
// of the float 1 - eps; used only when the effective eps is strictly between 0 and 1). With those
// the result is field for field the C++ object's. eps in [0, 1]: validation is the host's job.
vplkit_mixture_split vplkit_make_mixture_split(float eps, bool learned_empty, bool fallback_empty,
                                               float eps_scale, float one_minus_eps_scale) {
  vplkit_mixture_split s;
  // An eps below the smallest normal float counts as 0, as in the C++.
  s.effective_eps = learned_empty ? (fallback_empty ? 0.0 : 1.0)
                                  : (fallback_empty ? 0.0 : vplkit_flush_denormal(eps));
  // reciprocal_or_zero of 0 is 0 and of 1 is 1; otherwise the host's reciprocals.
  s.fallback_scale = s.effective_eps == 0.0 ? 0.0 : (s.effective_eps == 1.0 ? 1.0 : eps_scale);
  s.learned_scale = s.effective_eps == 1.0 ? 0.0 : (s.effective_eps == 0.0 ? 1.0 : one_minus_eps_scale);
  return s;
}

// The same with the reciprocals computed here (GLSL division: within 2.5 ulp of the C++ scales,
// so a remapped u, and then an index, may differ from the C++ one for u within a few ulps of a
// bin edge; the pmf is exact either way, since it does not use the scales).
vplkit_mixture_split vplkit_make_mixture_split(float eps, bool learned_empty, bool fallback_empty) {
  return vplkit_make_mixture_split(eps, learned_empty, fallback_empty, vplkit_reciprocal_or_zero(eps),
                                   vplkit_reciprocal_or_zero(1.0 - eps));
}

// C++ choose(u): u clamped to [0, 1), the component that serves it and the remapped u (clamped
// too). Effective eps 0: the learned component with u itself, so eps = 0 is the learned component
// bit for bit; effective eps 1: the fallback with u itself. A zero scale is never used.
vplkit_mixture_choice vplkit_mixture_split_choose(vplkit_mixture_split s, float u) {
  u = vplkit_discrete_clamp_u(u);
  if (u < s.effective_eps)
    return vplkit_mixture_choice(VPLKIT_MIXTURE_FALLBACK, vplkit_discrete_clamp_u(u * s.fallback_scale));
  return vplkit_mixture_choice(VPLKIT_MIXTURE_LEARNED,
                               vplkit_discrete_clamp_u((u - s.effective_eps) * s.learned_scale));
}

// The mixture's pmf from its parts (C++ defensive_mixture_pmf); sampling and the pmf of an index
// both use it. A term below 2^-126 while both factors are > 0 becomes 2^-126: 0 or normal terms,
// so the sum has the C++ bits on every device.
// precise: the sum must not absorb a product into an FMA (one rounding fewer than the C++).
float vplkit_defensive_mixture_pmf(float eps, float p_learned, float p_fallback) {
  precise float a = vplkit_probability_product(1.0 - eps, p_learned);
  precise float b = vplkit_probability_product(eps, p_fallback);
  precise float p = a + b;
  return p;
}

// C++ pmf(p_learned, p_fallback).
float vplkit_mixture_split_pmf(vplkit_mixture_split s, float p_learned, float p_fallback) {
  return vplkit_defensive_mixture_pmf(s.effective_eps, p_learned, p_fallback);
}

#endif  // VPLKIT_DISTRIBUTION_MIXTURE_SPLIT_GLSL
