// SPDX-License-Identifier: MIT
#pragma once
// Shared by the tests of the estimators' range forms (not part of the library): the synthetic
// room with two local VPL distributions, and the check that an estimate spread over ranges of its
// samples gives the one-shot estimate bit for bit with the stream at the same counter.
#include <float_bits.hpp>
#include <synthetic_scene.hpp>

#include <vplkit/builders/vpl_distribution.hpp>
#include <vplkit/estimators/estimator_state.hpp>
#include <vplkit/estimators/mis_estimator.hpp>
#include <vplkit/vpl/luminance.hpp>

#include <catch2/catch.hpp>

#include <cstdint>
#include <initializer_list>
#include <utility>
#include <vector>

namespace vplkit_test {

// The room at DPRSM resolution R and two local distributions (eps 0.1) over it: the first CDF's
// weight of texel t is first(t, lum), the second's second(t, lum), lum the VPL's luminance.
// Holes in the second make the mixture's fallback matter.
template <class T>
struct room_with_local_dists : lit_room<T> {
  std::vector<vplkit::defensive_mixture<T>> dists;
  template <class First, class Second>
  room_with_local_dists(int R, First&& first, Second&& second) : lit_room<T>(R) {
    const std::size_t n = std::size_t(this->view.texel_count());
    std::vector<T> flat(2 * n);
    for (std::size_t t = 0; t < n; ++t) {
      const T lum = vplkit::luminance(this->view.vpl_at(int(t)).flux);
      flat[t] = first(t, lum);
      flat[n + t] = second(t, lum);
    }
    dists = vplkit::make_local_vpl_distributions(flat, 2, this->view, T(0.1));
  }
};

// Cuts of [0, n): one range, every sample its own range, and `uneven` (empty pieces allowed).
inline std::vector<std::vector<int>> cuts_of(int n, std::vector<int> uneven) {
  std::vector<std::vector<int>> cuts = {{0, n}};
  std::vector<int> each;
  for (int k = 0; k <= n; ++k) each.push_back(k);
  cuts.push_back(each);
  cuts.push_back(std::move(uneven));
  return cuts;
}

// Runs `range(state, begin, end)` over each cut, from the stream (key, counter) the one-shot
// starts from, and checks the finished estimate and the stream against the one-shot's.
template <class T, class OneShot, class Range, class Finish>
void check_splits(vplkit::counter_rng start, const std::vector<std::vector<int>>& cuts, OneShot&& one_shot,
                  Range&& range, Finish&& finish) {
  vplkit::counter_rng rng = start;
  const vec3<T> expected = one_shot(rng);
  for (const std::vector<int>& cut : cuts) {
    vplkit::estimator_state<T> state = vplkit::make_estimator_state<T>(start);
    for (std::size_t k = 0; k + 1 < cut.size(); ++k) range(state, cut[k], cut[k + 1]);
    INFO("pieces " << cut.size() - 1);
    CHECK(same_bits(finish(state), expected));
    CHECK(state.rng.counter == rng.counter);
  }
}

// Both MIS modes with each (n_dirs, n_vpls) of `counts`: check(mode, n_dirs, n_vpls), named in INFO.
template <class Check>
void for_each_mis_case(std::initializer_list<std::pair<int, int>> counts, Check&& check) {
  for (const vplkit::mis_mode mode : {vplkit::mis_mode::solid_angle, vplkit::mis_mode::as_published})
    for (const std::pair<int, int>& c : counts) {
      INFO("MIS, mode " << int(mode) << ", " << c.first << " directions, " << c.second << " VPLs");
      check(mode, c.first, c.second);
    }
}

}  // namespace vplkit_test
