// SPDX-License-Identifier: MIT
// vplkit GLSL pack: unbiased spatial reuse of RIS reservoirs (docs/math.md section 13.2): a pixel
// combines its own reservoir with those of up to K neighbours picked in a square around it and
// rejected on normal and plane distance, by generalized RIS with pairwise (default) or balance MIS
// weights over the confidences; mirrors include/vplkit/estimators/ris_spatial_reuse.hpp (T =
// float), random numbers included: the canonical's selection u, then per attempt u0, u1 (the
// neighbour) and its selection u.
// Where C++ takes a load(pixel) callable, the shader defines two accessors (a kernel reads them
// from the previous pass's buffers):
//   vplkit_gather_point vplkit_load_gather_point(int pixel);   (core/gather_point.glsl)
//   vplkit_ris_reservoir vplkit_load_ris_reservoir(int pixel); (e.g. vplkit_ris_reservoir_from_record
//                                                               of a ris_params.h record)
// The target is a vplkit_ris_reuse_target (C++: a callable): ris's ris_target, or, with
// VPLKIT_RIS_MIS_REUSE defined (ris_mis_spatial_reuse.glsl does), ris-mis's MIS-weighted target,
// which reads the distribution hooks of mis_estimator.glsl and the accessor
//   uint vplkit_ris_reuse_distribution(int pixel);             (the pixel's candidate distribution)
// Neighbours are passed as pixel indices and loaded where needed, so a kernel holds K ints, not K
// reservoirs and gather points (registers; VPLKIT_RIS_MAX_NEIGHBOURS may be lowered by a #define
// before the include).
#ifndef VPLKIT_ESTIMATORS_RIS_SPATIAL_REUSE_GLSL
#define VPLKIT_ESTIMATORS_RIS_SPATIAL_REUSE_GLSL

#include "vplkit/core/gather_point.glsl"
#include "vplkit/core/unit_or_zero.glsl"
#include "vplkit/distribution/weighted_reservoir.glsl"
#include "vplkit/estimators/ris_estimator.glsl"
#include "vplkit/estimators/ris_reservoir.glsl"
#include "vplkit/mis/heuristics.glsl"
#include "vplkit/sampling/rng.glsl"
#include "vplkit/vpl/dprsm_view.glsl"
#ifdef VPLKIT_RIS_MIS_REUSE
// No conditional #include (include_resolver.hpp inlines every file once, #if or not):
// ris_mis_spatial_reuse.glsl includes ris_mis_estimator.glsl before this file.
#ifndef VPLKIT_ESTIMATORS_RIS_MIS_ESTIMATOR_GLSL
#error "VPLKIT_RIS_MIS_REUSE: include vplkit/estimators/ris_mis_spatial_reuse.glsl instead of ris_spatial_reuse.glsl"
#endif
#endif

#ifndef VPLKIT_RIS_MAX_NEIGHBOURS
#define VPLKIT_RIS_MAX_NEIGHBOURS 16  // C++ ris_max_neighbours
#endif

const int vplkit_ris_reuse_pairwise = 0;
const int vplkit_ris_reuse_balance = 1;

vplkit_ris_reservoir vplkit_load_ris_reservoir(int pixel);

// C++ ris_spatial_settings<float>.
struct vplkit_ris_spatial_settings {
  int neighbours;          // K attempts
  int radius;              // pixels
  float min_normal_cos;
  float max_plane_slope;
  int mis;                 // vplkit_ris_reuse_pairwise or _balance
};

vplkit_ris_spatial_settings vplkit_make_ris_spatial_settings() {
  return vplkit_ris_spatial_settings(4, 16, 0.9, 0.1, vplkit_ris_reuse_pairwise);
}

// The neighbour (u0, u1) picks in the (2 radius + 1)^2 square around `pixel`; -1 for the pixel
// itself, outside the image, radius <= 0. One correctly rounded product and a floor per axis.
int vplkit_ris_neighbour_pixel(int pixel, int width, int height, int radius, float u0, float u1) {
  if (radius <= 0 || width <= 0 || height <= 0 || pixel < 0 || pixel >= width * height) return -1;
  int side = 2 * radius + 1;
  precise float s0 = !(u0 >= 0.0) ? 0.0 : u0 * float(side);
  precise float s1 = !(u1 >= 0.0) ? 0.0 : u1 * float(side);
  int dx = (s0 < float(side) ? int(floor(s0)) : side - 1) - radius;
  int dy = (s1 < float(side) ? int(floor(s1)) : side - 1) - radius;
  int x = pixel % width + dx;
  int y = pixel / width + dy;
  if ((dx == 0 && dy == 0) || x < 0 || y < 0 || x >= width || y >= height) return -1;
  return y * width + x;
}

// Both valid, geometric normals within acos(min_normal_cos), the neighbour within max_plane_slope
// of the receiver's tangent plane (relative to their distance).
bool vplkit_ris_neighbour_similar(vplkit_gather_point receiver, vplkit_gather_point neighbour, float min_normal_cos,
                                  float max_plane_slope) {
  if (!vplkit_gather_point_valid(receiver) || !vplkit_gather_point_valid(neighbour)) return false;
  vec3 nq = vplkit_unit_or_zero(receiver.normal);
  vec3 nj = vplkit_unit_or_zero(neighbour.normal);
  if (!(dot(nq, nj) >= min_normal_cos)) return false;
  vec3 d = neighbour.position - receiver.position;
  return abs(dot(nq, d)) <= max_plane_slope * sqrt(dot(d, d));
}

// a / (a + b) for a, b >= 0; 0 when both are 0.
float vplkit_ris_pair_share(float a, float b) {
  float s = a + b;
  return s > 0.0 ? vplkit_mis_div(a, s) : 0.0;
}

// The target of a reuse (C++: the callable target(pixel, g, s) of ris_combine_with). GLSL has no
// callables, so the kinds the pack knows are a small struct: --method ris's ris_target
// (vplkit_ris_reuse_target_unshadowed, C++ ris_unshadowed_target) and, compiled in with
// VPLKIT_RIS_MIS_REUSE (ris_mis_spatial_reuse.glsl defines it), the MIS-weighted target of
// ris_mis_estimator.glsl (vplkit_ris_reuse_target_mis, C++ ris_mis_target).
const int vplkit_ris_reuse_target_unshadowed = 0;
const int vplkit_ris_reuse_target_mis = 1;

struct vplkit_ris_reuse_target {
  int kind;                // one of the constants above
  vplkit_dprsm_view view;
  float dmin;              // unshadowed
  int vpl_mode;
  float depth_tolerance;
  float n1;                // mis: the gathering directions and RIS samples of the estimate
  float n2;
};

vplkit_ris_reuse_target vplkit_make_ris_unshadowed_target(vplkit_dprsm_view view, float dmin, int vpl_mode,
                                                          float depth_tolerance) {
  return vplkit_ris_reuse_target(vplkit_ris_reuse_target_unshadowed, view, dmin, vpl_mode, depth_tolerance, 0.0, 0.0);
}

#ifdef VPLKIT_RIS_MIS_REUSE
// The candidate distribution of pixel `pixel` (the id the distribution hooks take): ris-mis's target
// at a pixel uses its own distribution's pmf.
uint vplkit_ris_reuse_distribution(int pixel);

vplkit_ris_reuse_target vplkit_make_ris_mis_target(vplkit_dprsm_view view, float n1, float n2, int vpl_mode,
                                                   float depth_tolerance) {
  return vplkit_ris_reuse_target(vplkit_ris_reuse_target_mis, view, 0.0, vpl_mode, depth_tolerance, n1, n2);
}
#endif

// p_hat of the sample s at the gather point g of pixel `pixel`.
float vplkit_ris_reuse_target_at(vplkit_ris_reuse_target t, int pixel, vplkit_gather_point g, vplkit_ris_sample s) {
#ifdef VPLKIT_RIS_MIS_REUSE
  if (t.kind == vplkit_ris_reuse_target_mis) {
    if (s.texel < 0 || s.texel >= vplkit_dprsm_view_texel_count(t.view)) return 0.0;
    float pmf = vplkit_estimator_pmf(vplkit_estimator_distribution_pmf(vplkit_ris_reuse_distribution(pixel),
                                                                       uint(s.texel)));
    vplkit_vpl v;
    float p = vplkit_luminance(vplkit_ris_mis_unshadowed(g, t.view, s, pmf, t.n1, t.n2, t.vpl_mode,
                                                         t.depth_tolerance, v));
    return vplkit_reservoir_weight_usable(p) ? p : 0.0;
  }
#endif
  return vplkit_ris_target(g, vplkit_ris_sample_vpl(t.view, s, t.vpl_mode, t.depth_tolerance), t.dmin);
}

// Combines the canonical reservoir of gp (pixel `pixel`) with the reservoirs of
// neighbour_pixels[0 .. n) (loaded through the accessors), u[0] the canonical's selection number,
// u[1 + j] neighbour j's; offered in the order neighbours, then canonical; p_hat from `target`.
vplkit_ris_reservoir vplkit_ris_combine_with(vplkit_gather_point gp, int pixel, vplkit_ris_reservoir canonical,
                                             int neighbour_pixels[VPLKIT_RIS_MAX_NEIGHBOURS], int n,
                                             float u[VPLKIT_RIS_MAX_NEIGHBOURS + 1], int mis,
                                             vplkit_ris_reuse_target target) {
  vplkit_ris_reservoir out_r = vplkit_make_ris_reservoir();
  if (!vplkit_gather_point_valid(gp)) return out_r;
  n = clamp(n, 0, VPLKIT_RIS_MAX_NEIGHBOURS);
  bool has_c = vplkit_ris_reservoir_has_sample(canonical);
  float m_c_conf = canonical.confidence;
  float m_n = 0.0;
  for (int j = 0; j < n; ++j) m_n += vplkit_load_ris_reservoir(neighbour_pixels[j]).confidence;
  float m_sum = m_c_conf + m_n;
  if (!(m_sum > 0.0)) return out_r;

  // Neighbours first, each offered at once, the canonical last (see the C++): no per-neighbour arrays.
  vplkit_weighted_reservoir res = vplkit_make_weighted_reservoir();
  int kept = -1;
  float kept_target = 0.0;
  float m_c = mis == vplkit_ris_reuse_pairwise ? m_c_conf / m_sum : 0.0;
  float balance_c = m_c_conf * canonical.target;
  for (int j = 0; j < n; ++j) {
    int pj = neighbour_pixels[j];
    vplkit_gather_point g_j = vplkit_load_gather_point(pj);
    vplkit_ris_reservoir r_j = vplkit_load_ris_reservoir(pj);
    float m_j = r_j.confidence;
    float p_j_at_c = has_c ? vplkit_ris_reuse_target_at(target, pj, g_j, canonical.kept) : 0.0;
    if (mis == vplkit_ris_reuse_pairwise)
      m_c += (m_j / m_sum) * vplkit_ris_pair_share(m_c_conf * canonical.target, m_n * p_j_at_c);
    else
      balance_c += m_j * p_j_at_c;
    if (!vplkit_ris_reservoir_has_sample(r_j)) continue;
    float target_q = vplkit_ris_reuse_target_at(target, pixel, gp, r_j.kept);
    if (!(target_q > 0.0)) continue;
    float w = 0.0;
    if (mis == vplkit_ris_reuse_pairwise) {
      float share = vplkit_ris_pair_share(m_n * r_j.target, m_c_conf * target_q);
      w = (m_j / m_sum) * share * target_q * vplkit_mis_div(r_j.weight_sum, r_j.target);
    } else {
      float denominator = m_c_conf * target_q + m_j * r_j.target;
      for (int s = 0; s < n; ++s) {
        if (s == j) continue;
        int ps = neighbour_pixels[s];
        vplkit_gather_point g_s = vplkit_load_gather_point(ps);
        denominator += vplkit_load_ris_reservoir(ps).confidence * vplkit_ris_reuse_target_at(target, ps, g_s, r_j.kept);
      }
      w = denominator > 0.0 ? vplkit_mis_div(m_j * target_q * r_j.weight_sum, denominator) : 0.0;
    }
    if (vplkit_reservoir_update(res, uint(j + 1), w, u[j + 1])) {
      kept = j;
      kept_target = target_q;
    }
  }
  if (mis == vplkit_ris_reuse_balance)
    m_c = balance_c > 0.0 ? vplkit_mis_div(m_c_conf * canonical.target, balance_c) : 0.0;
  float w_c = has_c ? m_c * canonical.weight_sum : 0.0;
  if (vplkit_reservoir_update(res, 0u, w_c, u[0])) kept = -1;
  out_r.confidence = m_sum;
  if (vplkit_reservoir_empty_of(res)) return out_r;
  if (kept < 0) {
    out_r.kept = canonical.kept;
    out_r.target = canonical.target;
  } else {
    out_r.kept = vplkit_load_ris_reservoir(neighbour_pixels[kept]).kept;
    out_r.target = kept_target;
  }
  out_r.weight_sum = res.weight_sum;
  return out_r;
}

// vplkit_ris_combine_with for --method ris's target.
vplkit_ris_reservoir vplkit_ris_combine(vplkit_gather_point gp, vplkit_dprsm_view view, vplkit_ris_reservoir canonical,
                                        int neighbour_pixels[VPLKIT_RIS_MAX_NEIGHBOURS], int n,
                                        float u[VPLKIT_RIS_MAX_NEIGHBOURS + 1], int mis, float dmin, int vpl_mode,
                                        float depth_tolerance) {
  return vplkit_ris_combine_with(gp, -1, canonical, neighbour_pixels, n, u, mis,
                                 vplkit_make_ris_unshadowed_target(view, dmin, vpl_mode, depth_tolerance));
}

// Picks up to settings.neighbours neighbours of `pixel` and combines their reservoirs with gp's
// canonical one, p_hat from `target`.
vplkit_ris_reservoir vplkit_ris_spatial_reuse_with(vplkit_gather_point gp, int pixel, int width, int height,
                                                   vplkit_ris_reservoir canonical,
                                                   vplkit_ris_spatial_settings settings, inout vplkit_counter_rng rng,
                                                   vplkit_ris_reuse_target target) {
  if (!vplkit_gather_point_valid(gp)) return vplkit_make_ris_reservoir();
  int attempts = clamp(settings.neighbours, 0, VPLKIT_RIS_MAX_NEIGHBOURS);
  int pixels[VPLKIT_RIS_MAX_NEIGHBOURS];
  float u[VPLKIT_RIS_MAX_NEIGHBOURS + 1];
  int n = 0;
  u[0] = vplkit_rng_next_unit(rng);
  for (int a = 0; a < attempts; ++a) {
    float u0 = vplkit_rng_next_unit(rng);
    float u1 = vplkit_rng_next_unit(rng);
    float us = vplkit_rng_next_unit(rng);
    int p = vplkit_ris_neighbour_pixel(pixel, width, height, settings.radius, u0, u1);
    if (p < 0 || !vplkit_ris_neighbour_similar(gp, vplkit_load_gather_point(p), settings.min_normal_cos,
                                               settings.max_plane_slope))
      continue;
    pixels[n] = p;
    u[n + 1] = us;
    ++n;
  }
  return vplkit_ris_combine_with(gp, pixel, canonical, pixels, n, u, settings.mis, target);
}

// vplkit_ris_spatial_reuse_with for --method ris's target.
vplkit_ris_reservoir vplkit_ris_spatial_reuse(vplkit_gather_point gp, int pixel, int width, int height,
                                              vplkit_dprsm_view view, vplkit_ris_reservoir canonical,
                                              vplkit_ris_spatial_settings settings, inout vplkit_counter_rng rng,
                                              float dmin, int vpl_mode, float depth_tolerance) {
  return vplkit_ris_spatial_reuse_with(gp, pixel, width, height, canonical, settings, rng,
                                       vplkit_make_ris_unshadowed_target(view, dmin, vpl_mode, depth_tolerance));
}

#endif  // VPLKIT_ESTIMATORS_RIS_SPATIAL_REUSE_GLSL
