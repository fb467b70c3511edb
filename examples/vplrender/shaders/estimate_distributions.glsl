// SPDX-License-Identifier: MIT
// vplrender's estimate kernels: the distributions over the VPLs that the pack's estimators sample
// through their two hooks (vplkit_estimator_distribution_sample / _pmf). Distribution d is the
// defensive mixture of record d (estimate_params.h's vr_mixture_record, built on the GPU by
// gpu_cdf.cpp's cdf_build.comp dispatches and described to the kernel by gpu_backend.cpp). How a
// draw turns u into a texel is the variant's VR_SAMPLER:
//   VR_SAMPLER_CDF_GUIDE / _CDF_BINARY: the mixture's CDFs, guide table or plain binary search
//     (both return the same index and pmf);
//   VR_SAMPLER_ALIAS / _ROULETTE: the mixture's split with its components replaced by alias tables
//     or face roulettes built on the host (render/mixture_components.hpp, binding 7, packed by
//     gpu_backend.cpp's pack_components: 12 uints per component k = 2 d + c, c = 0 the learned
//     part, 1 the fallback, then the arrays they point into).
//   VR_SAMPLER_SHARE_TREE: the mixture's split and fallback CDF, its learned part a share tree built
//     by share_tree_build.comp (binding 7: the shares, tree d at d L), drawn with 24-bit numbers
//     from the pixel's tree stream vr_share_tree_rng (render/share_tree_mixture.hpp, number for
//     number): the kernel calls vr_begin_share_tree_stream before its first draw of a dispatch
//     (global, gbg: one mixture; local: the regions' mixtures, their draws in one stream).
// VR_RIS_TILES (ris-mis, --candidate-source tiles): mixture d is tile d's, its learned part a CDF
//   over texel blocks refined by the blocks' shares (estimate_tiles.glsl); VR_SAMPLER is not used.
// A kernel that samples one mixture only (global, gbg, mis) defines VR_ONE_MIXTURE and calls
// vr_load_mixtures() once: the record then lives in registers instead of being loaded per draw.
// A distribution's CDF and guide are addressed by arithmetic on its index (cdf_stride, guide_base,
// guide_stride): no slot table between a draw and its loads.
#ifndef VPLRENDER_ESTIMATE_DISTRIBUTIONS_GLSL
#define VPLRENDER_ESTIMATE_DISTRIBUTIONS_GLSL

#include "estimate_io.glsl"
#include "vplkit/distribution/alias_table.glsl"
#include "vplkit/distribution/defensive_mixture.glsl"
#include "vplkit/distribution/flat_face_roulette.glsl"

layout(std430, binding = VR_ESTIMATE_BINDING_CDF_DATA) restrict readonly buffer VrCdfData { uint vr_cdf_data[]; };
layout(std430, binding = VR_ESTIMATE_BINDING_MIXTURES) restrict readonly buffer VrMixtures {
  vr_mixture_record vr_mixture_records[];
};
#if VR_SAMPLER == VR_SAMPLER_ALIAS || VR_SAMPLER == VR_SAMPLER_ROULETTE
layout(std430, binding = VR_ESTIMATE_BINDING_COMPONENTS) restrict readonly buffer VrComponents { uint vr_components[]; };
#endif
#if VR_SAMPLER == VR_SAMPLER_SHARE_TREE
#include "vplkit/distribution/share_tree.glsl"
#include "vplkit/sampling/rng.glsl"
layout(std430, binding = VR_ESTIMATE_BINDING_COMPONENTS) restrict readonly buffer VrShares { uint vr_shares[]; };
#endif

#ifdef VR_RIS_TILES
#include "estimate_tiles.glsl"
#endif

float vplkit_load_cdf(uint id, uint i) {
#ifdef VR_RIS_TILES
  if (id >= VR_TILE_SLOT) return vr_tile_load_cdf(id - VR_TILE_SLOT, i);
#endif
#if VR_SAMPLER == VR_SAMPLER_ROULETTE
  if (id >= VR_COMPONENT_SLOT) {
    uint record = 12u * ((id - VR_COMPONENT_SLOT) >> 1u) + 3u * (id & 1u);
    return uintBitsToFloat(vr_components[vr_components[record] + i]);
  }
#endif
  return uintBitsToFloat(vr_cdf_data[id * vr_params.cdf_stride + i]);
}
uint vplkit_load_guide(uint id, uint j) {
#ifdef VR_RIS_TILES
  if (id >= VR_TILE_SLOT) return vr_tile_load_guide(id - VR_TILE_SLOT, j);
#endif
#if VR_SAMPLER == VR_SAMPLER_ROULETTE
  if (id >= VR_COMPONENT_SLOT) {
    uint record = 12u * ((id - VR_COMPONENT_SLOT) >> 1u) + 3u * (id & 1u);
    return vr_components[vr_components[record + 1u] + j];
  }
#endif
  return vr_cdf_data[vr_params.guide_base + id * vr_params.guide_stride + j];
}

// Callers copy the record out of the buffer first: NVIDIA's compiler (580) refuses a member of a
// `restrict readonly` buffer as a function argument (error C1317, "qualified actual parameter
// cannot be converted to less qualified parameter"), which the GLSL spec allows.
vplkit_defensive_mixture vr_unpack_mixture(vr_mixture_record r) {
  return vplkit_defensive_mixture(
      vplkit_discrete_cdf(r.learned.x, r.learned.y, r.learned.z, uintBitsToFloat(r.learned.w)),
      vplkit_discrete_cdf(r.fallback.x, r.fallback.y, r.fallback.z, uintBitsToFloat(r.fallback.w)), r.mix.x, r.mix.y,
      r.mix.z);
}

#ifdef VR_ONE_MIXTURE
vplkit_defensive_mixture vr_mixture0;
void vr_load_mixtures() {
  vr_mixture_record r = vr_mixture_records[0];
  vr_mixture0 = vr_unpack_mixture(r);
}
vplkit_defensive_mixture vr_mixture(uint d) { return vr_mixture0; }
#else
void vr_load_mixtures() {}
vplkit_defensive_mixture vr_mixture(uint d) {
  vr_mixture_record r = vr_mixture_records[d];
  return vr_unpack_mixture(r);
}
#endif

// Component k as the C++ alias_table / flat_face_roulette (the roulette's scalars as uploaded, so
// the GPU picks its face bit for bit).
#if VR_SAMPLER == VR_SAMPLER_ALIAS
vplkit_alias_bin vplkit_load_alias_bin(uint table, uint j) {
  uint b = vr_components[12u * table] + 3u * j;
  return vplkit_alias_bin(uintBitsToFloat(vr_components[b]), uintBitsToFloat(vr_components[b + 1u]),
                          vr_components[b + 2u]);
}
vplkit_alias_table vr_alias(uint k) {
  return vplkit_alias_table(k, vr_components[12u * k + 10u], uintBitsToFloat(vr_components[12u * k + 2u]));
}
vplkit_discrete_sample vr_component_sample(uint k, float u) { return vplkit_alias_table_sample(vr_alias(k), u); }
float vr_component_pmf(uint k, uint i) { return vplkit_alias_table_pmf(vr_alias(k), i); }
#else
vplkit_alias_bin vplkit_load_alias_bin(uint table, uint j) { return vplkit_alias_bin(0.0, 0.0, 0u); }
#endif
#if VR_SAMPLER == VR_SAMPLER_ROULETTE
vplkit_flat_face_roulette vr_roulette(uint k) {
  uint r = 12u * k;
  uint n = vr_components[r + 10u], m = vr_components[r + 11u];
  vplkit_discrete_cdf front = vplkit_discrete_cdf(VR_COMPONENT_SLOT + 2u * k, n, m, uintBitsToFloat(vr_components[r + 2u]));
  vplkit_discrete_cdf back = vplkit_discrete_cdf(VR_COMPONENT_SLOT + 2u * k + 1u, n, m,
                                                 uintBitsToFloat(vr_components[r + 5u]));
  vplkit_face_roulette f = vplkit_face_roulette(front, back, uintBitsToFloat(vr_components[r + 6u]),
                                                uintBitsToFloat(vr_components[r + 7u]),
                                                uintBitsToFloat(vr_components[r + 8u]),
                                                uintBitsToFloat(vr_components[r + 9u]));
  return vplkit_make_flat_face_roulette(f, vr_params.resolution);
}
vplkit_discrete_sample vr_component_sample(uint k, float u) {
  return vplkit_flat_face_roulette_sample(vr_roulette(k), u);
}
float vr_component_pmf(uint k, uint i) { return vplkit_flat_face_roulette_pmf(vr_roulette(k), i); }
#endif

#if VR_SAMPLER == VR_SAMPLER_ALIAS || VR_SAMPLER == VR_SAMPLER_ROULETTE
// The C++ vplkit::defensive_mixture<float, Component> of render/mixture_components.hpp: mixture d
// over components 2d (learned) and 2d + 1 (fallback), with the split of the joint mixture d.
float vr_resampled_pmf(vplkit_defensive_mixture m, uint d, uint i) {
  return vplkit_mixture_split_pmf(vplkit_defensive_mixture_split(m), vr_component_pmf(2u * d, i),
                                  vr_component_pmf(2u * d + 1u, i));
}
vplkit_discrete_sample vr_resampled_sample(uint d, float u) {
  vplkit_defensive_mixture m = vr_mixture(d);
  if (vplkit_defensive_mixture_empty(m)) return vplkit_discrete_sample(0u, 0.0);
  vplkit_mixture_choice c = vplkit_mixture_split_choose(vplkit_defensive_mixture_split(m), u);
  uint i = vr_component_sample(2u * d + c.component, c.u).index;
  return vplkit_discrete_sample(i, vr_resampled_pmf(m, d, i));
}
#endif

#if VR_SAMPLER == VR_SAMPLER_SHARE_TREE
// The pixel's tree stream (C++ share_tree_stream): every draw takes exactly depth = log2(L) of its
// numbers, so draw k starts at k depth, and a dispatch whose first draw is `first_draw` starts
// there (split renders keep no tree state between dispatches).
// Every mixture's tree has the same L leaves (one per texel, padded): tree d's shares start at d L.
// The draws of all the mixtures (local's regions) take numbers from the one stream, in draw order.
vplkit_counter_rng vr_share_tree_rng;
uint vr_share_tree_leaves;
uint vr_share_tree_depth(uint leaves) { return uint(findMSB(leaves)); }  // leaves: a power of two
// After vr_load_mixtures().
void vr_begin_share_tree_stream(vplkit_counter_rng pixel, int first_draw) {
  vr_share_tree_leaves = vr_mixture(0u).learned.guide_size;
  vr_share_tree_rng = vplkit_counter_rng(vplkit_rng_key(pixel.key, VR_SHARE_TREE_STREAM_SALT),
                                         uint(first_draw) * vr_share_tree_depth(vr_share_tree_leaves));
}
uint vplkit_load_share_tree_share(uint tree, uint node) { return vr_shares[tree * vr_share_tree_leaves + node]; }
uint vplkit_share_tree_next_bits(uint tree) { return vplkit_rng_next_u32(vr_share_tree_rng) >> 8u; }
// The learned part of mixture m as its tree (the record's learned fields, estimate_params.h).
vplkit_share_tree vr_share_tree(vplkit_defensive_mixture m) {
  return vplkit_share_tree(m.learned.id, m.learned.size, m.learned.guide_size, m.learned.total);
}
float vr_share_tree_mixture_pmf(vplkit_defensive_mixture m, uint i) {
  return vplkit_mixture_split_pmf(vplkit_defensive_mixture_split(m), vplkit_share_tree_pmf(vr_share_tree(m), i),
                                  vplkit_discrete_cdf_pmf(m.fallback, i));
}
// C++ share_tree_mixture_draw::sample.
vplkit_discrete_sample vr_share_tree_mixture_sample(vplkit_defensive_mixture m, float u) {
  uint depth = vr_share_tree_depth(m.learned.guide_size);
  if (vplkit_defensive_mixture_empty(m)) {
    vr_share_tree_rng.counter += depth;
    return vplkit_discrete_sample(0u, 0.0);
  }
  vplkit_mixture_choice c = vplkit_mixture_split_choose(vplkit_defensive_mixture_split(m), u);
  uint i;
  if (c.component == VPLKIT_MIXTURE_FALLBACK) {
    i = vplkit_discrete_cdf_sample(m.fallback, c.u).index;
    vr_share_tree_rng.counter += depth;
  } else {
    i = vplkit_share_tree_sample(vr_share_tree(m)).index;
  }
  return vplkit_discrete_sample(i, vr_share_tree_mixture_pmf(m, i));
}
#endif

// The estimators' hooks.
vplkit_discrete_sample vplkit_estimator_distribution_sample(uint distribution, float u) {
#if defined(VR_RIS_TILES)
  return vr_tiled_sample(vr_mixture(distribution), u);
#elif VR_SAMPLER == VR_SAMPLER_CDF_GUIDE
  return vplkit_defensive_mixture_sample(vr_mixture(distribution), u);
#elif VR_SAMPLER == VR_SAMPLER_CDF_BINARY
  return vplkit_defensive_mixture_sample_binary_search(vr_mixture(distribution), u);
#elif VR_SAMPLER == VR_SAMPLER_SHARE_TREE
  return vr_share_tree_mixture_sample(vr_mixture(distribution), u);
#else
  return vr_resampled_sample(distribution, u);
#endif
}
float vplkit_estimator_distribution_pmf(uint distribution, uint index) {
#if defined(VR_RIS_TILES)
  return vr_tiled_pmf(vr_mixture(distribution), index);
#elif VR_SAMPLER == VR_SAMPLER_ALIAS || VR_SAMPLER == VR_SAMPLER_ROULETTE
  return vr_resampled_pmf(vr_mixture(distribution), distribution, index);
#elif VR_SAMPLER == VR_SAMPLER_SHARE_TREE
  return vr_share_tree_mixture_pmf(vr_mixture(distribution), index);
#else
  return vplkit_defensive_mixture_pmf(vr_mixture(distribution), index);
#endif
}

#endif  // VPLRENDER_ESTIMATE_DISTRIBUTIONS_GLSL
