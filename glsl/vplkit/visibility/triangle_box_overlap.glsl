// SPDX-License-Identifier: MIT
// vplkit GLSL pack: triangle / axis-aligned box overlap by the separating axis theorem
// (Akenine-Moeller 2001; mirrors include/vplkit/visibility/triangle_box_overlap.hpp, T = float).
//
// 13 axes: the 3 box normals (the triangle's bounding box against the box), the triangle normal and
// the 9 cross products box axis x triangle edge. Closed sets: touching counts as overlap; an axis
// separates only if the projections are STRICTLY apart. Degenerate triangles need no special code
// (a zero axis cannot separate; what remains is the complete axis set of the segment or point).
// Every axis projects all three vertices, so rounding leans towards "overlap". Non-finite input
// gives true; validate before calling.
//
// Bit-for-bit parity: the test uses only +, -, *, abs and comparisons. The dot and cross products
// are written out in glm's order and `precise` (no FMA contraction, no reordering), so on any
// implementation with IEEE float add/mul the answer equals the C++ float answer exactly (denormal
// flushing aside, which only matters for coordinates below 1e-38).
//
// No accessor.
#ifndef VPLKIT_VISIBILITY_TRIANGLE_BOX_OVERLAP_GLSL
#define VPLKIT_VISIBILITY_TRIANGLE_BOX_OVERLAP_GLSL

// glm::cross, unfused.
vec3 vplkit_sat_cross(vec3 x, vec3 y) {
  precise vec3 r = vec3(x.y * y.z - y.y * x.z, x.z * y.x - y.z * x.x, x.x * y.y - y.x * x.y);
  return r;
}

// Does `axis` separate the triangle (vertices relative to the box centre) from the box of half
// size h? Projections of the box: [-r, r], r = sum_i h_i |axis_i|.
bool vplkit_sat_axis_separates(vec3 axis, vec3 v0, vec3 v1, vec3 v2, vec3 h) {
  precise float p0 = axis.x * v0.x + axis.y * v0.y + axis.z * v0.z;
  precise float p1 = axis.x * v1.x + axis.y * v1.y + axis.z * v1.z;
  precise float p2 = axis.x * v2.x + axis.y * v2.y + axis.z * v2.z;
  float lo = p0 < p1 ? (p0 < p2 ? p0 : p2) : (p1 < p2 ? p1 : p2);
  float hi = p0 > p1 ? (p0 > p2 ? p0 : p2) : (p1 > p2 ? p1 : p2);
  precise float r = h.x * abs(axis.x) + h.y * abs(axis.y) + h.z * abs(axis.z);
  return lo > r || hi < -r;
}

// Does triangle (a, b, c) overlap the closed box centred at box_center with half extents
// box_half (each >= 0)?
bool vplkit_triangle_box_overlap(vec3 box_center, vec3 box_half, vec3 a, vec3 b, vec3 c) {
  // Work relative to the box centre: smaller magnitudes, smaller rounding.
  precise vec3 v0 = a - box_center;
  precise vec3 v1 = b - box_center;
  precise vec3 v2 = c - box_center;
  vec3 h = box_half;

  // 1. Box normals: the triangle's bounding box against the box (cheapest, rejects most).
  for (int i = 0; i < 3; ++i) {
    float lo = v0[i] < v1[i] ? (v0[i] < v2[i] ? v0[i] : v2[i]) : (v1[i] < v2[i] ? v1[i] : v2[i]);
    float hi = v0[i] > v1[i] ? (v0[i] > v2[i] ? v0[i] : v2[i]) : (v1[i] > v2[i] ? v1[i] : v2[i]);
    if (lo > h[i] || hi < -h[i]) return false;
  }

  precise vec3 e0 = v1 - v0;
  precise vec3 e1 = v2 - v1;
  precise vec3 e2 = v0 - v2;

  // 2. Triangle normal (zero for a degenerate triangle: then it cannot separate).
  if (vplkit_sat_axis_separates(vplkit_sat_cross(e0, e1), v0, v1, v2, h)) return false;

  // 3. Box axis x edge, 9 axes: unit_x x e = (0, -e.z, e.y), unit_y x e = (e.z, 0, -e.x),
  //    unit_z x e = (-e.y, e.x, 0).
  vec3 edges[3] = vec3[3](e0, e1, e2);
  for (int k = 0; k < 3; ++k) {
    vec3 e = edges[k];
    if (vplkit_sat_axis_separates(vec3(0.0, -e.z, e.y), v0, v1, v2, h)) return false;
    if (vplkit_sat_axis_separates(vec3(e.z, 0.0, -e.x), v0, v1, v2, h)) return false;
    if (vplkit_sat_axis_separates(vec3(-e.y, e.x, 0.0), v0, v1, v2, h)) return false;
  }
  return true;
}

#endif  // VPLKIT_VISIBILITY_TRIANGLE_BOX_OVERLAP_GLSL
