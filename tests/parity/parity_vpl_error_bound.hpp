// SPDX-License-Identifier: MIT
#pragma once
// Forward error bounds of a VPL's contribution computed in float under docs/math.md "GPU arithmetic
// model" (GLSL 4.30 section 4.7.1, Vulkan "Precision and Operation of SPIR-V Instructions"): every
// + - * correctly rounded or fused into an FMA, division 2.5 ulp, inversesqrt 2 ulp. u = 2^-23 is
// one ulp relative. The bounds are evaluated in double from the C++ side's own inputs; the C++
// float side obeys the same model (FMA or not), so two sides differ by at most twice the bound.
//
// Why a bound per term instead of one relative number: the contribution
//   L = (rho_x / pi) Phi cos1 cos2 / (pi d2^2),   d = y - x,
// is ill-conditioned in two places. A patch VPL's position y = c + d1 w (dprsm_patch_vpl) carries
// an absolute error of a few ulps of |c| + d1, which d = y - x turns into a relative error
// amplified by 1 / d2; and a cosine near 0 (a receiver or a VPL seen edge-on, both on one plane)
// is rounding noise whose relative error is unbounded. Both are properties of the configuration,
// so the bound is: exact inputs in double, each cosine widened by its own noise.
#include <vplkit/core/gather_point.hpp>
#include <vplkit/vpl/dprsm_patch.hpp>
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/luminance.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <iostream>
#include <string>
#include <vector>

namespace vplkit::parity {

namespace vpl_error {
inline const double u = std::ldexp(1.0, -23);
// unit_or_zero / normalize: inversesqrt 2 ulp, the 3-term dot 3 (an FMA chain), the product 1.
inline const double unit = 2.0 * u + 3.0 * u + u;
// paraboloid_to_direction: 1 / (1 + r2) 2.5 ulp and 5 roundings; the frame's rotation a 3-term dot.
inline const double light_dir = 2.5 * u + 5.0 * u + 3.0 * u;
// The flux rho_t I Omega: two products, Omega = J(uv) (2/R)^2 with J a 2.5-ulp division and four
// roundings; (rho_x / pi) Phi G: three products; G's quotient: 2.5 ulp.
inline const double products = 2.0 * u + (2.5 * u + 4.0 * u) + 3.0 * u + 2.5 * u;
}  // namespace vpl_error

// Absolute error of the position of patch point p of texel t (dprsm_patch_vpl in float):
// h = n . (c - y_t) and cos(alpha) = -n . w each a subtraction and a 3-term dot of unit vectors,
// d1 = h / cos(alpha) a 2.5-ulp division, y = c + d1 w two roundings or one FMA. 0 at the centre
// (y = y_t, loaded exactly).
inline double patch_point_error(const dprsm_view<float>& view, int t, const dprsm_patch_sample<float>& p) {
  using namespace vpl_error;
  if (p.at_centre || !(p.cos_alpha > 0.0f) || t < 0 || t >= view.texel_count()) return 0.0;
  const glm::dvec3 c(view.light.position);
  const double d1 = p.distance, cos_a = p.cos_alpha, h = d1 * cos_a;
  const double cy = glm::length(c - glm::dvec3(view.position[std::size_t(t)]));
  const double e_h = (unit + 4.0 * u) * cy / h;
  const double e_cos = (unit + light_dir + 3.0 * u) / cos_a;
  const double e_d1 = e_h + e_cos + 2.5 * u;
  return d1 * (e_d1 + light_dir) + 2.0 * u * (glm::length(c) + d1);
}

// Per channel, a bound on |fl(L) - L| for vpl_contribution(gp, v, dmin) in float, where v's position
// carries the absolute error dy (0 for a texel's stored VPL). A direction error rho (the error of d
// over d2, in radians) moves a cosine by at most rho plus the two unit vectors' and the dot's
// rounding: delta. A cosine within delta of 0 may come out on either side of it, so the term is
// bounded by L evaluated with each cosine raised by delta, minus L.
inline glm::dvec3 vpl_contribution_error(const gather_point<float>& gp, const vpl<float>& v, double dy, float dmin) {
  using namespace vpl_error;
  const glm::dvec3 x(gp.position), y(v.position);
  const glm::dvec3 d = y - x;
  const double d2 = glm::length(d);
  const double ln = glm::length(glm::dvec3(v.normal));
  const glm::dvec3 nsf(gather_point_shading_normal(gp));
  if (!(d2 > 0.0) || !(ln > 0.0) || !(glm::length(nsf) > 0.0)) return glm::dvec3(0.0);
  const double rho = (dy + u * (glm::length(y) + glm::length(x))) / d2;  // d = y - x: one rounding each
  const double delta = rho + 2.0 * unit + 3.0 * u;
  const glm::dvec3 wd = d / d2;
  const double cos1 = -glm::dot(glm::dvec3(v.normal) / ln, wd), cos2 = glm::dot(glm::normalize(nsf), wd);
  if (cos1 < -delta || cos2 < -delta) return glm::dvec3(0.0);  // back-facing on both sides
  const double c1 = std::max(cos1, 0.0), c2 = std::max(cos2, 0.0);
  const double dsq = std::max(d2 * d2, double(dmin) * double(dmin));
  const double e_dist = d2 > double(dmin) ? 2.0 * rho : 0.0;  // 1 / d2^2, unless dmin clamps it
  const double pi = 3.14159265358979323846;
  const glm::dvec3 k = glm::dvec3(gp.albedo) / pi * glm::dvec3(v.flux) / (pi * dsq);
  return k * ((c1 + delta) * (c2 + delta) * (1.0 + e_dist + products) - c1 * c2);
}

// The error bound of luminance(L) (a 3-term dot of positive weights: 3 ulp more).
inline double luminance_error(const glm::dvec3& err, double value) {
  return luminance(vec3<double>(err)) * (1.0 + 4.0 * vpl_error::u) + 3.0 * vpl_error::u * std::abs(value);
}

// gpu within bound[k] (absolute) of cpu at every item; prints the worst |gpu - cpu| / bound.
template <class C>
bool check_within_bounds(const std::vector<float>& gpu, const std::vector<C>& cpu, const std::vector<double>& bound,
                         const std::string& what) {
  std::size_t outside = 0, worst = 0;
  double worst_ratio = 0.0;
  for (std::size_t k = 0; k < gpu.size(); ++k) {
    const double diff = std::abs(double(gpu[k]) - double(cpu[k]));
    const double ratio = diff / (bound[k] + 1e-30);
    if (!(ratio <= 1.0)) ++outside;
    if (!(ratio <= worst_ratio)) worst_ratio = ratio, worst = k;
  }
  std::cout << "parity " << what << ": " << gpu.size() << " floats within a per-item forward error bound; worst |gpu - cpu| / bound "
            << worst_ratio;
  if (!gpu.empty())
    std::cout << " at [" << worst << "] gpu=" << gpu[worst] << " cpu=" << cpu[worst] << " bound " << bound[worst];
  std::cout << ", " << outside << " outside\n";
  return outside == 0;
}

}  // namespace vplkit::parity
