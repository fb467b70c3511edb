// SPDX-License-Identifier: MIT
// vplkit GLSL pack: defensive sampling, p(i) = (1 - eps) p_learned(i) + eps p_fallback(i)
// (docs/math.md section 3, defensive mixing; mirrors
// include/vplkit/distribution/defensive_mixture.hpp, T = float).
//
// One u serves both decisions: u < eps picks the fallback and is rescaled to u * (1 / eps),
// otherwise the learned CDF gets (u - eps) * (1 / (1 - eps)). The reciprocals are constants of the
// mixture (fallback_scale, learned_scale), so a sample uses only -, * and comparisons, which GLSL
// 4.x rounds correctly: with the scales the C++ object reports, the GPU returns the C++ index and
// pmf bit for bit.
//
// ACCESSORS: those of discrete_cdf.glsl (vplkit_load_cdf, vplkit_load_guide); the two
// distributions are told apart by their descriptors' ids.
#ifndef VPLKIT_DISTRIBUTION_DEFENSIVE_MIXTURE_GLSL
#define VPLKIT_DISTRIBUTION_DEFENSIVE_MIXTURE_GLSL

#include "vplkit/distribution/discrete_cdf.glsl"
#include "vplkit/distribution/discrete_sample.glsl"
#include "vplkit/distribution/weights.glsl"

// The C++ defensive_mixture<float> after construction: its two distributions, effective_eps()
// (eps, or 1 when the learned distribution is empty, 0 when the fallback is) and the two scales
// fallback_scale() = 1 / effective_eps and learned_scale() = 1 / (1 - effective_eps) (0 where
// undefined). Fill it from those accessors, or with vplkit_make_defensive_mixture.
struct vplkit_defensive_mixture {
  vplkit_discrete_cdf learned;
  vplkit_discrete_cdf fallback;
  float effective_eps;
  float fallback_scale;
  float learned_scale;
};

// The C++ constructor's choice of the effective eps, for distributions known only on the GPU (say
// built by cdf_build.comp), with the reciprocals of the requested eps supplied by the host:
// eps_scale = float(1.0 / double(eps)) and one_minus_eps_scale = float(1.0 / double(1.0f - eps))
// (the C++ reciprocal_or_zero of eps and of the float 1 - eps; used only when the effective eps
// is strictly between 0 and 1). With those, the result is field for field the C++ object's.
// eps in [0, 1]: validation is the host's job.
vplkit_defensive_mixture vplkit_make_defensive_mixture(vplkit_discrete_cdf learned,
                                                       vplkit_discrete_cdf fallback, float eps,
                                                       float eps_scale,
                                                       float one_minus_eps_scale) {
  bool learned_empty = vplkit_discrete_cdf_empty(learned);
  bool fallback_empty = vplkit_discrete_cdf_empty(fallback);
  vplkit_defensive_mixture m;
  m.learned = learned;
  m.fallback = fallback;
  // An eps below the smallest normal float counts as 0, as in the C++.
  m.effective_eps = learned_empty ? (fallback_empty ? 0.0 : 1.0)
                                  : (fallback_empty ? 0.0 : vplkit_flush_denormal(eps));
  // reciprocal_or_zero of 0 is 0 and of 1 is 1; otherwise the host's reciprocals.
  m.fallback_scale = m.effective_eps == 0.0 ? 0.0 : (m.effective_eps == 1.0 ? 1.0 : eps_scale);
  m.learned_scale = m.effective_eps == 1.0 ? 0.0 : (m.effective_eps == 0.0 ? 1.0 : one_minus_eps_scale);
  return m;
}

// The same with the reciprocals computed here (GLSL division: within 2.5 ulp of the C++ scales,
// so an index may differ from the C++ one for u within a few ulps of a bin edge; the pmf is exact
// either way, since it does not use the scales).
vplkit_defensive_mixture vplkit_make_defensive_mixture(vplkit_discrete_cdf learned,
                                                       vplkit_discrete_cdf fallback, float eps) {
  return vplkit_make_defensive_mixture(learned, fallback, eps, vplkit_reciprocal_or_zero(eps),
                                       vplkit_reciprocal_or_zero(1.0 - eps));
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

bool vplkit_defensive_mixture_empty(vplkit_defensive_mixture m) {
  return vplkit_discrete_cdf_empty(m.learned) && vplkit_discrete_cdf_empty(m.fallback);
}

uint vplkit_defensive_mixture_size(vplkit_defensive_mixture m) {
  return max(m.learned.size, m.fallback.size);
}

// C++ pmf(i).
float vplkit_defensive_mixture_pmf(vplkit_defensive_mixture m, uint i) {
  return vplkit_defensive_mixture_pmf(m.effective_eps, vplkit_discrete_cdf_pmf(m.learned, i),
                                      vplkit_discrete_cdf_pmf(m.fallback, i));
}

// The index and the mixture pmf (not the pmf of the component that produced it); {0, 0} when
// both distributions are empty. e = 0: u < 0 never holds and (u - 0) * 1 == u, so eps = 0 is the
// learned CDF bit for bit; e = 1: u < 1 always holds and u * 1 == u.
vplkit_discrete_sample vplkit_defensive_mixture_sample(vplkit_defensive_mixture m, float u) {
  if (vplkit_defensive_mixture_empty(m)) return vplkit_discrete_sample(0u, 0.0);
  float e = m.effective_eps;
  u = vplkit_discrete_clamp_u(u);
  uint i = u < e
      ? vplkit_discrete_cdf_sample(m.fallback, vplkit_discrete_clamp_u(u * m.fallback_scale)).index
      : vplkit_discrete_cdf_sample(m.learned,
                                   vplkit_discrete_clamp_u((u - e) * m.learned_scale)).index;
  return vplkit_discrete_sample(i, vplkit_defensive_mixture_pmf(m, i));
}

// C++ sample_binary_search(u): the same index and pmf as vplkit_defensive_mixture_sample, each
// component searched by a plain binary search over its whole CDF (no guide table read).
vplkit_discrete_sample vplkit_defensive_mixture_sample_binary_search(vplkit_defensive_mixture m, float u) {
  if (vplkit_defensive_mixture_empty(m)) return vplkit_discrete_sample(0u, 0.0);
  float e = m.effective_eps;
  u = vplkit_discrete_clamp_u(u);
  uint i = u < e
      ? vplkit_discrete_cdf_sample_binary_search(m.fallback,
                                                 vplkit_discrete_clamp_u(u * m.fallback_scale)).index
      : vplkit_discrete_cdf_sample_binary_search(m.learned,
                                                 vplkit_discrete_clamp_u((u - e) * m.learned_scale)).index;
  return vplkit_discrete_sample(i, vplkit_defensive_mixture_pmf(m, i));
}

#endif  // VPLKIT_DISTRIBUTION_DEFENSIVE_MIXTURE_GLSL
