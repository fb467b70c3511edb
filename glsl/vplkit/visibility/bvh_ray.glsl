// SPDX-License-Identifier: MIT
// vplkit GLSL pack: the two geometric tests of BVH traversal (mirrors
// include/vplkit/visibility/bvh_ray.hpp, T = float, statement for statement):
//  - Woop, Benthin and Wald's watertight ray/triangle test (JCGT 2013), both windings, closed
//    triangles (a ray exactly on a shared edge hits both; none passes between them);
//  - the slab test against a box, its exit distance scaled by vplkit_bvh_box_expansion
//    (>= 1 + 2 gamma(3), Ize 2013) so that rounding never culls a box the ray meets.
// Ray: origin + t * dir (dir any length, t in units of |dir|); hits for t in (t_min, t_max].
// No epsilon anywhere; direction components below FLT_MIN count as 0; a non-finite or zero
// direction or a non-finite origin makes the ray invalid. A non-finite t is no hit, so overflow
// (coordinates beyond about 2^42 from the origin: t is cubic in them) loses hits, never invents
// them. See docs/api/bvh.md for the argument.
// Huge values: GLSL bounds x / y only for |y| in [2^-126, 2^126], and NVIDIA divides as
// x * (1 / y) with 1 / y flushed to 0 above 2^126; so, as in the C++, a direction whose largest
// |component| exceeds 2^126 is stored scaled by 1/4 (t_scale = 4: the ray's parameter is 4 t),
// vplkit_bvh_unit_vector scales its divisor alike and the triangle test divides by det / 4 when
// |det| > 2^126. Powers of two: exact, and none fires where the divisor is at most 2^126.
//
// Parity: every value is `precise` and written in the C++ order (no FMA contraction, which
// would break both watertightness and parity). With correctly rounded division (llvmpipe) the
// results are the C++ float results bit for bit.
//
// No accessor.
#ifndef VPLKIT_VISIBILITY_BVH_RAY_GLSL
#define VPLKIT_VISIBILITY_BVH_RAY_GLSL

#include "vplkit/core/constants.glsl"
#include "vplkit/core/normal_range.glsl"

// 1 + 2^-20 (the C++ bvh_box_expansion).
const float vplkit_bvh_box_expansion = 1.00000095367431640625;

struct vplkit_bvh_ray {
  vec3 origin;
  vec3 dir;      // as given (times 1 / t_scale), with components below FLT_MIN set to 0
  vec3 inv_dir;  // 1 / dir per component; 0 where dir is 0 (unused there)
  ivec3 k;       // Woop's permutation: k.z = the dominant axis of dir
  vec3 shear;    // (dir[k.x] / dir[k.z], dir[k.y] / dir[k.z], 1 / dir[k.z])
  float t_scale; // 1, or 4 where the given direction was scaled by 1/4 (largest |component| > 2^126)
  bool valid;    // finite origin, finite non-zero dir
};

struct vplkit_bvh_triangle_hit {
  bool hit;
  float t;  // in (t_min, t_max]
  float u;  // barycentric weight of v1 (Embree's u)
  float v;  // barycentric weight of v2
  float w;  // barycentric weight of v0
};

// Finite test on the bits: immune to drivers that assume no NaN / Inf under fast math.
bool vplkit_bvh_isfinite(float x) { return vplkit_is_finite(x); }

bool vplkit_bvh_vec3_finite(vec3 v) {
  return vplkit_bvh_isfinite(v.x) && vplkit_bvh_isfinite(v.y) && vplkit_bvh_isfinite(v.z);
}

// 2^126 (the C++ detail::bvh_division_limit).
const float vplkit_bvh_division_limit = 8.5070591730234615865843651857942052864e37;

// The largest |component| (the C++ detail::bvh_max_abs).
float vplkit_bvh_max_abs(vec3 v) {
  float ax = abs(v.x);
  float ay = abs(v.y);
  float az = abs(v.z);
  float myz = ay < az ? az : ay;
  return ax < myz ? myz : ax;
}

// v / |v| after scaling by the largest component (itself scaled by 1/4 above 2^126); 0 for a
// non-finite v or one below FLT_MIN.
vec3 vplkit_bvh_unit_vector(vec3 v) {
  if (!vplkit_bvh_vec3_finite(v)) return vec3(0.0);
  precise float m = vplkit_bvh_max_abs(v);
  if (!(m >= vplkit_FLT_MIN)) return vec3(0.0);
  precise vec3 vs = v;
  if (m > vplkit_bvh_division_limit) {
    vs = vs * 0.25;
    m = m * 0.25;
  }
  precise vec3 s = vs / m;
  precise float len = sqrt(s.x * s.x + s.y * s.y + s.z * s.z);
  precise vec3 u = s / len;
  return u;
}

vplkit_bvh_ray vplkit_make_bvh_ray(vec3 origin, vec3 dir) {
  vplkit_bvh_ray r = vplkit_bvh_ray(origin, vec3(0.0), vec3(0.0), ivec3(0, 1, 2), vec3(0.0), 1.0, false);
  if (!vplkit_bvh_vec3_finite(origin) || !vplkit_bvh_vec3_finite(dir)) return r;
  precise vec3 d = dir;
  // 1 / d and d / d[kz] need |d| <= 2^126: origin + t dir is origin + (4 t) (dir / 4).
  if (vplkit_bvh_max_abs(d) > vplkit_bvh_division_limit) {
    d = d * 0.25;
    r.t_scale = 4.0;
  }
  for (int a = 0; a < 3; ++a)
    if (abs(d[a]) < vplkit_FLT_MIN) d[a] = 0.0;
  vec3 ad = vec3(abs(d.x), abs(d.y), abs(d.z));
  int kz = ad.x >= ad.y ? (ad.x >= ad.z ? 0 : 2) : (ad.y >= ad.z ? 1 : 2);
  if (!(ad[kz] > 0.0)) return r;
  int kx = kz + 1 == 3 ? 0 : kz + 1;
  int ky = kx + 1 == 3 ? 0 : kx + 1;
  if (d[kz] < 0.0) {  // keep the winding: a negative dominant axis swaps the other two
    int s = kx;
    kx = ky;
    ky = s;
  }
  r.dir = d;
  for (int a = 0; a < 3; ++a) {
    precise float inv = 1.0 / d[a];
    r.inv_dir[a] = d[a] != 0.0 ? inv : 0.0;
  }
  r.k = ivec3(kx, ky, kz);
  precise vec3 shear = vec3(d[kx] / d[kz], d[ky] / d[kz], 1.0 / d[kz]);
  r.shear = shear;
  r.valid = true;
  return r;
}

// Does the ray meet the closed box [bmin, bmax] for some t in [t_min, t_max] (conservatively)?
// t_entry: where it enters, max(t_min, slab entry). An axis the ray does not move along is a plain
// comparison (origin inside the closed slab or not).
bool vplkit_bvh_ray_box(vplkit_bvh_ray r, vec3 bmin, vec3 bmax, float t_min, float t_max, out float t_entry) {
  const float big = vplkit_FLT_MAX;
  vec3 t_in = vec3(0.0);
  vec3 t_out = vec3(0.0);
  t_entry = t_min;
  for (int a = 0; a < 3; ++a) {
    if (r.dir[a] == 0.0) {
      if (r.origin[a] < bmin[a] || r.origin[a] > bmax[a]) return false;
      t_in[a] = -big;
      t_out[a] = big;
    } else {
      precise float t0 = (bmin[a] - r.origin[a]) * r.inv_dir[a];
      precise float t1 = (bmax[a] - r.origin[a]) * r.inv_dir[a];
      t_in[a] = t0 < t1 ? t0 : t1;
      t_out[a] = t0 < t1 ? t1 : t0;
    }
  }
  float t_near = t_in.x > t_in.y ? t_in.x : t_in.y;
  t_near = t_in.z > t_near ? t_in.z : t_near;
  t_near = t_min > t_near ? t_min : t_near;
  float t_far = t_out.x < t_out.y ? t_out.x : t_out.y;
  t_far = t_out.z < t_far ? t_out.z : t_far;
  precise float t_far_expanded = t_far * vplkit_bvh_box_expansion;  // may overflow to +inf: still right
  t_far = t_max < t_far_expanded ? t_max : t_far_expanded;
  t_entry = t_near;
  return t_near <= t_far;
}

// Woop et al.'s watertight test of the ray against triangle (v0, v1, v2), both windings.
vplkit_bvh_triangle_hit vplkit_bvh_ray_triangle(vplkit_bvh_ray r, vec3 v0, vec3 v1, vec3 v2, float t_min,
                                                float t_max) {
  vplkit_bvh_triangle_hit h = vplkit_bvh_triangle_hit(false, 0.0, 0.0, 0.0, 0.0);
  precise vec3 a = v0 - r.origin;
  precise vec3 b = v1 - r.origin;
  precise vec3 c = v2 - r.origin;
  int kx = r.k.x;
  int ky = r.k.y;
  int kz = r.k.z;
  precise float ax = a[kx] - r.shear.x * a[kz];
  precise float ay = a[ky] - r.shear.y * a[kz];
  precise float bx = b[kx] - r.shear.x * b[kz];
  precise float by = b[ky] - r.shear.y * b[kz];
  precise float cx = c[kx] - r.shear.x * c[kz];
  precise float cy = c[ky] - r.shear.y * c[kz];
  precise float eu = cx * by - cy * bx;  // edge function of (v1, v2): v0's weight
  precise float ev = ax * cy - ay * cx;  // edge function of (v2, v0): v1's weight
  precise float ew = bx * ay - by * ax;  // edge function of (v0, v1): v2's weight
  if ((eu < 0.0 || ev < 0.0 || ew < 0.0) && (eu > 0.0 || ev > 0.0 || ew > 0.0)) return h;
  precise float det = eu + ev + ew;
  if (det == 0.0) return h;
  precise float az = r.shear.z * a[kz];
  precise float bz = r.shear.z * b[kz];
  precise float cz = r.shear.z * c[kz];
  precise float tn = eu * az + ev * bz + ew * cz;
  // Quotients by det need |det| <= 2^126; the edge functions share det's sign here, so the
  // scaled ones stay finite.
  precise float su = eu;
  precise float sv = ev;
  precise float sw = ew;
  if (abs(det) > vplkit_bvh_division_limit) {
    det = det * 0.25;
    tn = tn * 0.25;
    su = su * 0.25;
    sv = sv * 0.25;
    sw = sw * 0.25;
  }
  precise float t = tn / det;
  if (!vplkit_bvh_isfinite(t) || !(t > t_min) || !(t <= t_max)) return h;
  h.hit = true;
  h.t = t;
  precise float u = sv / det;
  precise float v = sw / det;
  precise float w = su / det;
  h.u = u;
  h.v = v;
  h.w = w;
  return h;
}

#endif  // VPLKIT_VISIBILITY_BVH_RAY_GLSL
