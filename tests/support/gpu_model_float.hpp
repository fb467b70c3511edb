// SPDX-License-Identifier: MIT
#pragma once
// A GPU model for the C++ templates: gpu_float is a float whose +, -, * and comparisons are IEEE
// binary32 (correctly rounded, as every GPU does them), but whose division and square root are
// not correctly rounded: each result is moved off the correctly rounded one by a number of ulps the
// specifications allow (gpu_precision.hpp). Instantiating a template with T = gpu_float gives a
// second reference, one conforming GPU's answer, which a parity test compares with the IEEE
// reference under the same bound it uses for the real GPU: a bound that holds for the model's
// extremes (every division -2 / +2 ulps off) and for random deviations inside the bound holds for
// any GPU within the table, not only for llvmpipe, whose division and sqrt are correctly rounded.
// Denormals: the MXCSR mode of the thread applies (run the model inside an fp_mode_scope(true) to
// model a GPU that flushes).
// Division through the reciprocal (reciprocal_division_scope): a / b computed as a * (1 / b) with
// the reciprocal flushed to 0 when it is below FLT_MIN, i.e. for |b| > 2^126, as NVIDIA's GPUs
// divide (an approximate reciprocal without denormal results, then a product). GLSL bounds
// division only for |b| in [2^-126, 2^126], so this is conforming; it turns x / b with a huge b
// into 0, and a quotient by such a 0 into 0 * inf = NaN: what a guard against huge divisors must prevent.
//
// The model (gpu_model_scope sets it for the thread):
//   a / b          the correctly rounded quotient, then k ulps away, k in [-2, 2] (2.5 ulp from
//                  the exact quotient at most: [GLSL] [VK] 2.5 ulp);
//   inversesqrt(x) the correctly rounded 1 / sqrt(x) moved by k' in [-1, 1] ulps (1.5 ulp: inside
//                  [GLSL] 2 ulp), where a template asks for it (vplkit::detail::inversesqrt_of);
//   sqrt(x)        1 / inversesqrt(x) with the division above ([GLSL]: inherited);
//   k, k'          fixed at the low or the high end, or drawn per operation from a seeded stream.
// The templates take a float-like T through std::numeric_limits<T>, argument-dependent sqrt and
// abs (vplkit::detail::sqrt_of, abs_of) and the bit layout of vplkit/core/normal_range.hpp.
#include <vplkit/core/normal_range.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace vplkit_test {

enum class gpu_model_deviation { none, low, high, random };

struct gpu_model_state {
  gpu_model_deviation deviation = gpu_model_deviation::none;
  std::uint64_t random = 0;  // splitmix64 state for gpu_model_deviation::random
  bool reciprocal_division = false;  // a / b as a * flush(1 / b) (see the header)
};

inline gpu_model_state& gpu_model() {
  static thread_local gpu_model_state s;
  return s;
}

// Sets the model for its lifetime (the previous one comes back on exit).
class gpu_model_scope {
public:
  explicit gpu_model_scope(gpu_model_deviation d, std::uint64_t seed = 1) : saved_(gpu_model()) {
    gpu_model().deviation = d;
    gpu_model().random = seed;
  }
  ~gpu_model_scope() { gpu_model() = saved_; }
  gpu_model_scope(const gpu_model_scope&) = delete;
  gpu_model_scope& operator=(const gpu_model_scope&) = delete;

private:
  gpu_model_state saved_;
};

// Division through a reciprocal that flushes below FLT_MIN, for its lifetime (the deviation
// stays as it was).
class reciprocal_division_scope {
public:
  reciprocal_division_scope() : saved_(gpu_model().reciprocal_division) { gpu_model().reciprocal_division = true; }
  ~reciprocal_division_scope() { gpu_model().reciprocal_division = saved_; }
  reciprocal_division_scope(const reciprocal_division_scope&) = delete;
  reciprocal_division_scope& operator=(const reciprocal_division_scope&) = delete;

private:
  bool saved_;
};

inline const char* to_string(gpu_model_deviation d) {
  switch (d) {
    case gpu_model_deviation::none: return "correctly rounded";
    case gpu_model_deviation::low: return "division -2 ulp, inversesqrt -1 ulp";
    case gpu_model_deviation::high: return "division +2 ulp, inversesqrt +1 ulp";
    case gpu_model_deviation::random: return "division and inversesqrt random within the bound";
  }
  return "?";
}

namespace detail {

// An offset in [-limit, limit] per the thread's model.
inline int gpu_model_offset(int limit) {
  gpu_model_state& s = gpu_model();
  switch (s.deviation) {
    case gpu_model_deviation::none: return 0;
    case gpu_model_deviation::low: return -limit;
    case gpu_model_deviation::high: return limit;
    case gpu_model_deviation::random: {
      std::uint64_t z = (s.random += 0x9E3779B97F4A7C15ull);
      z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
      z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
      z ^= z >> 31;
      return int(z % std::uint64_t(2 * limit + 1)) - limit;
    }
  }
  return 0;
}

// x moved by k floats (towards +inf for k > 0); zeros, infinities and NaN stay (a device keeps
// exact results exact: 0 / b, x / inf, and the specials are not rounding results).
inline float gpu_model_step(float x, int k) {
  if (x == 0.0f || !std::isfinite(x)) return x;
  const float to = k > 0 ? std::numeric_limits<float>::infinity() : -std::numeric_limits<float>::infinity();
  for (int i = 0; i < (k > 0 ? k : -k); ++i) x = std::nextafter(x, to);
  return x;
}

// a / b under the thread's model: correctly rounded, or a * (1 / b) with the reciprocal flushed
// to 0 below FLT_MIN (reciprocal_division_scope).
inline float gpu_model_quotient(float a, float b) {
  if (!gpu_model().reciprocal_division) return a / b;
  float r = 1.0f / b;
  if (std::fabs(r) < std::numeric_limits<float>::min()) r = std::copysign(0.0f, r);
  return a * r;
}

}  // namespace detail

struct gpu_float {
  float v;  // no initializer: trivially default-constructible, as GLM's unions need (like float)

  gpu_float() = default;
  constexpr gpu_float(float x) : v(x) {}  // NOLINT: implicit, like a float literal
  constexpr gpu_float(double x) : v(float(x)) {}
  constexpr gpu_float(int x) : v(float(x)) {}
  constexpr gpu_float(long x) : v(float(x)) {}
  constexpr gpu_float(long long x) : v(float(x)) {}
  constexpr gpu_float(unsigned x) : v(float(x)) {}
  constexpr gpu_float(unsigned long x) : v(float(x)) {}
  constexpr gpu_float(unsigned long long x) : v(float(x)) {}
  constexpr explicit operator float() const { return v; }
  constexpr explicit operator double() const { return double(v); }
  constexpr explicit operator int() const { return int(v); }
  constexpr explicit operator long() const { return long(v); }
  constexpr explicit operator long long() const { return (long long)(v); }
  constexpr explicit operator unsigned() const { return unsigned(v); }
  constexpr explicit operator unsigned long() const { return (unsigned long)(v); }
  constexpr explicit operator bool() const { return v != 0.0f; }

  friend constexpr gpu_float operator+(gpu_float a, gpu_float b) { return a.v + b.v; }
  friend constexpr gpu_float operator-(gpu_float a, gpu_float b) { return a.v - b.v; }
  friend constexpr gpu_float operator*(gpu_float a, gpu_float b) { return a.v * b.v; }
  friend gpu_float operator/(gpu_float a, gpu_float b) {
    return detail::gpu_model_step(detail::gpu_model_quotient(a.v, b.v), detail::gpu_model_offset(2));
  }
  friend constexpr gpu_float operator-(gpu_float a) { return -a.v; }
  friend constexpr gpu_float operator+(gpu_float a) { return a; }
  gpu_float& operator+=(gpu_float b) { return *this = *this + b; }
  gpu_float& operator-=(gpu_float b) { return *this = *this - b; }
  gpu_float& operator*=(gpu_float b) { return *this = *this * b; }
  gpu_float& operator/=(gpu_float b) { return *this = *this / b; }
  friend constexpr bool operator<(gpu_float a, gpu_float b) { return a.v < b.v; }
  friend constexpr bool operator<=(gpu_float a, gpu_float b) { return a.v <= b.v; }
  friend constexpr bool operator>(gpu_float a, gpu_float b) { return a.v > b.v; }
  friend constexpr bool operator>=(gpu_float a, gpu_float b) { return a.v >= b.v; }
  friend constexpr bool operator==(gpu_float a, gpu_float b) { return a.v == b.v; }
  friend constexpr bool operator!=(gpu_float a, gpu_float b) { return a.v != b.v; }

  // Found by argument-dependent lookup (vplkit::detail::sqrt_of, abs_of; GLM's geometric functions).
  friend gpu_float sqrt(gpu_float x) {
    if (!(x.v > 0.0f) || !std::isfinite(x.v)) return std::sqrt(x.v);  // 0, negative, NaN, inf: exact
    return gpu_float(1.0f) / inversesqrt(x);
  }
  // GLSL's inversesqrt: 2 ulp ([GLSL] [VK]); modelled as the correctly rounded 1 / sqrt(x) moved
  // by k' in [-1, 1] ulps (vplkit::detail::inversesqrt_of finds it).
  friend gpu_float inversesqrt(gpu_float x) {
    if (!(x.v > 0.0f) || !std::isfinite(x.v)) return 1.0f / std::sqrt(x.v);
    return detail::gpu_model_step(1.0f / std::sqrt(x.v), detail::gpu_model_offset(1));
  }
  friend gpu_float abs(gpu_float x) { return std::fabs(x.v); }
  friend gpu_float fabs(gpu_float x) { return std::fabs(x.v); }
  friend bool isnan(gpu_float x) { return std::isnan(x.v); }
  friend bool isinf(gpu_float x) { return std::isinf(x.v); }
  friend bool isfinite(gpu_float x) { return std::isfinite(x.v); }
};

}  // namespace vplkit_test

namespace std {
template <>
class numeric_limits<vplkit_test::gpu_float> : public numeric_limits<float> {
  using F = vplkit_test::gpu_float;
  using L = numeric_limits<float>;

public:
  static constexpr F min() noexcept { return L::min(); }
  static constexpr F max() noexcept { return L::max(); }
  static constexpr F lowest() noexcept { return L::lowest(); }
  static constexpr F epsilon() noexcept { return L::epsilon(); }
  static constexpr F round_error() noexcept { return L::round_error(); }
  static constexpr F infinity() noexcept { return L::infinity(); }
  static constexpr F quiet_NaN() noexcept { return L::quiet_NaN(); }
  static constexpr F signaling_NaN() noexcept { return L::signaling_NaN(); }
  static constexpr F denorm_min() noexcept { return L::denorm_min(); }
};
}  // namespace std

namespace vplkit::detail {
// The bits of a gpu_float are those of its float (normal_range.hpp reads exponents from them).
template <>
struct float_layout<vplkit_test::gpu_float> : float_layout<float> {};
}  // namespace vplkit::detail

namespace vplkit_test {

// The deviations every model check runs: both extremes and two random streams.
inline constexpr gpu_model_deviation gpu_model_deviations[] = {gpu_model_deviation::low, gpu_model_deviation::high,
                                                               gpu_model_deviation::random, gpu_model_deviation::random};

}  // namespace vplkit_test
