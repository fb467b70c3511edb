// SPDX-License-Identifier: MIT
// vplkit GLSL pack: one presampled candidate of ris-mis (docs/math.md, "Presampled candidates"), the
// struct ris_pool_entry of include/vplkit/estimators/ris_candidate_pool.hpp (T = float), made and
// read by ris_candidate_pool.glsl. A file of its own, without accessors or hooks, so that a kernel
// that only moves entries (ris_pool_params.h's buffer record) includes it alone: Mesa's linker
// wants a body for every function that any included function references (docs/glsl.md, "Accessors
// and Mesa's linker"), and ris_candidate_pool.glsl brings the estimators' hooks.
#ifndef VPLKIT_ESTIMATORS_RIS_POOL_ENTRY_GLSL
#define VPLKIT_ESTIMATORS_RIS_POOL_ENTRY_GLSL

// What weighing the candidate at any gather point needs. pmf 0: an empty entry (the draw was
// empty, left the view, or its point has no flux), which every gather point weighs 0.
struct vplkit_ris_pool_entry {
  vec3 position;  // y: the texel's point (vplkit_vpl_point) or its jittered patch point
  float pmf;      // pmf(t) of the distribution the pool was drawn from
  vec3 normal;    // unit n_t (also the normal the visibility query gets)
  float area;     // the A of p2 (A_t, or A(uv) for a patch point)
  vec3 radiance;  // L_o(y), the reflected radiance of the point light at y
  int texel;      // -1: the draw was empty
  vec2 xi;        // the jitter (0 with vplkit_vpl_point)
  int at_centre;  // 1: the patch moved the point to the texel centre (gathering's alone when n1 > 0)
  int pad;
};

// The C++ ris_pool_entry<float>{}: empty, texel -1.
vplkit_ris_pool_entry vplkit_make_ris_pool_entry() {
  return vplkit_ris_pool_entry(vec3(0.0), 0.0, vec3(0.0), 0.0, vec3(0.0), -1, vec2(0.0), 0, 0);
}

#endif  // VPLKIT_ESTIMATORS_RIS_POOL_ENTRY_GLSL
