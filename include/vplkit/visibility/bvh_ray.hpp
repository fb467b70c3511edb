// SPDX-License-Identifier: MIT
#pragma once
// The two geometric tests of BVH traversal, mirrored statement for statement by
// glsl/vplkit/visibility/bvh_ray.glsl:
//  - the watertight ray/triangle test of Woop, Benthin and Wald, "Watertight ray/triangle
//    intersection", JCGT 2(1), 2013;
//  - the slab test against a node's box, made conservative as in Ize, "Robust BVH ray traversal",
//    JCGT 2(2), 2013.
//
// Ray: origin + t * dir, dir of any length (t is in units of |dir|, as in Embree), hits accepted
// for t in (t_min, t_max].
//
// Watertight: the test shears and permutes the ray onto +z once per ray, then evaluates the three
// 2D edge functions of the projected triangle. An edge shared by two triangles has one pair of
// transformed vertices and one edge function value whose sign flips exactly between the two
// triangles (a*b - c*d and c*d - a*b round to exact negatives), so a ray can never pass between two
// triangles that share an edge or a vertex; a ray exactly on the edge hits both (a zero edge
// function counts as inside: triangles are closed). The paper's double-precision re-evaluation
// of zero edge functions is left out: GLSL cannot rely on doubles, and watertightness does not
// need it. Requires that a*b - c*d is not contracted into an FMA (GLSL: `precise`; C++: the
// default on x86-64; with -march=native or on ARM compile with -ffp-contract=off for bit parity).
// Epsilon policy: there is none. Both sides, and both tests, work on the exact float inputs;
// self-intersection at surface points is the caller's business (bvh_visibility.hpp offsets the
// segment ends).
// Range: T (= Tn below) is a cubic expression in the vertex coordinates relative to the origin,
// so with floats it overflows past about 2^42 (4e12) world units and underflows below about
// 2^-42; beyond that a hit may be missed, never invented, and no NaN escapes (a non-finite t is
// no hit).
// Degenerate triangles: repeated vertices give det == 0 exactly (no hit). Exactly collinear but
// distinct vertices can round to a tiny det: a hit is then reported only where the ray passes
// within rounding of the segment the triangle collapses to.
//
// Box test: the slab distances (b - o) * (1 / d) carry at most 3 roundings each, so the exit
// distance is multiplied by bvh_box_expansion >= 1 + 2 gamma(3) (Ize) before the comparison: a
// ray that meets a box in exact arithmetic is never culled by rounding, flat boxes (a wall's
// leaf) included. On an axis with a zero direction component the slab spans all t when the
// origin lies in it (closed) and none otherwise, decided by comparison (no 0 * inf = NaN).
// Direction components below FLT_MIN (1.17549435e-38, for T = double too) count as 0 because
// GPUs flush denormals; a direction that is then zero, or a non-finite origin or direction,
// makes the ray invalid (no hit).
// Huge values: GLSL bounds x / y only for |y| in [2^-126, 2^126] (GLSL 4.60 4.7.1), and NVIDIA
// computes it as x * (1 / y) with 1 / y flushed to 0 when |y| > 2^126. So nothing here divides by
// a value that can exceed 2^126: a direction whose largest |component| is above 2^126 is stored
// scaled by 1/4 (bvh_ray::t_scale = 4: the ray's own parameter is 4 t, and bvh_traverse.hpp scales
// t_min, t_max and the hit's t accordingly), bvh_unit_vector scales its divisor the same way, and
// the triangle test divides by det / 4 when |det| > 2^126. Every such scaling is by a power of two,
// exact unless a value falls below FLT_MIN, and none fires where its divisor is at most 2^126, so
// there the results are the unscaled ones bit for bit.
#include <vplkit/core/normal_range.hpp>
#include <vplkit/core/vector.hpp>

#include <cmath>
#include <cstdint>
#include <limits>

namespace vplkit {

namespace detail {

// std::isfinite, or that of a float-like T found by argument-dependent lookup (the tests' GPU
// model of float arithmetic, tests/support/gpu_model_float.hpp, runs these templates).
template <class T>
inline bool bvh_isfinite(T x) {
  using std::isfinite;
  return isfinite(x);
}

template <class T>
inline bool bvh_vec3_finite(vec3<T> v) {
  return bvh_isfinite(v.x) && bvh_isfinite(v.y) && bvh_isfinite(v.z);
}

// The largest |component| (v finite).
template <class T>
inline T bvh_max_abs(vec3<T> v) {
  const T ax = abs_of(v.x), ay = abs_of(v.y), az = abs_of(v.z);
  const T myz = ay < az ? az : ay;
  return ax < myz ? myz : ax;
}

// 2^126: the largest divisor for which GLSL bounds a division (see the header).
template <class T>
constexpr T bvh_division_limit() {
  return T(8.5070591730234615865843651857942052864e37);
}

// v / |v|, scaled by the largest component first (no overflow or underflow in the dot product);
// 0 when v has a non-finite component or every component is below FLT_MIN (GPUs flush
// denormals). Sums in glm's order, so the GLSL mirror rounds the same way. A largest component
// above 2^126 is scaled by 1/4 first (exact), as in dda_unit_direction: v / m with m > 2^126 is
// 0 * m = NaN on NVIDIA (1 / m flushes to 0, then s / |s| = 0 / 0).
template <class T>
inline vec3<T> bvh_unit_vector(vec3<T> v) {
  if (!bvh_vec3_finite(v)) return vec3<T>(T(0));
  T m = bvh_max_abs(v);
  if (!(m >= T(1.17549435e-38f))) return vec3<T>(T(0));
  if (m > bvh_division_limit<T>()) {
    v = v * T(0.25);
    m = m * T(0.25);
  }
  const vec3<T> s = v / m;
  return s / sqrt_of(s.x * s.x + s.y * s.y + s.z * s.z);
}

}  // namespace detail

// 1 + 2^-20 (8 float ulps at 1): above Ize's 1 + 2 gamma(3) = 1 + 3.6e-7, with room for the
// rounding of the multiplication itself. Exactly representable in float and double.
constexpr double bvh_box_expansion = 1.00000095367431640625;

template <class T>
struct bvh_ray {
  vec3<T> origin;
  vec3<T> dir;      // as given (times 1 / t_scale), with components below FLT_MIN set to 0
  vec3<T> inv_dir;  // 1 / dir per component; 0 where dir is 0 (unused there)
  ivec3 k;          // Woop's axis permutation: k.z = the dominant axis of dir, (k.x, k.y) the others
  vec3<T> shear;    // (dir[k.x] / dir[k.z], dir[k.y] / dir[k.z], 1 / dir[k.z])
  T t_scale;        // 1, or 4 where the given direction was scaled by 1/4 (largest |component| > 2^126)
  bool valid;       // finite origin, finite non-zero dir
};

template <class T>
inline bvh_ray<T> make_bvh_ray(vec3<T> origin, vec3<T> dir) {
  bvh_ray<T> r;
  r.origin = origin;
  r.dir = vec3<T>(T(0));
  r.inv_dir = vec3<T>(T(0));
  r.k = ivec3(0, 1, 2);
  r.shear = vec3<T>(T(0));
  r.t_scale = T(1);
  r.valid = false;
  if (!detail::bvh_vec3_finite(origin) || !detail::bvh_vec3_finite(dir)) return r;
  const T tiny = T(1.17549435e-38f);  // FLT_MIN, for T = double too (parity with the GPU)
  vec3<T> d = dir;
  // 1 / d and d / d[kz] below need |d| <= 2^126 (see the header): origin + t dir is
  // origin + (4 t) (dir / 4).
  if (detail::bvh_max_abs(d) > detail::bvh_division_limit<T>()) {
    d = d * T(0.25);
    r.t_scale = T(4);
  }
  for (int a = 0; a < 3; ++a)
    if (detail::abs_of(d[a]) < tiny) d[a] = T(0);
  const vec3<T> ad(detail::abs_of(d.x), detail::abs_of(d.y), detail::abs_of(d.z));
  const int kz = ad.x >= ad.y ? (ad.x >= ad.z ? 0 : 2) : (ad.y >= ad.z ? 1 : 2);
  if (!(ad[kz] > T(0))) return r;
  int kx = kz + 1 == 3 ? 0 : kz + 1;
  int ky = kx + 1 == 3 ? 0 : kx + 1;
  if (d[kz] < T(0)) {  // keep the winding: a negative dominant axis swaps the other two
    const int s = kx;
    kx = ky;
    ky = s;
  }
  r.dir = d;
  for (int a = 0; a < 3; ++a) r.inv_dir[a] = d[a] != T(0) ? T(1) / d[a] : T(0);
  r.k = ivec3(kx, ky, kz);
  r.shear = vec3<T>(d[kx] / d[kz], d[ky] / d[kz], T(1) / d[kz]);
  r.valid = true;
  return r;
}

// Does the ray meet the closed box [bmin, bmax] for some t in [t_min, t_max] (conservatively)?
// t_entry: where it enters, max(t_min, slab entry). An axis the ray does not move along is a
// plain comparison (the origin inside the closed slab or not), since (b - o) * (1 / 0) would be
// NaN exactly when the origin lies on the slab's plane, a common case (a ray along a wall).
template <class T>
inline bool bvh_ray_box(const bvh_ray<T>& r, vec3<T> bmin, vec3<T> bmax, T t_min, T t_max, T& t_entry) {
  const T big = std::numeric_limits<T>::max();
  vec3<T> t_in(T(0)), t_out(T(0));
  t_entry = t_min;
  for (int a = 0; a < 3; ++a) {
    if (r.dir[a] == T(0)) {
      if (r.origin[a] < bmin[a] || r.origin[a] > bmax[a]) return false;
      t_in[a] = -big;
      t_out[a] = big;
    } else {
      const T t0 = (bmin[a] - r.origin[a]) * r.inv_dir[a];
      const T t1 = (bmax[a] - r.origin[a]) * r.inv_dir[a];
      t_in[a] = t0 < t1 ? t0 : t1;
      t_out[a] = t0 < t1 ? t1 : t0;
    }
  }
  T t_near = t_in.x > t_in.y ? t_in.x : t_in.y;
  t_near = t_in.z > t_near ? t_in.z : t_near;
  t_near = t_min > t_near ? t_min : t_near;
  T t_far = t_out.x < t_out.y ? t_out.x : t_out.y;
  t_far = t_out.z < t_far ? t_out.z : t_far;
  t_far = t_far * T(bvh_box_expansion);  // may overflow to +inf (an axis with dir 0): still right
  t_far = t_max < t_far ? t_max : t_far;
  t_entry = t_near;
  return t_near <= t_far;
}

template <class T>
struct bvh_triangle_hit {
  bool hit;
  T t;  // ray parameter of the hit, in (t_min, t_max]
  T u;  // barycentric weight of v1 (Embree's u): hit point = w v0 + u v1 + v v2
  T v;  // barycentric weight of v2
  T w;  // barycentric weight of v0 (computed as such, not as 1 - u - v)
};

// Woop et al.'s watertight test of the ray against triangle (v0, v1, v2), both windings.
template <class T>
inline bvh_triangle_hit<T> bvh_ray_triangle(const bvh_ray<T>& r, vec3<T> v0, vec3<T> v1, vec3<T> v2, T t_min,
                                            T t_max) {
  bvh_triangle_hit<T> h{false, T(0), T(0), T(0), T(0)};
  const vec3<T> a = v0 - r.origin, b = v1 - r.origin, c = v2 - r.origin;
  const int kx = r.k.x, ky = r.k.y, kz = r.k.z;
  const T ax = a[kx] - r.shear.x * a[kz], ay = a[ky] - r.shear.y * a[kz];
  const T bx = b[kx] - r.shear.x * b[kz], by = b[ky] - r.shear.y * b[kz];
  const T cx = c[kx] - r.shear.x * c[kz], cy = c[ky] - r.shear.y * c[kz];
  const T eu = cx * by - cy * bx;  // edge function of (v1, v2): v0's weight
  const T ev = ax * cy - ay * cx;  // edge function of (v2, v0): v1's weight
  const T ew = bx * ay - by * ax;  // edge function of (v0, v1): v2's weight
  if ((eu < T(0) || ev < T(0) || ew < T(0)) && (eu > T(0) || ev > T(0) || ew > T(0))) return h;
  T det = eu + ev + ew;
  if (det == T(0)) return h;
  const T az = r.shear.z * a[kz], bz = r.shear.z * b[kz], cz = r.shear.z * c[kz];
  T tn = eu * az + ev * bz + ew * cz;
  // Quotients by det need |det| <= 2^126 (see the header); the edge functions share det's sign
  // here, so |eu|, |ev|, |ew| <= |det| and the scaled ones stay finite.
  T su = eu, sv = ev, sw = ew;
  if (detail::abs_of(det) > detail::bvh_division_limit<T>()) {
    det = det * T(0.25);
    tn = tn * T(0.25);
    su = su * T(0.25);
    sv = sv * T(0.25);
    sw = sw * T(0.25);
  }
  const T t = tn / det;
  if (!detail::bvh_isfinite(t) || !(t > t_min) || !(t <= t_max)) return h;
  h.hit = true;
  h.t = t;
  h.u = sv / det;
  h.v = sw / det;
  h.w = su / det;
  return h;
}

}  // namespace vplkit
