// SPDX-License-Identifier: MIT
// libFuzzer harness: discrete_cdf, alias_table, face_roulette and defensive_mixture (float and
// double) against their contract (docs/api/distribution.md): bad input throws invalid_input naming
// the FIRST bad index; otherwise no sampler returns a zero-weight index or pmf 0, sample().pmf
// is pmf(index) bit for bit, the guided search returns the binary search's index, the stored
// arrays keep their invariants, every pmf is w / sum to T's rounding, and a failed assign()
// changes nothing.
#include "fuzz_check.hpp"

#include <special_values.hpp>

#include <vplkit/distribution/alias_table.hpp>
#include <vplkit/distribution/defensive_mixture.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/distribution/face_roulette.hpp>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace {

using vplkit_fuzz::byte_reader;

// One weight from a selector byte: the shapes where distributions break (zeros, -0, denormals,
// huge values, exact powers of two, raw bit patterns that may be NaN, Inf or negative).
template <class T>
T make_weight(byte_reader& in) {
  using bits = std::conditional_t<std::is_same<T, float>::value, std::uint32_t, std::uint64_t>;
  const std::uint8_t sel = in.get<std::uint8_t>();
  const std::uint8_t arg = in.get<std::uint8_t>();
  const int max_exp = std::numeric_limits<T>::max_exponent;       // 128 / 1024
  const int min_exp = std::numeric_limits<T>::min_exponent - std::numeric_limits<T>::digits;  // denormal floor
  switch (sel % 10) {
    case 0: return T(0);
    case 1: return -T(0);
    case 2: return T(arg) * std::numeric_limits<T>::denorm_min();
    case 3: return std::ldexp(T(1), min_exp + int(arg) * (max_exp - min_exp) / 255);
    case 4: return std::numeric_limits<T>::max() * (T(arg) / T(255));
    case 5: return T(1) + T(arg);
    case 6: return T(arg) / T(7);
    case 7: { const bits b = in.get<bits>(); T w; std::memcpy(&w, &b, sizeof w); return w; }
    case 8: return T(arg & 1 ? 3e38 : 1e-38);
    default: return std::nextafter(T(arg), T(0));
  }
}

// The library's rule (weights.hpp, normal-range contract): rejected are NaN, +-Inf and negatives of
// normal size; a negative denormal is a valid weight that counts as 0.
template <class T>
bool is_bad(T w) {
  return !(w > -std::numeric_limits<T>::min() && w <= std::numeric_limits<T>::max());
}

template <class T>
std::vector<T> edge_and_input_us(byte_reader& in) {
  std::vector<T> us = {T(0), -T(0), std::numeric_limits<T>::denorm_min(), T(0.5), T(1), T(2),
                       std::nextafter(T(1), T(0)), std::numeric_limits<T>::infinity(),
                       std::numeric_limits<T>::quiet_NaN(), T(-1)};
  for (int k = 0; k < 48 && in.left() > 0; ++k) {
    const std::uint32_t r = in.get<std::uint32_t>();
    us.push_back((r & 1u) ? T(r >> 8) * T(0x1p-24) : T(r) * T(0x1p-32));
  }
  return us;
}

template <class T>
void check_cdf(const vplkit::discrete_cdf<T>& d, const std::vector<T>& w, long double sum,
               const std::vector<T>& us) {
  const std::size_t n = w.size();
  VPLKIT_FUZZ_CHECK(d.size() == n);
  const bool all_zero = sum == 0;
  VPLKIT_FUZZ_CHECK(d.empty() == all_zero);
  const auto& c = d.cdf();
  VPLKIT_FUZZ_CHECK(c.size() == n + 1);
  if (all_zero) {
    for (T x : c) VPLKIT_FUZZ_CHECK(x == T(0));
    for (T u : us) VPLKIT_FUZZ_CHECK(d.sample(u).pmf == T(0) && d.sample(u).index == 0);
    return;
  }
  VPLKIT_FUZZ_CHECK(c[0] == T(0) && c[n] == T(1));
  const double eps = double(std::numeric_limits<T>::epsilon());
  for (std::size_t i = 0; i < n; ++i) {
    VPLKIT_FUZZ_CHECK(c[i] <= c[i + 1]);
    if (w[i] == T(0)) VPLKIT_FUZZ_CHECK(c[i] == c[i + 1]);
    VPLKIT_FUZZ_CHECK(std::fabs(double(d.pmf(i)) - double(w[i] / sum)) <= 4.0 * eps);
  }
  // guide[j] = the largest i in [0, n - 1] with cdf[i] <= j / m (m a power of two: exact).
  const std::size_t m = d.guide_size();
  VPLKIT_FUZZ_CHECK(m >= n && (m & (m - 1)) == 0 && d.guide().size() == m + 1);
  for (std::size_t j = 0; j <= m; ++j) {
    const T edge = T(j) / T(m);
    std::size_t want = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (c[i] <= edge) want = i;
    VPLKIT_FUZZ_CHECK(d.guide()[j] == want);
  }
  std::vector<T> all = us;
  for (T x : c) {
    all.push_back(x);
    all.push_back(std::nextafter(x, T(0)));
    all.push_back(std::nextafter(x, T(2)));
  }
  for (T u : all) {
    const auto s = d.sample(u);
    VPLKIT_FUZZ_CHECK(s.index < n);
    VPLKIT_FUZZ_CHECK(w[s.index] > T(0));
    VPLKIT_FUZZ_CHECK(s.pmf > T(0) && std::isfinite(s.pmf));
    VPLKIT_FUZZ_CHECK(s.pmf == d.pmf(s.index));
    const auto b = d.sample_binary_search(u);
    VPLKIT_FUZZ_CHECK(b.index == s.index && b.pmf == s.pmf);
  }
}

template <class T>
void check_alias(const vplkit::alias_table<T>& a, const std::vector<T>& w, long double sum,
                 const std::vector<T>& us) {
  const std::size_t n = w.size();
  VPLKIT_FUZZ_CHECK(a.size() == n && a.empty() == (sum == 0));
  if (a.empty()) {
    for (T u : us) VPLKIT_FUZZ_CHECK(a.sample(u).pmf == T(0) && a.sample(u, u).pmf == T(0));
    return;
  }
  const double eps = double(std::numeric_limits<T>::epsilon());
  std::vector<double> realised(n, 0.0);
  for (std::size_t j = 0; j < n; ++j) {
    const auto& b = a.bins()[j];
    VPLKIT_FUZZ_CHECK(b.threshold >= T(0) && b.threshold <= T(1));
    VPLKIT_FUZZ_CHECK(b.alias < n);
    if (w[j] == T(0) || b.pmf == T(0)) VPLKIT_FUZZ_CHECK(b.threshold == T(0));
    if (b.threshold < T(1)) VPLKIT_FUZZ_CHECK(a.bins()[b.alias].pmf > T(0));
    const double exact = double(w[j] / sum);
    if (exact >= double(std::numeric_limits<T>::min()))
      VPLKIT_FUZZ_CHECK(std::fabs(double(b.pmf) - exact) <= 2.0 * eps * exact);
    realised[j] += double(b.threshold) / double(n);
    realised[b.alias] += (1.0 - double(b.threshold)) / double(n);
  }
  for (std::size_t i = 0; i < n; ++i)
    VPLKIT_FUZZ_CHECK(std::fabs(realised[i] - double(w[i] / sum)) <= 4.0 * eps + double(n) * 0x1p-52);
  std::vector<T> all = us;
  vplkit_test::append_bucket_edges(all, n);
  for (T u : all) {
    for (const auto& s : {a.sample(u), a.sample(u, T(0)), a.sample(u, u), a.sample(u, std::nextafter(T(1), T(0)))}) {
      VPLKIT_FUZZ_CHECK(s.index < n);
      VPLKIT_FUZZ_CHECK(w[s.index] > T(0));
      VPLKIT_FUZZ_CHECK(s.pmf > T(0) && std::isfinite(s.pmf));
      VPLKIT_FUZZ_CHECK(s.pmf == a.pmf(s.index));
    }
  }
}

template <class T>
void check_compositions(const std::vector<T>& w, std::size_t split, T eps, const std::vector<T>& us) {
  const std::vector<T> front(w.begin(), w.begin() + long(split)), back(w.begin() + long(split), w.end());
  const vplkit::face_roulette<T> r{vplkit::discrete_cdf<T>(front), vplkit::discrete_cdf<T>(back)};
  const T bf = r.front_probability(), bb = r.back_probability();
  VPLKIT_FUZZ_CHECK(bf >= T(0) && bf <= T(1) && bb >= T(0) && bb <= T(1));
  VPLKIT_FUZZ_CHECK(r.empty() ? (bf == T(0) && bb == T(0))
                              : std::fabs(bf + bb - T(1)) <= std::numeric_limits<T>::epsilon());
  for (T u : us) {
    const auto s = r.sample(u);
    if (r.empty()) {
      VPLKIT_FUZZ_CHECK(s.pmf == T(0));
      continue;
    }
    const std::vector<T>& face = s.face == 0 ? front : back;
    VPLKIT_FUZZ_CHECK((s.face == 0 || s.face == 1) && s.index < face.size());
    VPLKIT_FUZZ_CHECK(face[s.index] > T(0));
    VPLKIT_FUZZ_CHECK(s.pmf > T(0) && std::isfinite(s.pmf));
    VPLKIT_FUZZ_CHECK(s.pmf == r.pmf(s.face, s.index));
  }
  // A defensive mixture of the weights with a 0/1 fallback over the second half of the indices.
  std::vector<T> cover(w.size(), T(0));
  for (std::size_t i = split; i < w.size(); ++i) cover[i] = T(1);
  const vplkit::defensive_mixture<T> mix(vplkit::discrete_cdf<T>(w), vplkit::discrete_cdf<T>(cover), eps);
  for (T u : us) {
    const auto s = mix.sample(u);
    if (mix.empty()) {
      VPLKIT_FUZZ_CHECK(s.pmf == T(0));
      continue;
    }
    VPLKIT_FUZZ_CHECK(s.index < w.size());
    VPLKIT_FUZZ_CHECK(w[s.index] > T(0) || cover[s.index] > T(0));
    VPLKIT_FUZZ_CHECK(s.pmf > T(0) && std::isfinite(s.pmf));
    VPLKIT_FUZZ_CHECK(s.pmf == mix.pmf(s.index));
    const auto b = mix.sample_binary_search(u);
    VPLKIT_FUZZ_CHECK(b.index == s.index && b.pmf == s.pmf);
  }
}

template <class D>
void check_rejects(const char* who, const std::vector<typename D::value_type>& w, std::size_t first_bad) {
  try {
    D d(w);
    VPLKIT_FUZZ_CHECK(!"a negative, NaN or infinite weight was accepted");
  } catch (const vplkit::invalid_input& e) {
    const std::string m = e.what();
    VPLKIT_FUZZ_CHECK(m.find(who) != std::string::npos);
    VPLKIT_FUZZ_CHECK(m.find("weight[" + std::to_string(first_bad) + "]") != std::string::npos);
  }
  using T = typename D::value_type;
  std::size_t bad = 0;
  long double kept = 0;
  for (T x : w) {
    const bool b = is_bad(x);
    bad += b ? 1 : 0;
    kept += b ? 0 : vplkit::detail::weight_value(x);
  }
  try {
    const auto s = D::sanitized(w);
    VPLKIT_FUZZ_CHECK(s.zeroed == bad);
  } catch (const vplkit::invalid_input& e) {  // the weights it keeps may still overflow double
    VPLKIT_FUZZ_CHECK((std::is_same<T, double>::value));
    VPLKIT_FUZZ_CHECK(kept >= (long double)std::numeric_limits<double>::max() * 0.999999L);
    VPLKIT_FUZZ_CHECK(std::string(e.what()).find("sum to more than") != std::string::npos);
  }
}

template <class T>
void run(byte_reader& in) {
  const std::uint8_t size_byte = in.get<std::uint8_t>();
  const std::size_t n = size_byte % 97;
  std::vector<T> w(n);
  for (T& x : w) x = make_weight<T>(in);
  const std::size_t split = n == 0 ? 0 : in.get<std::uint8_t>() % (n + 1);
  const T eps = T(in.get<std::uint8_t>()) / T(255);
  const std::vector<T> us = edge_and_input_us<T>(in);

  std::size_t first_bad = n;
  long double sum = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (first_bad == n && is_bad(w[i])) first_bad = i;
    sum += w[i];
  }
  if (first_bad < n) {
    check_rejects<vplkit::discrete_cdf<T>>("discrete_cdf", w, first_bad);
    check_rejects<vplkit::alias_table<T>>("alias_table", w, first_bad);
    // A rejected assign() leaves the object as it was (strong guarantee).
    const std::vector<T> good = {T(1), T(0), T(2)};
    vplkit::discrete_cdf<T> d(good);
    const std::vector<T> before = d.cdf();
    try {
      d.assign(w);
      VPLKIT_FUZZ_CHECK(!"assign accepted a bad weight");
    } catch (const vplkit::invalid_input&) {
    }
    VPLKIT_FUZZ_CHECK(d.cdf() == before && d.size() == 3);
    return;
  }
  // Valid weights: only a double sum past DBL_MAX may be refused (float sums are kept in double).
  // The structures are built from w as given; the checks compare them with the weights the
  // normal-range contract makes of w (a weight below the smallest normal T counts as 0).
  std::vector<T> wv(n);
  long double contract_sum = 0;
  for (std::size_t i = 0; i < n; ++i) {
    wv[i] = vplkit::detail::weight_value(w[i]);
    contract_sum += wv[i];
  }
  const long double dmax = std::numeric_limits<double>::max();
  try {
    const vplkit::discrete_cdf<T> d(w);
    VPLKIT_FUZZ_CHECK(sum <= dmax * 1.000001L);
    VPLKIT_FUZZ_CHECK(std::isfinite(d.sum()));
    check_cdf(d, wv, contract_sum, us);
    check_alias(vplkit::alias_table<T>(w), wv, contract_sum, us);
    check_compositions(w, split, eps, us);
  } catch (const vplkit::invalid_input& e) {
    VPLKIT_FUZZ_CHECK((std::is_same<T, double>::value));
    VPLKIT_FUZZ_CHECK(sum >= dmax * 0.999999L);
    VPLKIT_FUZZ_CHECK(std::string(e.what()).find("sum to more than") != std::string::npos);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  byte_reader in(data, size);
  if (in.get<std::uint8_t>() & 1)
    run<double>(in);
  else
    run<float>(in);
  return 0;
}
