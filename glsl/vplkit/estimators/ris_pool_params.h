// SPDX-License-Identifier: MIT
// The presampled candidates' buffer interface (docs/math.md, "Presampled candidates"), shared by
// the kernels (GLSL) and hosts (C++, namespace vplkit::gpu) of ris-mis's candidate pool: the std430
// record of one pool entry (64 bytes, every member a 4-byte scalar, so std430 and C++ agree member
// for member without padding rules), and its conversions to and from the entry types
// (estimators/ris_candidate_pool.hpp, estimators/ris_pool_entry.glsl). The fill pass writes one
// record per entry, the estimate pass reads them through the host's vplkit_load_ris_pool_entry
// (ris_candidate_pool.glsl); the CPU renderer keeps the same layout. core/params.h explains the
// two-language form.
#ifndef VPLKIT_ESTIMATORS_RIS_POOL_PARAMS_H
#define VPLKIT_ESTIMATORS_RIS_POOL_PARAMS_H

#include "vplkit/core/params.h"

#ifdef __cplusplus
#include <vplkit/estimators/ris_candidate_pool.hpp>

#include <cstddef>
namespace vplkit::gpu {
struct ris_pool_record {
#else
#include "vplkit/estimators/ris_pool_entry.glsl"
struct vplkit_ris_pool_record {
#endif
  float position_x;  // y
  float position_y;
  float position_z;
  float pmf;         // 0: an empty entry
  float normal_x;    // unit n_t
  float normal_y;
  float normal_z;
  float area;        // the A of p2
  float radiance_x;  // L_o(y)
  float radiance_y;
  float radiance_z;
  int texel;         // -1: the draw was empty
  float xi_x;        // the patch jitter (0 for point VPLs)
  float xi_y;
  int at_centre;     // 1: the patch moved the point to the texel centre
  int pad;
};
#ifdef __cplusplus
static_assert(sizeof(ris_pool_record) == 64);
static_assert(offsetof(ris_pool_record, position_x) == 0 && offsetof(ris_pool_record, pmf) == 12 &&
              offsetof(ris_pool_record, normal_x) == 16 && offsetof(ris_pool_record, area) == 28 &&
              offsetof(ris_pool_record, radiance_x) == 32 && offsetof(ris_pool_record, texel) == 44 &&
              offsetof(ris_pool_record, xi_x) == 48 && offsetof(ris_pool_record, xi_y) == 52 &&
              offsetof(ris_pool_record, at_centre) == 56 && offsetof(ris_pool_record, pad) == 60);

inline ris_pool_record make_ris_pool_record(const ris_pool_entry<float>& e) {
  return {e.position.x, e.position.y, e.position.z, e.pmf,        e.normal.x,   e.normal.y,
          e.normal.z,   e.area,       e.radiance.x, e.radiance.y, e.radiance.z, e.texel,
          e.xi.x,       e.xi.y,       e.at_centre,  0};
}

inline ris_pool_entry<float> ris_pool_entry_from_record(const ris_pool_record& q) {
  ris_pool_entry<float> e;
  e.position = vec3<float>(q.position_x, q.position_y, q.position_z);
  e.pmf = q.pmf;
  e.normal = vec3<float>(q.normal_x, q.normal_y, q.normal_z);
  e.area = q.area;
  e.radiance = vec3<float>(q.radiance_x, q.radiance_y, q.radiance_z);
  e.texel = q.texel;
  e.xi = vec2<float>(q.xi_x, q.xi_y);
  e.at_centre = q.at_centre;
  return e;
}
}  // namespace vplkit::gpu
#else
vplkit_ris_pool_record vplkit_make_ris_pool_record(vplkit_ris_pool_entry e) {
  return vplkit_ris_pool_record(e.position.x, e.position.y, e.position.z, e.pmf, e.normal.x, e.normal.y, e.normal.z,
                                e.area, e.radiance.x, e.radiance.y, e.radiance.z, e.texel, e.xi.x, e.xi.y,
                                e.at_centre, 0);
}

vplkit_ris_pool_entry vplkit_ris_pool_entry_from_record(vplkit_ris_pool_record q) {
  return vplkit_ris_pool_entry(vec3(q.position_x, q.position_y, q.position_z), q.pmf,
                               vec3(q.normal_x, q.normal_y, q.normal_z), q.area,
                               vec3(q.radiance_x, q.radiance_y, q.radiance_z), q.texel, vec2(q.xi_x, q.xi_y),
                               q.at_centre, 0);
}
#endif

#endif  // VPLKIT_ESTIMATORS_RIS_POOL_PARAMS_H
