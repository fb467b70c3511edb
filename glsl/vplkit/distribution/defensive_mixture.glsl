// SPDX-License-Identifier: MIT
// vplkit GLSL pack: defensive sampling, p(i) = (1 - eps) p_learned(i) + eps p_fallback(i)
// (docs/math.md, "Defensive mixing"; mirrors include/vplkit/distribution/defensive_mixture.hpp
// with its default component, T = float: defensive_mixture<float, discrete_cdf<float>>).
//
// The split of u and the pmf rule are mixture_split.glsl's: vplkit_defensive_mixture_split(m)
// hands them to a mixture over other components (see mixture_split.glsl for the pattern).
//
// ACCESSORS: those of discrete_cdf.glsl (vplkit_load_cdf, vplkit_load_guide); the two
// distributions are told apart by their descriptors' ids.
#ifndef VPLKIT_DISTRIBUTION_DEFENSIVE_MIXTURE_GLSL
#define VPLKIT_DISTRIBUTION_DEFENSIVE_MIXTURE_GLSL

#include "vplkit/distribution/discrete_cdf.glsl"
#include "vplkit/distribution/discrete_sample.glsl"
#include "vplkit/distribution/mixture_split.glsl"
#include "vplkit/distribution/weights.glsl"

// The C++ defensive_mixture<float> after construction: its two distributions and its split's
// effective_eps() (eps, or 1 when the learned distribution is empty, 0 when the fallback is),
// fallback_scale() = 1 / effective_eps and learned_scale() = 1 / (1 - effective_eps) (0 where
// undefined). Fill it from those accessors, or with vplkit_make_defensive_mixture.
struct vplkit_defensive_mixture {
  vplkit_discrete_cdf learned;
  vplkit_discrete_cdf fallback;
  float effective_eps;
  float fallback_scale;
  float learned_scale;
};

// C++ split().
vplkit_mixture_split vplkit_defensive_mixture_split(vplkit_defensive_mixture m) {
  return vplkit_mixture_split(m.effective_eps, m.fallback_scale, m.learned_scale);
}

// The C++ constructor for distributions known only on the GPU (say built by cdf_build.comp): the
// split of vplkit_make_mixture_split (eps_scale and one_minus_eps_scale as documented there).
vplkit_defensive_mixture vplkit_make_defensive_mixture(vplkit_discrete_cdf learned,
                                                       vplkit_discrete_cdf fallback, float eps,
                                                       float eps_scale,
                                                       float one_minus_eps_scale) {
  vplkit_mixture_split s = vplkit_make_mixture_split(eps, vplkit_discrete_cdf_empty(learned),
                                                     vplkit_discrete_cdf_empty(fallback), eps_scale,
                                                     one_minus_eps_scale);
  return vplkit_defensive_mixture(learned, fallback, s.effective_eps, s.fallback_scale,
                                  s.learned_scale);
}

// The same with the reciprocals computed here (GLSL division: within 2.5 ulp of the C++ scales,
// so an index may differ from the C++ one for u within a few ulps of a bin edge; the pmf is exact
// either way, since it does not use the scales).
vplkit_defensive_mixture vplkit_make_defensive_mixture(vplkit_discrete_cdf learned,
                                                       vplkit_discrete_cdf fallback, float eps) {
  return vplkit_make_defensive_mixture(learned, fallback, eps, vplkit_reciprocal_or_zero(eps),
                                       vplkit_reciprocal_or_zero(1.0 - eps));
}

bool vplkit_defensive_mixture_empty(vplkit_defensive_mixture m) {
  return vplkit_discrete_cdf_empty(m.learned) && vplkit_discrete_cdf_empty(m.fallback);
}

uint vplkit_defensive_mixture_size(vplkit_defensive_mixture m) {
  return max(m.learned.size, m.fallback.size);
}

// C++ pmf(i).
float vplkit_defensive_mixture_pmf(vplkit_defensive_mixture m, uint i) {
  return vplkit_mixture_split_pmf(vplkit_defensive_mixture_split(m),
                                  vplkit_discrete_cdf_pmf(m.learned, i),
                                  vplkit_discrete_cdf_pmf(m.fallback, i));
}

// The index and the mixture pmf (not the pmf of the component that produced it); {0, 0} when
// both distributions are empty.
vplkit_discrete_sample vplkit_defensive_mixture_sample(vplkit_defensive_mixture m, float u) {
  if (vplkit_defensive_mixture_empty(m)) return vplkit_discrete_sample(0u, 0.0);
  vplkit_mixture_choice c = vplkit_mixture_split_choose(vplkit_defensive_mixture_split(m), u);
  vplkit_discrete_cdf d = c.component == VPLKIT_MIXTURE_FALLBACK ? m.fallback : m.learned;
  uint i = vplkit_discrete_cdf_sample(d, c.u).index;
  return vplkit_discrete_sample(i, vplkit_defensive_mixture_pmf(m, i));
}

// C++ sample_binary_search(u): the same index and pmf as vplkit_defensive_mixture_sample, each
// component searched by a plain binary search over its whole CDF (no guide table read).
vplkit_discrete_sample vplkit_defensive_mixture_sample_binary_search(vplkit_defensive_mixture m, float u) {
  if (vplkit_defensive_mixture_empty(m)) return vplkit_discrete_sample(0u, 0.0);
  vplkit_mixture_choice c = vplkit_mixture_split_choose(vplkit_defensive_mixture_split(m), u);
  vplkit_discrete_cdf d = c.component == VPLKIT_MIXTURE_FALLBACK ? m.fallback : m.learned;
  uint i = vplkit_discrete_cdf_sample_binary_search(d, c.u).index;
  return vplkit_discrete_sample(i, vplkit_defensive_mixture_pmf(m, i));
}

#endif  // VPLKIT_DISTRIBUTION_DEFENSIVE_MIXTURE_GLSL
