// vplkit kernel: conservative voxelisation of a triangle mesh into the binary voxel grid (the GPU
// side of vplkit::voxelize; grid layout in voxel_grid.glsl). One work group per triangle: the
// group converts the triangle's vertices to continuous voxel coordinates, its invocations share
// the voxel columns of the triangle's bounding box (column k goes to invocation k % LOCAL_SIZE),
// test the voxels with vplkit_triangle_box_overlap (boxes inflated by margin_voxels) and set the
// bits of the overlapping ones with atomicOr. Like the C++ it ORs into the grid: clear the words
// first for a fresh grid.
//
// Interface (no #version: the host prepends "#version 430" (GL) or "#version 450" (Vulkan, plus
// "#extension GL_GOOGLE_include_directive : require"), then its #defines): voxelize_params.h,
// shared with the C++ host -- bindings (VPLKIT_VOXELIZE_BINDING_*: vec4 positions[] (xyz), uint
// indices[3 T], the grid's uint words[] read and written), the local size (work groups
// LOCAL_SIZE x 1 x 1) and the std140 block vplkit_voxelize_params (bounds, resolution, triangle
// count, margin in voxels; the C++ default margin is 1e-4, voxelize_default_margin).
// Dispatch: one work group per triangle, (min(T, 65535), ceil(T / 65535), 1) groups for T
// triangles; triangle = group x + group y * groups x (groups past T return at once).
// The host validates what vplkit::voxelize validates (bounds, resolution, margin in [0, 0.5)); a
// triangle with an index past the end of `positions` or a non-finite vertex is skipped here (the
// C++ throws for the whole mesh instead).
//
// Parity with the C++ voxelize (which converts to voxel coordinates and tests in double): the GPU
// works in float, so a voxel can differ only where the double test is within float rounding of
// flipping, i.e. where the voxel's distance to the triangle is within ~1e-5 voxel of the margin.
// Measured and bounded in tests/parity/parity_visibility_test.cpp; see docs/glsl/visibility.md.
//
// Cost: the triangle normal's dominant axis w is swept per column: for every (u, v) voxel column of
// the bounding box only the w-range where the plane can pass the SAT's normal-axis test (widened
// by one voxel each side for rounding) is tested, so a large tilted triangle costs O(area), not
// O(bounding-box volume). Degenerate triangles, and slivers or far-away vertices for which float
// rounding there could exceed a quarter voxel, fall back to the whole bounding box. The SAT alone
// decides which voxels are marked.
// Why a work group per triangle rather than an invocation: besides spreading a large triangle over
// many lanes, Mesa's llvmpipe stops every loop of an invocation after 65535 iterations in total
// (LP_MAX_TGSI_LOOP_ITERATIONS, shared by all loops), silently. One invocation looping over a
// large triangle's bounding box passes that easily (a 60^3 box already does); shared over 64
// lanes, a column sweep stays far below it, and even the fallback stays below it for bounding
// boxes of up to 64 * 65535 / (longest column + 1) columns (all of a 128^3 grid).
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

void vplkit_voxelize_set(ivec3 resolution, ivec3 c) {
  uint i = vplkit_voxel_flat_index(resolution, c);
  atomicOr(vplkit_voxelize_words[i >> 5u], 1u << (i & 31u));
}

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
      if (vplkit_voxel_test(g, c)) continue;
      if (vplkit_triangle_box_overlap(vec3(c) + vec3(0.5), half_size, v[0], v[1], v[2]))
        vplkit_voxelize_set(res, c);
    }
  }
}
