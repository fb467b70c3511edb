// SPDX-License-Identifier: MIT
// vplkit kernel: conservative voxelisation of a triangle mesh into the binary voxel grid, the GPU
// side of vplkit::voxelize (grid layout in voxel_grid.glsl). One work group per triangle: its
// invocations share the voxel columns of the triangle's bounding box, sweep only the part of each
// column the triangle's plane can reach, test the voxels with vplkit_triangle_box_overlap (boxes
// inflated by margin_voxels) and atomicOr the overlapping ones into the grid (clear it first for
// a fresh grid). Interface: voxelize_params.h, shared with the C++ host. Dispatch:
// (min(T, 65535), ceil(T / 65535), 1) groups for T triangles. The host validates what voxelize
// validates; a triangle with an index past the positions or a non-finite vertex is skipped (the
// C++ throws). A voxel differs from the C++ (double) only within ~1e-5 voxel of the margin. Cost,
// the work-group layout and why: docs/glsl/visibility.md, "voxelize.comp".
//
// MODES (VPLKIT_VOXELIZE_MODE, voxelize_params.h): the same sweep and overlap test also build the
// triangle voxel grid's lists (C++ voxelize_triangles), after the occupancy and its rank
// (prefix_sum.comp, bit-count mode): 0 occupancy (atomicOr, the default); 1 count (atomicAdd 1 to
// counts[r] of every overlapping voxel, r its occupied index; offsets are then the exclusive prefix
// sum of counts); 2 fill (entries[offsets[r] + atomicAdd(cursor[r], 1)] = t). Modes 1 and 2 visit
// every overlapping voxel and only read the words: every voxel a triangle overlaps is occupied, so
// r is always valid. A voxel's entries come in the atomics' order; no query depends on it.
#include "vplkit/visibility/triangle_box_overlap.glsl"
#include "vplkit/visibility/voxel_grid.glsl"
#include "vplkit/visibility/voxelize_params.h"

layout(local_size_x = VPLKIT_VOXELIZE_LOCAL_SIZE, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = VPLKIT_VOXELIZE_BINDING_POSITIONS) readonly buffer vplkit_voxelize_positions_buffer {
  vec4 vplkit_voxelize_positions[];
};
layout(std430, binding = VPLKIT_VOXELIZE_BINDING_INDICES) readonly buffer vplkit_voxelize_indices_buffer {
  uint vplkit_voxelize_indices[];
};
layout(std430, binding = VPLKIT_VOXELIZE_BINDING_WORDS) buffer vplkit_voxelize_words_buffer {
  uint vplkit_voxelize_words[];
};
layout(std140, binding = VPLKIT_VOXELIZE_BINDING_PARAMS) uniform vplkit_voxelize_uniforms {
  vplkit_voxelize_params vplkit_voxelize;
};

uint vplkit_load_voxel_word(uint word_index) {
  return vplkit_voxelize_words[word_index];
}

#if VPLKIT_VOXELIZE_MODE == 0
void vplkit_voxelize_set(ivec3 resolution, ivec3 c) {
  uint i = vplkit_voxel_flat_index(resolution, c);
  atomicOr(vplkit_voxelize_words[i >> 5u], 1u << (i & 31u));
}
#else
#include "vplkit/visibility/voxel_rank.glsl"

layout(std430, binding = VPLKIT_VOXELIZE_BINDING_RANK) readonly buffer vplkit_voxelize_rank_buffer {
  uint vplkit_voxelize_rank[];
};
layout(std430, binding = VPLKIT_VOXELIZE_BINDING_COUNTS) buffer vplkit_voxelize_counts_buffer {
  uint vplkit_voxelize_counts[];
};
uint vplkit_load_voxel_rank(uint word_index) {
  return vplkit_voxelize_rank[word_index];
}
#if VPLKIT_VOXELIZE_MODE == 2
layout(std430, binding = VPLKIT_VOXELIZE_BINDING_OFFSETS) readonly buffer vplkit_voxelize_offsets_buffer {
  uint vplkit_voxelize_offsets[];
};
layout(std430, binding = VPLKIT_VOXELIZE_BINDING_ENTRIES) writeonly buffer vplkit_voxelize_entries_buffer {
  uint vplkit_voxelize_entries[];
};
#endif

// Mode 1 counts triangle t in voxel c's list; mode 2 writes it there.
void vplkit_voxelize_list(vplkit_voxel_grid g, ivec3 c, uint t) {
  int r = vplkit_voxel_occupied_index(g, c);
  if (r < 0) return;  // cannot happen: mode 0 marked every voxel this test passes
#if VPLKIT_VOXELIZE_MODE == 1
  atomicAdd(vplkit_voxelize_counts[r], 1u);
#else
  uint slot = atomicAdd(vplkit_voxelize_counts[r], 1u);
  vplkit_voxelize_entries[vplkit_voxelize_offsets[r] + slot] = t;
#endif
}
#endif

void main() {
  uint t = gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x;
  if (t >= vplkit_voxelize.triangle_count) return;
  uint lane = gl_LocalInvocationIndex;
  vplkit_voxel_grid g = vplkit_voxel_grid(vplkit_voxelize.bounds_min.xyz, vplkit_voxelize.bounds_max.xyz,
                                          vplkit_voxelize.resolution.xyz);
  ivec3 res = g.resolution;
  float margin = vplkit_voxelize.margin_voxels;

  // Vertices in continuous voxel coordinates (the grid's own convention, as the C++ but in float).
  vec3 v[3];
  uint vertex_count = uint(vplkit_voxelize_positions.length());
  for (uint k = 0u; k < 3u; ++k) {
    uint index = vplkit_voxelize_indices[3u * t + k];
    if (index >= vertex_count) return;
    vec3 p = vplkit_voxelize_positions[index].xyz;
    if (!vplkit_voxel_vec3_finite(p)) return;
    v[k] = vplkit_world_to_voxel_coord(g, p);
  }
  vec3 half_size = vec3(0.5 + margin);

  // Voxel i (closed [i, i+1], inflated by the margin) can touch [lo, hi] only if
  // i - margin <= hi and i + 1 + margin >= lo.
  ivec3 first;
  ivec3 last;
  float largest = 0.0;
  for (int a = 0; a < 3; ++a) {
    float lo = min(v[0][a], min(v[1][a], v[2][a]));
    float hi = max(v[0][a], max(v[1][a], v[2][a]));
    precise float f_lo = ceil(lo - margin) - 1.0;
    precise float f_hi = hi + margin;
    int f = vplkit_voxel_floor_to_int(f_lo);
    int l = vplkit_voxel_floor_to_int(f_hi);
    first[a] = f < 0 ? 0 : f;
    last[a] = l > res[a] - 1 ? res[a] - 1 : l;
    if (first[a] > last[a]) return;
    largest = max(largest, max(abs(lo), abs(hi)));
  }

  // Sweep axis w: the dominant axis of the normal; u, v the other two.
  vec3 n = vplkit_sat_cross(v[1] - v[0], v[2] - v[1]);
  vec3 an = abs(n);
  int w = an.x >= an.y ? (an.x >= an.z ? 0 : 2) : (an.y >= an.z ? 1 : 2);
  int u = w == 0 ? 1 : 0;
  int vv = w == 2 ? 1 : 2;
  float nw = n[w];
  float n1 = an.x + an.y + an.z;
  // Rounding of the per-column w-range below, in voxels, bounded generously: the SAT's own normal
  // (from edges relative to each box centre) differs from n by up to ~6 * 2^-22 * M * emax, where
  // M bounds every coordinate involved and emax the edge components; evaluating dd adds a few ulp
  // of n1 * M; both are divided by |nw|. Columns are used only while this stays below a quarter of
  // the one-voxel widening (slivers and far-away vertices fall back to the whole bounding box).
  vec3 e_abs = max(abs(v[1] - v[0]), max(abs(v[2] - v[1]), abs(v[0] - v[2])));
  float emax = max(e_abs.x, max(e_abs.y, e_abs.z));
  float big_m = largest + float(res.x + res.y + res.z) + 2.0;
  float column_error = (1.5e-6 * big_m * emax * big_m + 2.5e-7 * n1 * big_m) / abs(nw);
  bool columns = vplkit_voxel_vec3_finite(n) && nw != 0.0 && column_error < 0.25;
  precise float r = (0.5 + margin) * n1;
  precise float d0 = n.x * v[0].x + n.y * v[0].y + n.z * v[0].z;

  // Columns of the bounding box, shared among the group's invocations.
  uint columns_u = uint(last[u] - first[u] + 1);
  uint column_count = columns_u * uint(last[vv] - first[vv] + 1);
  for (uint k = lane; k < column_count; k += uint(VPLKIT_VOXELIZE_LOCAL_SIZE)) {
    int iu = first[u] + int(k % columns_u);
    int iv = first[vv] + int(k / columns_u);
    int w_first = first[w];
    int w_last = last[w];
    if (columns) {
      // Exact arithmetic: the normal axis passes iff |n . (centre - v0)| <= r, i.e.
      // nw * (iw + 0.5) in [dd - r, dd + r] with dd = n . v0 - nu * (iu + 0.5) - nv * (iv + 0.5).
      precise float dd = d0 - n[u] * (float(iu) + 0.5) - n[vv] * (float(iv) + 0.5);
      precise float c0 = (dd - r) / nw - 0.5;
      precise float c1 = (dd + r) / nw - 0.5;
      float c_lo = min(c0, c1);
      float c_hi = max(c0, c1);
      int a0 = vplkit_voxel_floor_to_int(ceil(c_lo)) - 1;
      int a1 = vplkit_voxel_floor_to_int(c_hi) + 1;
      w_first = max(w_first, a0);
      w_last = min(w_last, a1);
    }
    for (int iw = w_first; iw <= w_last; ++iw) {
      ivec3 c;
      c[u] = iu;
      c[vv] = iv;
      c[w] = iw;
#if VPLKIT_VOXELIZE_MODE == 0
      if (vplkit_voxel_test(g, c)) continue;
      if (vplkit_triangle_box_overlap(vec3(c) + vec3(0.5), half_size, v[0], v[1], v[2]))
        vplkit_voxelize_set(res, c);
#else
      if (vplkit_triangle_box_overlap(vec3(c) + vec3(0.5), half_size, v[0], v[1], v[2]))
        vplkit_voxelize_list(g, c, t);
#endif
    }
  }
}
