// SPDX-License-Identifier: MIT
// The resampled estimators' buffer interface, shared by their kernels (GLSL) and hosts (C++,
// namespace vplkit::gpu): the std430 record that stores one reservoir per pixel between the
// candidate pass and the spatial-reuse pass (32 bytes, every member 4-byte aligned, so std430 and
// C++ agree member for member), and its conversions to and from the reservoir types
// (estimators/ris_reservoir.hpp / .glsl). The CPU renderer keeps its reservoirs in the same
// records. core/params.h explains the two-language form.
#ifndef VPLKIT_ESTIMATORS_RIS_PARAMS_H
#define VPLKIT_ESTIMATORS_RIS_PARAMS_H

#include "vplkit/core/params.h"

#ifdef __cplusplus
#include <vplkit/estimators/ris_reservoir.hpp>

#include <cstddef>
namespace vplkit::gpu {
struct ris_reservoir_record {
#else
#include "vplkit/estimators/ris_reservoir.glsl"
struct vplkit_ris_reservoir_record {
#endif
  int texel;          // the kept texel, -1: none
  float xi_x;         // its patch jitter (0 for point VPLs)
  float xi_y;
  float weight_sum;   // the reservoir's weight_sum, target and confidence
  float target;
  float confidence;
  uint pad0;
  uint pad1;
};
#ifdef __cplusplus
static_assert(sizeof(ris_reservoir_record) == 32);
static_assert(offsetof(ris_reservoir_record, texel) == 0 && offsetof(ris_reservoir_record, xi_x) == 4 &&
              offsetof(ris_reservoir_record, xi_y) == 8 && offsetof(ris_reservoir_record, weight_sum) == 12 &&
              offsetof(ris_reservoir_record, target) == 16 && offsetof(ris_reservoir_record, confidence) == 20);

inline ris_reservoir_record make_ris_reservoir_record(const ris_reservoir<float>& r) {
  return {r.kept.texel, r.kept.xi.x, r.kept.xi.y, r.weight_sum, r.target, r.confidence, 0u, 0u};
}

inline ris_reservoir<float> ris_reservoir_from_record(const ris_reservoir_record& q) {
  ris_reservoir<float> r;
  r.kept.texel = q.texel;
  r.kept.xi = vec2<float>(q.xi_x, q.xi_y);
  r.weight_sum = q.weight_sum;
  r.target = q.target;
  r.confidence = q.confidence;
  return r;
}
}  // namespace vplkit::gpu
#else
vplkit_ris_reservoir_record vplkit_make_ris_reservoir_record(vplkit_ris_reservoir r) {
  return vplkit_ris_reservoir_record(r.kept.texel, r.kept.xi.x, r.kept.xi.y, r.weight_sum, r.target, r.confidence,
                                     0u, 0u);
}

vplkit_ris_reservoir vplkit_ris_reservoir_from_record(vplkit_ris_reservoir_record q) {
  return vplkit_ris_reservoir(vplkit_ris_sample(q.texel, vec2(q.xi_x, q.xi_y)), q.weight_sum, q.target,
                              q.confidence);
}
#endif

#endif  // VPLKIT_ESTIMATORS_RIS_PARAMS_H
