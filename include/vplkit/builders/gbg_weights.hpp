// SPDX-License-Identifier: MIT
#pragma once
// Gathering-based global (GBG) weights (paper 5.3 and Alg. 2, docs/math.md section 4): every
// valid gather point shoots n_dirs cosine rays through the host's tracer; a hit that the DPRSM sees
// lit, on a texel that carries a VPL, off x's own plane (vpl_hit_on_own_plane), adds the
// accumulator's value to that texel; then
// w_t = acc[t] / (|G| n_dirs), accumulated in double, and the hole-aware 3x3 median fills the
// texels that carry a VPL but no ray reached. The per-gather-point random numbers (stream = pixel,
// direction j = counters 2j, 2j + 1) are the GPU mirror's (glsl/vplkit/builders/gbg_weights.glsl).
// The two accumulators, what each estimates, normalisation, holes, depth tolerance:
// docs/api/builders.md, "GBG weights".
#include <vplkit/builders/detail/argument_checks.hpp>
#include <vplkit/core/error.hpp>
#include <vplkit/core/gather_point.hpp>
#include <vplkit/core/unit_or_zero.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/image/median_fill.hpp>
#include <vplkit/paraboloid/texel_grid.hpp>
#include <vplkit/sampling/cosine_hemisphere.hpp>
#include <vplkit/sampling/orthonormal_basis.hpp>
#include <vplkit/sampling/rng.hpp>
#include <vplkit/vpl/dprsm_lookup.hpp>
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/luminance.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace vplkit {

enum class gbg_accumulator {
  paper,      // luminance of the VPL's contribution to x (eq. 5 value) per lit hit
  gathering,  // luminance of the gathering estimator's value rho_x L_o(y) per lit hit
};

template <class T>
struct gbg_params {
  int n_dirs = 16;         // NBDIR: cosine-distributed rays per gather point, >= 1
  T dmin = T(0);           // VPL distance clamp of the paper accumulator (unused by gathering)
  T depth_tolerance = T(0);  // world-space tolerance of dprsm_lookup (about a voxel when the host
                             // traces through a voxel grid)
  std::uint32_t seed = 0;  // counter_rng seed; streams are pixel indices
  gbg_accumulator accumulator = gbg_accumulator::gathering;
  bool fill_holes = true;  // run gbg_fill_holes after the accumulation
};

// What happened during a build (for reports and tests).
struct gbg_stats {
  int gather_points = 0;    // |G|, valid gather points
  long long rays = 0;       // |G| * n_dirs
  long long hits = 0;       // rays whose trace hit something
  long long lit_hits = 0;   // hits that accumulated a value (lit, and the texel carries a VPL)
  int reached_texels = 0;   // texels with a nonzero weight after accumulation
  int holes = 0;            // texels carrying a VPL left at 0 by the accumulation
  int filled = 0;           // holes that the median fill gave a nonzero weight (0 if not run)
};

// Value accumulated for one lit hit (see the header comment). Plain arithmetic, never throws.
template <class T>
inline T gbg_hit_value(const gather_point<T>& g, const dprsm_view<T>& view, const dprsm_lookup_result& lookup,
                       const ray_hit<T>& hit, T dmin, gbg_accumulator accumulator, T depth_tolerance) {
  if (accumulator == gbg_accumulator::paper)
    return luminance(vpl_contribution(g, view.vpl_at(lookup.texel), dmin));
  // As the gathering estimator: one-sided, a hit on another surface with its own normal, an
  // inexact hit evaluated on the texel's plane.
  return luminance(g.albedo * dprsm_hit_radiance(view, lookup, g.position, hit, depth_tolerance));
}

// Direction j of gather point `pixel` (the random-number consumption documented above). The
// counter is set explicitly, so directions can be generated in any order (one GPU thread each).
template <class T>
inline vec3<T> gbg_direction(vec3<T> n_x, int pixel, int j, std::uint32_t seed) {
  counter_rng rng = make_counter_rng(seed, std::uint32_t(pixel));
  rng.counter = 2u * std::uint32_t(j);
  const T u0 = rng_next_unit<T>(rng);
  const T u1 = rng_next_unit<T>(rng);
  return to_world(make_orthonormal_basis(n_x), sample_cosine_hemisphere(vec2<T>(u0, u1)));
}

// Accumulates the n_dirs rays of one gather point into acc[0 .. 2 R^2) (double), adding to
// *stats when given. g must be valid (gather_point_valid). Never throws by itself (the tracer
// may). Hosts that parallelise use gbg_accumulate_pixels and gbg_merge below.
template <class T, class Tracer>
inline void gbg_accumulate_gather_point(const gather_point<T>& g, int pixel,
                                        const dprsm_view<T>& view, Tracer&& trace,
                                        const gbg_params<T>& params, double* acc,
                                        gbg_stats* stats = nullptr) {
  const orthonormal_basis<T> frame = make_orthonormal_basis(gather_point_shading_normal(g));
  counter_rng rng = make_counter_rng(params.seed, std::uint32_t(pixel));
  long long hits = 0, lit = 0;
  for (int j = 0; j < params.n_dirs; ++j) {
    const T u0 = rng_next_unit<T>(rng);
    const T u1 = rng_next_unit<T>(rng);
    const vec3<T> local = sample_cosine_hemisphere(vec2<T>(u0, u1));
    // On the horizon (probability ~2^-24 per draw) p1 = 0: no contribution, no trace, as in the
    // gathering estimator.
    if (!(local.z > T(0))) continue;
    const vec3<T> dir = to_world(frame, local);
    if (!gather_point_accepts_direction(g, dir)) continue;  // below the geometric surface: 0
    const ray_hit<T> h = trace(g.position, g.normal, dir);
    if (!h.hit) continue;
    ++hits;
    // x on the hit's own plane (a crease through x, coincident surfaces) sees it edge-on: the VPL
    // strategy gives its texel cos(theta1) = 0 at x, so no draws go there for x. Without the rule
    // an exact tracer's lifted origin meets the crease's other surface at distance ~0, and which
    // rays do so is a rounding tie that Embree and the GLSL BVH decide differently.
    if (vpl_hit_on_own_plane(g.position, h)) continue;
    const dprsm_lookup_result r = dprsm_lookup(view, h.position, params.depth_tolerance);
    if (!r.lit || !vpl_has_flux(view.vpl_at(r.texel))) continue;
    ++lit;
    acc[r.texel] += double(gbg_hit_value(g, view, r, h, params.dmin, params.accumulator, params.depth_tolerance));
  }
  if (stats != nullptr) {
    stats->rays += params.n_dirs;
    stats->hits += hits;
    stats->lit_hits += lit;
  }
}

// The valid gather points among pixels [begin, end) of `gbuffer`, in pixel order, accumulated into
// acc[0 .. 2 R^2) (gbg_accumulate_gather_point), each counted in stats->gather_points when stats is
// given. The unit of work of a build: a serial build is one call over every pixel; a host that
// parallelises gives each worker its own gbg_partial, accumulates ranges of pixels into it, then
// calls gbg_merge. No validation (build_gbg_weights validates); never throws by itself. The GLSL
// pack has no counterpart of this and gbg_merge: gbg_accumulate.comp runs one invocation per
// gather point and merges by atomics.
template <class T, class Tracer>
inline void gbg_accumulate_pixels(const gbuffer_view<T>& gbuffer, int begin, int end,
                                  const dprsm_view<T>& view, Tracer&& trace,
                                  const gbg_params<T>& params, double* acc,
                                  gbg_stats* stats = nullptr) {
  for (int p = begin; p < end; ++p) {
    const gather_point<T> g = gbuffer.at(p);
    if (!gather_point_valid(g)) continue;
    if (stats != nullptr) ++stats->gather_points;
    gbg_accumulate_gather_point(g, p, view, trace, params, acc, stats);
  }
}

// One worker's share of a parallel build: its accumulator (empty until the worker gets pixels; then
// 2 R^2 doubles) and its counts.
struct gbg_partial {
  std::vector<double> acc;
  gbg_stats stats;
};

// acc[t] = the sum of the partials' acc[t] in index order, starting from +0 (a partial with an
// empty acc is skipped); their gather points, rays, hits and lit hits added to `stats`. The sum
// of doubles depends on which pixels went to which worker, not on anything else.
inline void gbg_merge(const std::vector<gbg_partial>& parts, std::size_t n, double* acc,
                      gbg_stats& stats) {
  for (std::size_t t = 0; t < n; ++t) acc[t] = 0.0;
  for (const gbg_partial& part : parts) {
    if (!part.acc.empty())
      for (std::size_t t = 0; t < n; ++t) acc[t] += part.acc[t];
    stats.gather_points += part.stats.gather_points;
    stats.rays += part.stats.rays;
    stats.hits += part.stats.hits;
    stats.lit_hits += part.stats.lit_hits;
  }
}

// out[t] = T(acc[t] / (gather_points * n_dirs)); all zeros when gather_points == 0 (no NaN).
template <class T>
inline void gbg_finish(const double* acc, std::size_t n, int gather_points, int n_dirs, T* out) {
  const double denom = double(gather_points) * double(n_dirs);
  for (std::size_t t = 0; t < n; ++t) out[t] = denom > 0.0 ? T(acc[t] / denom) : T(0);
}

namespace detail {
inline void check_gbg_params_common(int n_dirs, const char* who) {
  if (n_dirs < 1)
    throw invalid_input(std::string(who) + ": n_dirs = " + std::to_string(n_dirs) +
                        " (NBDIR) must be >= 1; with no ray nothing can be learned");
}
}  // namespace detail

// Hole filling on its own: out = hole-aware 3x3 median fill of `in` (2 R^2 weights), per face,
// filling only texels that carry a VPL (vpl_has_flux) and have weight 0. `in` and `out` must not
// overlap. Returns the number of texels filled with a nonzero value. Throws invalid_input for a
// bad view, null pointers, overlapping buffers, or a NaN / infinite weight.
// Cost: 2 R^2 texels x (9 reads + a sort of <= 8 values).
template <class T>
inline int gbg_fill_holes(const T* in, T* out, const dprsm_view<T>& view) {
  view.validate();
  const int R = view.resolution;
  const std::size_t face_size = std::size_t(R) * std::size_t(R);
  const std::size_t n = 2 * face_size;
  if (in == nullptr || out == nullptr) throw invalid_input("gbg_fill_holes: null weights pointer");
  if (detail::median_fill_ranges_overlap<T>(in, n, out, n))
    throw invalid_input("gbg_fill_holes: `in` and `out` overlap (the fill cannot run in place)");
  std::vector<unsigned char> carries(n, 0);
  for (std::size_t t = 0; t < n; ++t) carries[t] = vpl_has_flux(view.vpl_at(int(t))) ? 1 : 0;
  for (int face = 0; face < 2; ++face) {
    const unsigned char* mask = carries.data() + std::size_t(face) * face_size;
    median_fill(in + std::size_t(face) * face_size, out + std::size_t(face) * face_size, R, R,
                [mask, R](int x, int y) { return mask[std::size_t(y) * std::size_t(R) + std::size_t(x)] != 0; });
  }
  int filled = 0;
  for (std::size_t t = 0; t < n; ++t) filled += (in[t] == T(0) && out[t] != T(0)) ? 1 : 0;
  return filled;
}

template <class T>
inline std::vector<T> gbg_fill_holes(const std::vector<T>& in, const dprsm_view<T>& view) {
  view.validate();
  detail::check_weights_span(view, in.data(), in.size(), "gbg_fill_holes");
  std::vector<T> out(in.size(), T(0));
  gbg_fill_holes(in.data(), out.data(), view);
  return out;
}

// The last step of a build, on the finished weights raw[0 .. n) (gbg_finish): counts the texels the
// rays reached and the holes into `stats`, then writes the hole-filled weights (gbg_fill_holes) to
// `weights` when fill_holes is set, else a copy of raw. Throws as gbg_fill_holes.
template <class T>
inline void gbg_count_and_fill(const T* raw, std::size_t n, const dprsm_view<T>& view,
                               bool fill_holes, T* weights, gbg_stats& stats) {
  for (std::size_t t = 0; t < n; ++t) {
    if (raw[t] != T(0)) {
      ++stats.reached_texels;
    } else if (vpl_has_flux(view.vpl_at(int(t)))) {
      ++stats.holes;
    }
  }
  if (fill_holes) {
    stats.filled = gbg_fill_holes(raw, weights, view);
  } else {
    for (std::size_t t = 0; t < n; ++t) weights[t] = raw[t];
  }
}

// GBG weights for all 2 R^2 texels into weights[0 .. 2 R^2). trace(vec3<T> x, vec3<T> n_x,
// vec3<T> dir) -> ray_hit<T> is the host's first-hit query. Throws invalid_input for a bad
// G-buffer / DPRSM view, n_dirs < 1, dmin or depth_tolerance negative or not finite, or a weights
// span of the wrong size. No valid gather point gives all-zero weights (an empty distribution).
// Cost: |G| x n_dirs traces + DPRSM lookups (the traces dominate), then the fill.
template <class T, class Tracer>
inline gbg_stats build_gbg_weights(const gbuffer_view<T>& gbuffer, const dprsm_view<T>& view,
                                   Tracer&& trace, const gbg_params<T>& params, T* weights,
                                   std::size_t weights_size) {
  const char* who = "build_gbg_weights";
  gbuffer.validate();
  view.validate();
  detail::check_gbg_params_common(params.n_dirs, who);
  detail::check_dmin(params.dmin, who);
  if (!(params.depth_tolerance >= T(0)) || !std::isfinite(params.depth_tolerance))
    throw invalid_input(std::string(who) + ": depth_tolerance = " +
                        std::to_string(params.depth_tolerance) + " must be finite and >= 0");
  detail::check_weights_span(view, weights, weights_size, who);

  const std::size_t n = weights_size;
  std::vector<double> acc(n, 0.0);
  gbg_stats stats;
  gbg_accumulate_pixels(gbuffer, 0, gbuffer.pixel_count(), view, trace, params, acc.data(), &stats);
  std::vector<T> raw(n, T(0));
  gbg_finish(acc.data(), n, stats.gather_points, params.n_dirs, raw.data());
  gbg_count_and_fill(raw.data(), n, view, params.fill_holes, weights, stats);
  return stats;
}

// Convenience: the weights in a new vector of 2 R^2 entries (stats to *stats when given).
template <class T, class Tracer>
inline std::vector<T> build_gbg_weights(const gbuffer_view<T>& gbuffer, const dprsm_view<T>& view,
                                        Tracer&& trace, const gbg_params<T>& params,
                                        gbg_stats* stats = nullptr) {
  view.validate();
  std::vector<T> w(std::size_t(view.texel_count()), T(0));
  const gbg_stats s = build_gbg_weights(gbuffer, view, trace, params, w.data(), w.size());
  if (stats != nullptr) *stats = s;
  return w;
}

}  // namespace vplkit
