// SPDX-License-Identifier: MIT
#pragma once
// Russian roulette between the front and the back paraboloid (paper Alg. 1, docs/math.md section
// 3): choose the front face with probability b_F = v_F / (v_F + v_B), v = the sum of a face's
// weights, then sample within that face's CDF. The probability of (face, t) is
// b_F * w_t / v_F = w_t / (v_F + v_B): the same as one CDF over both faces' weights.
//
// One u serves both decisions, as in the paper: u < b_F picks the front face and is rescaled to
// u * (1 / b_F), otherwise the back face gets (u - b_F) * (1 / b_B) with b_B = 1 - b_F. That is
// mixture_split with eps = b_F: the front face is the split's `fallback` side (u < eps), the back
// face its `learned` side, so the split of u is the library's one, not a copy. Written
// that way, b_F = 1 (back face empty) always picks the front, b_F = 0 always the back, and a
// back face whose share rounds away (b_B = 0) is never picked and reports pmf 0. The rescaling
// is monotone, so (up to its rounding) u maps to the same (face, index) as the concatenated CDF
// would. The reciprocals are computed once in double and rounded to T, so a sample uses only
// -, * and comparisons (correctly rounded in IEEE and in GLSL 4.x highp): a GPU mirror picks
// the same face and index bit for bit, which a GLSL division (2.5 ulp) would not promise.
#include <vplkit/core/normal_range.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/distribution/mixture_split.hpp>
#include <vplkit/distribution/weights.hpp>

#include <cstddef>
#include <limits>
#include <utility>

namespace vplkit {

template <class T>
struct face_sample {
  int face;           // 0 = front (d.z >= 0), 1 = back
  std::size_t index;  // within the face's distribution
  T pmf;              // probability of (face, index); 0 when the roulette is empty
};

// b_F from the two face totals, in double; 0 when both are 0 (the caller checks emptiness), and
// 0 when it is below the smallest normal T (the front face's share then counts as 0: the
// normal-range contract of weights.hpp).
template <class T>
inline T face_roulette_front_probability(T v_front, T v_back) noexcept {
  const double sum = double(v_front) + double(v_back);
  return sum > 0.0 ? flush_denormal(T(double(v_front) / sum)) : T(0);
}

template <class T>
class face_roulette {
public:
  using value_type = T;
  static constexpr int front_face = 0;
  static constexpr int back_face = 1;

  face_roulette() = default;

  // The faces may differ in size. A face may be empty (or default-constructed).
  face_roulette(discrete_cdf<T> front, discrete_cdf<T> back)
      : front_(std::move(front)), back_(std::move(back)) {
    // From the totals as T (what a GPU mirror has), unless one is +Inf (float weights summing
    // past FLT_MAX): then from the double sums, which keep the ratio the rounding lost.
    const bool overflowed = front_.total() > std::numeric_limits<T>::max() ||
                            back_.total() > std::numeric_limits<T>::max();
    b_front_ = overflowed ? flush_denormal(T(front_.sum() / (front_.sum() + back_.sum())))
                          : face_roulette_front_probability(front_.total(), back_.total());
    b_back_ = empty() ? T(0) : T(1) - b_front_;
    // b_F is already 0 for an empty front face, 1 for an empty back one, and flushed: the split's
    // effective eps is b_F itself, its scales 1 / b_F and 1 / (1 - b_F) (0 where never used).
    split_ = mixture_split<T>(b_front_, false, false);
  }

  // v_F + v_B == 0: sample() returns {0, 0, 0} and every pmf is 0.
  bool empty() const noexcept { return front_.empty() && back_.empty(); }
  // The roulette probabilities b_F and b_B = 1 - b_F (both 0 when empty).
  T front_probability() const noexcept { return b_front_; }
  T back_probability() const noexcept { return b_back_; }
  T face_probability(int face) const noexcept {
    return face == front_face ? b_front_ : face == back_face ? b_back_ : T(0);
  }
  const discrete_cdf<T>& front() const noexcept { return front_; }
  const discrete_cdf<T>& back() const noexcept { return back_; }
  const discrete_cdf<T>& face(int f) const noexcept { return f == front_face ? front_ : back_; }

  // b_face * pmf within the face; 0 for a face other than 0 / 1 or an index out of range. A
  // product below the smallest normal T becomes that value (see detail::probability_product): a
  // (face, index) the roulette can return never has pmf 0, on any device.
  T pmf(int face, std::size_t index) const noexcept {
    if (face == front_face) return detail::probability_product(b_front_, front_.pmf(index));
    if (face == back_face) return detail::probability_product(b_back_, back_.pmf(index));
    return T(0);
  }

  face_sample<T> sample(T u) const noexcept {
    if (empty()) return {front_face, 0, T(0)};
    const mixture_choice<T> c = split_.choose(u);
    if (c.component == mixture_fallback) {
      const std::size_t i = front_.sample(c.u).index;
      return {front_face, i, pmf(front_face, i)};
    }
    // Here b_back_ > 0 (u < 1 and u >= b_front_ = 1 - b_back_), so the learned scale is set.
    const std::size_t i = back_.sample(c.u).index;
    return {back_face, i, pmf(back_face, i)};
  }

  // 1 / b_F and 1 / b_B as T (0 where the face is never chosen), for a GPU mirror.
  T front_scale() const noexcept { return split_.fallback_scale(); }
  T back_scale() const noexcept { return empty() ? T(0) : split_.learned_scale(); }

private:
  discrete_cdf<T> front_;
  discrete_cdf<T> back_;
  T b_front_ = T(0);
  T b_back_ = T(0);
  mixture_split<T> split_;  // eps = b_F: fallback = the front face, learned = the back face
};

}  // namespace vplkit
