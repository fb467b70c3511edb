// SPDX-License-Identifier: MIT
#pragma once
// A face_roulette seen as one distribution over the flat DPRSM index (face * R * R + index within
// the face), with the sample(u) / pmf(i) interface of discrete_cdf, so every estimator takes it.
// The face CDFs must have R * R entries each (the faces of an R x R DPRSM).
#include <vplkit/distribution/discrete_sample.hpp>
#include <vplkit/distribution/face_roulette.hpp>

#include <cstddef>

namespace vplkit {

template <class T>
class flat_face_roulette {
public:
  using value_type = T;

  // Keeps a reference: `roulette` must outlive this adaptor.
  flat_face_roulette(const face_roulette<T>& roulette, int resolution)
      : roulette_(&roulette), face_size_(std::size_t(resolution) * std::size_t(resolution)) {}

  std::size_t size() const noexcept { return 2 * face_size_; }
  bool empty() const noexcept { return roulette_->empty(); }

  // b_face * pmf within the face (face_roulette::pmf): w_t / (v_F + v_B).
  T pmf(std::size_t flat) const noexcept {
    if (face_size_ == 0) return T(0);
    return roulette_->pmf(int(flat / face_size_), flat % face_size_);
  }

  // The paper's Alg. 1 with one u (face_roulette::sample); the index is flattened.
  discrete_sample<T> sample(T u) const noexcept {
    const face_sample<T> s = roulette_->sample(u);
    return {std::size_t(s.face) * face_size_ + s.index, s.pmf};
  }

private:
  const face_roulette<T>* roulette_;
  std::size_t face_size_;
};

}  // namespace vplkit
