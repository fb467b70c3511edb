// SPDX-License-Identifier: MIT
#pragma once
// A scene whose continuous one-bounce integral is known to ~1e-10: a point light over an infinite
// diffuse floor, and gather points above the floor looking down at it (not part of the library;
// header-only, namespace vplkit_test, T = double or float).
//
//   floor  the plane y = 0, normal +y, albedo rho_f; nothing else, so nothing occludes
//   light  at (0, H, 0), intensity I, DPRSM front axis (0, -1, 0): the front paraboloid sees the
//          floor (every valid texel of it), the back one sees nothing
//   gather points  above the floor with normals pointing below the horizon (n.y < 0): every
//          direction of x's hemisphere that goes down meets the floor
//
// The integral (docs/math.md section 11): in solid angle at x, with beta the angle from straight
// down and phi the azimuth,
//   L(x) = int (rho_x / pi) L_o(y(beta, phi)) cos(theta2) sin(beta) dbeta dphi,
//   L_o(y) = rho_f I H / (pi d1^3)   (cos(alpha) = H / d1),
// over the directions with cos(theta2) > 0. Splitting phi where the tangent plane of x crosses
// straight down and integrating beta from 0 to the tangent plane's edge makes the integrand smooth
// on every piece; Gauss-Legendre in both (continuous_integral) converges geometrically.
//
// What the DPRSM estimators' estimand leaves out of it: the directions of the invalid texels' parts
// inside the unit disk (docs/math.md section 11), all within sqrt(2)/R of the rim in uv, i.e. floor
// points beyond rho0 = H R / sqrt(2) from the light's foot. excluded_bound() bounds their
// contribution: there L_o <= rho_f I H / (pi rho0^3), and the floor beyond r = rho0 - |x's foot -
// the light's foot| from x's foot carries int cos(theta1) cos(theta2) / (pi d2^2) dA <=
// int hx / (pi d2^3) dA = 2 hx / sqrt(hx^2 + r^2) (cos(theta2) <= 1).
#include <vplkit/core/gather_point.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/vpl/dprsm_raycast.hpp>
#include <vplkit/vpl/dprsm_view.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include <synthetic_scene.hpp>  // dprsm_data, named_gather_point

namespace vplkit_test {

using vplkit::vec3;

// Gauss-Legendre nodes and weights on [-1, 1] (Newton on the Legendre recurrence, double).
struct gauss_legendre {
  std::vector<double> x, w;
  explicit gauss_legendre(int n) : x(std::size_t(n)), w(std::size_t(n)) {
    const double pi = 3.14159265358979323846;
    for (int i = 0; i < n; ++i) {
      double z = std::cos(pi * (i + 0.75) / (n + 0.5)), dp = 0.0;
      for (int it = 0; it < 100; ++it) {
        double p0 = 1.0, p1 = z;
        for (int k = 2; k <= n; ++k) {
          const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
          p0 = p1;
          p1 = p2;
        }
        dp = n * (z * p1 - p0) / (z * z - 1.0);
        const double dz = p1 / dp;
        z -= dz;
        if (std::abs(dz) < 1e-16) break;
      }
      x[std::size_t(i)] = z;
      w[std::size_t(i)] = 2.0 / ((1.0 - z * z) * dp * dp);
    }
  }
  // int_a^b f
  template <class F>
  double integrate(double a, double b, F&& f) const {
    const double m = 0.5 * (a + b), h = 0.5 * (b - a);
    double s = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) s += w[i] * f(m + h * x[i]);
    return s * h;
  }
};

template <class T>
class planar_scene {
public:
  T height = T(1.2);
  vec3<T> floor_albedo{T(0.7), T(0.6), T(0.5)};
  vplkit::point_light<T> light;

  planar_scene()
      : light(vplkit::make_point_light(vec3<T>(T(0), height, T(0)), vec3<T>(T(8), T(7), T(6)),
                                       vec3<T>(T(0), T(-1), T(0)))) {}

  // The floor point along the ray, if the ray goes down from above the floor.
  std::optional<vplkit::dprsm_hit<T>> trace_from_light(vec3<T> origin, vec3<T> dir) const {
    if (!(dir.y < T(0)) || !(origin.y > T(0))) return std::nullopt;
    const T t = -origin.y / dir.y;
    vec3<T> p = origin + t * dir;
    p.y = T(0);  // on the plane exactly
    return vplkit::dprsm_hit<T>{p, vec3<T>(T(0), T(1), T(0)), floor_albedo};
  }

  dprsm_data<T> make_dprsm(int R) const {
    return render_dprsm_data(light, R, [this](vec3<T> o, vec3<T> dir) { return trace_from_light(o, dir); });
  }

  // Gather points above the floor, normals below the horizon, albedo (0.8, 0.75, 0.7).
  std::vector<named_gather_point<T>> gather_points() const {
    const vec3<T> rho(T(0.8), T(0.75), T(0.7));
    auto gp = [&](const char* name, vec3<T> p, vec3<T> n) {
      return named_gather_point<T>{name, vplkit::gather_point<T>{p, glm::normalize(n), rho}, false};
    };
    return {
        gp("low_down", vec3<T>(T(0.3), T(0.1), T(0.2)), vec3<T>(T(0), T(-1), T(0))),
        gp("very_low_down", vec3<T>(T(-0.7), T(0.05), T(0.45)), vec3<T>(T(0), T(-1), T(0))),
        gp("mid_down", vec3<T>(T(-0.6), T(0.4), T(0.5)), vec3<T>(T(0), T(-1), T(0))),
        gp("low_tilted", vec3<T>(T(0.8), T(0.12), T(-0.4)), vec3<T>(T(-0.5), T(-1), T(0.3))),
        gp("far_tilted", vec3<T>(T(2.0), T(0.6), T(1.5)), vec3<T>(T(-1), T(-1), T(-0.6))),
    };
  }
};

// No occluders: x above the floor sees every floor point it faces (the cosines decide the rest).
struct planar_visibility {
  template <class T>
  bool operator()(vec3<T>, vec3<T>, vec3<T>, vec3<T>) const {
    return true;
  }
};

// The floor point a ray from x (above the floor) meets, if it goes down.
struct planar_tracer {
  template <class T>
  vplkit::ray_hit<T> operator()(vec3<T> x, vec3<T>, vec3<T> dir) const {
    vplkit::ray_hit<T> r;
    if (!(dir.y < T(0)) || !(x.y > T(0))) return r;
    r.hit = true;
    r.position = x + (-x.y / dir.y) * dir;
    r.position.y = T(0);
    return r;
  }
};

// The continuous integral at gp (double), Gauss-Legendre with n nodes per piece and direction.
// With two normals (docs/math.md section 12) the cosine is the shading normal's and directions
// below the geometric surface count 0; both normals must point down (y < 0).
inline vec3<double> continuous_integral(const planar_scene<double>& s, const vplkit::gather_point<double>& gp,
                                        int n = 160) {
  const double pi = 3.14159265358979323846;
  const vec3<double> x = gp.position, nx = glm::normalize(vplkit::gather_point_shading_normal(gp)),
                     ng = glm::normalize(gp.normal), c = s.light.position;
  const double hx = x.y, H = c.y;
  const gauss_legendre gl(n);
  // a(phi) = n.x cos phi + n.z sin phi = A cos(phi - phi0): zero at phi0 +- pi/2, for each normal;
  // the integrand's edge in beta is smooth between consecutive cuts.
  const double phi_s = std::atan2(nx.z, nx.x), phi_g = std::atan2(ng.z, ng.x);
  std::vector<double> cuts = {phi_s - 0.5 * pi, phi_s + 0.5 * pi};
  if (ng != nx)
    for (double p : {phi_g - 0.5 * pi, phi_g + 0.5 * pi}) cuts.push_back(p + 2.0 * pi * std::floor((p - cuts[0]) / (2.0 * pi)));
  std::sort(cuts.begin(), cuts.end());
  cuts.push_back(cuts[0] + 2.0 * pi);
  auto beta_limit = [&](vec3<double> nn, double phi) {
    const double a = nn.x * std::cos(phi) + nn.z * std::sin(phi);
    if (a >= 0.0) return 0.5 * pi;
    return std::atan2(-nn.y, -a);  // tan(beta) a > n.y  <=>  tan(beta) < |n.y| / |a|
  };
  auto beta_max = [&](double phi) { return std::min(beta_limit(nx, phi), beta_limit(ng, phi)); };
  auto radiance_term = [&](double beta, double phi) {
    const double sb = std::sin(beta), cb = std::cos(beta);
    const vec3<double> dir(sb * std::cos(phi), -cb, sb * std::sin(phi));
    const double cos2 = glm::dot(nx, dir);
    if (!(cos2 > 0.0) || !(glm::dot(ng, dir) > 0.0) || !(cb > 0.0)) return 0.0;
    const vec3<double> y = x + (hx / cb) * dir;
    const vec3<double> d = y - c;
    const double d1 = std::sqrt(glm::dot(d, d));
    return cos2 * sb * H / (pi * d1 * d1 * d1) / pi;  // (1/pi) [I rho_f H / (pi d1^3)] cos2 sin(beta)
  };
  double total = 0.0;
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
    const double p_lo = cuts[k], p_hi = cuts[k + 1];
    total += gl.integrate(p_lo, p_hi, [&](double phi) {
      return gl.integrate(0.0, beta_max(phi), [&](double beta) { return radiance_term(beta, phi); });
    });
  }
  return gp.albedo * s.floor_albedo * s.light.intensity * total;
}

// Upper bound of what the DPRSM estimand leaves out (the rim band), per channel.
inline vec3<double> excluded_bound(const planar_scene<double>& s, const vplkit::gather_point<double>& gp, int R) {
  const double pi = 3.14159265358979323846;
  const double rho0 = s.height * R / std::sqrt(2.0);
  const double hx = gp.position.y;
  const double r = std::max(0.0, rho0 - std::hypot(gp.position.x - s.light.position.x,
                                                   gp.position.z - s.light.position.z));
  const double form_factor = std::min(1.0, 2.0 * hx / std::sqrt(hx * hx + r * r));
  return gp.albedo * s.floor_albedo * s.light.intensity * (s.height / (pi * rho0 * rho0 * rho0)) * form_factor;
}

}  // namespace vplkit_test
