// SPDX-License-Identifier: MIT
#pragma once
// Local weights (paper 5.2, docs/math.md section 4): the image is split into an rx x ry grid of
// regions (N = rx * ry; the paper's N = 4 is 2 x 2), and region i gets its own weight array, built
// exactly like the global weights (global_weights.hpp) from a stratified subset S_i of the region's
// pixels.
//
// Region grid: column c covers x in [floor(c W / rx), floor((c + 1) W / rx)), row r likewise with
// H and ry; region index i = r * rx + c (row-major). With rx <= W and ry <= H every region holds
// at least one pixel and every pixel lies in exactly one region.
//
// Storage: one flat array of N * 2 R^2 weights, region-major: weights[i * 2 R^2 + t] is texel t's
// weight in region i (the layout of one GPU buffer holding the N weight arrays one after another).
//
// Random numbers: region i's subset is stratified_gather_subset(rect_i, count, seed,
// stream_offset = i * count): stratum k of region i uses stream i * count + k, so no two strata of
// one build share a stream.
#include <vplkit/builders/gather_subset.hpp>
#include <vplkit/builders/global_weights.hpp>
#include <vplkit/core/error.hpp>
#include <vplkit/core/gather_point.hpp>
#include <vplkit/vpl/dprsm_view.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace vplkit {

// Column (or row) of pixel coordinate p in [0, extent) when [0, extent) is cut into n parts at
// floor(k * extent / n): the largest c with floor(c * extent / n) <= p, i.e.
// c = ceil((p + 1) n / extent) - 1 = ((p + 1) n - 1) / extent. Integer only (GLSL: the same).
inline int region_band_of(int p, int extent, int n) { return ((p + 1) * n - 1) / extent; }

// Region index of pixel (x, y) in a width x height image cut into rx x ry regions (row-major).
// Plain function for shaders; assumes 0 <= x < width, 0 <= y < height, 1 <= rx <= width,
// 1 <= ry <= height.
inline int region_of_pixel(int x, int y, int width, int height, int rx, int ry) {
  return region_band_of(y, height, ry) * rx + region_band_of(x, width, rx);
}

struct image_regions {
  int width = 0;
  int height = 0;
  int rx = 2;  // regions across
  int ry = 2;  // regions down

  image_regions() = default;

  // Throws invalid_input unless 1 <= width, height <= 32768 (the G-buffer limit), 1 <= rx <= width
  // and 1 <= ry <= height (an empty region would have no pixel to learn from).
  image_regions(int width_, int height_, int rx_ = 2, int ry_ = 2)
      : width(width_), height(height_), rx(rx_), ry(ry_) {
    if (width < 1 || height < 1 || width > (1 << 15) || height > (1 << 15))
      throw invalid_input("image_regions: image size " + std::to_string(width) + " x " +
                          std::to_string(height) + " is not in [1, 32768]^2");
    if (rx < 1 || ry < 1 || rx > width || ry > height)
      throw invalid_input("image_regions: " + std::to_string(rx) + " x " + std::to_string(ry) +
                          " regions do not fit a " + std::to_string(width) + " x " +
                          std::to_string(height) + " image (need 1 <= rx <= width, 1 <= ry <= "
                          "height)");
  }

  int count() const { return rx * ry; }

  int region_of_pixel(int x, int y) const {
    return vplkit::region_of_pixel(x, y, width, height, rx, ry);
  }

  // Pixel rectangle of region i (0 <= i < count()).
  pixel_rect region_rect(int i) const {
    const int r = i / rx, c = i - (i / rx) * rx;
    const int xa = c * width / rx, xb = (c + 1) * width / rx;
    const int ya = r * height / ry, yb = (r + 1) * height / ry;
    return pixel_rect{xa, ya, xb - xa, yb - ya};
  }
};

// Regions of a G-buffer's image.
template <class T>
inline image_regions make_image_regions(const gbuffer_view<T>& gbuffer, int rx = 2, int ry = 2) {
  return image_regions(gbuffer.width, gbuffer.height, rx, ry);
}

// The stratified subsets S_i of every region (count strata each; see gather_subset.hpp for how
// background strata drop), as flat pixel indices. Throws like stratified_gather_subset, and when
// the regions do not describe the G-buffer's image.
template <class T>
inline std::vector<std::vector<int>> local_gather_subsets(const gbuffer_view<T>& gbuffer,
                                                          const image_regions& regions, int count,
                                                          std::uint32_t seed,
                                                          int max_attempts = gather_subset_default_attempts) {
  gbuffer.validate();
  if (regions.width != gbuffer.width || regions.height != gbuffer.height)
    throw invalid_input("local_gather_subsets: regions are for a " + std::to_string(regions.width) +
                        " x " + std::to_string(regions.height) + " image, the G-buffer is " +
                        std::to_string(gbuffer.width) + " x " + std::to_string(gbuffer.height));
  if (count < 0)
    throw invalid_input("local_gather_subsets: count " + std::to_string(count) + " is negative");
  std::vector<std::vector<int>> subsets(std::size_t(regions.count()));
  for (int i = 0; i < regions.count(); ++i)
    subsets[std::size_t(i)] = stratified_gather_subset(
        gbuffer, regions.region_rect(i), count, seed,
        std::uint32_t(i) * std::uint32_t(count), max_attempts);
  return subsets;
}

// N weight arrays (region-major, N * 2 R^2 entries) into `weights`, from per-region subsets
// (e.g. local_gather_subsets). subsets.size() must equal regions.count(); subset_sizes (optional,
// N entries) receives each |S_i| (valid gather points used). A region whose subset has no valid
// gather point gets an all-zero array: an empty distribution (see make_vpl_distribution).
// Throws like build_global_weights and for mismatched sizes.
// Cost: sum_i |S_i| x (texels carrying a VPL) contribution evaluations.
template <class T>
inline void build_local_weights(const gbuffer_view<T>& gbuffer, const image_regions& regions,
                                const std::vector<std::vector<int>>& subsets,
                                const dprsm_view<T>& view, T dmin, T* weights,
                                std::size_t weights_size, int* subset_sizes = nullptr) {
  const char* who = "build_local_weights";
  view.validate();
  const std::size_t per = std::size_t(view.texel_count());
  const std::size_t n = std::size_t(regions.count());
  if (subsets.size() != n)
    throw invalid_input(std::string(who) + ": " + std::to_string(subsets.size()) +
                        " subsets for " + std::to_string(n) + " regions");
  if (weights_size != n * per)
    throw invalid_input(std::string(who) + ": weights span has " + std::to_string(weights_size) +
                        " entries, expected N * 2 R^2 = " + std::to_string(n * per));
  if (weights == nullptr) throw invalid_input(std::string(who) + ": null weights pointer");
  for (std::size_t i = 0; i < n; ++i) {
    const int used = build_global_weights(gbuffer, subsets[i].data(), subsets[i].size(), view,
                                          dmin, weights + i * per, per);
    if (subset_sizes != nullptr) subset_sizes[i] = used;
  }
}

// Convenience: subsets and weights in one call; returns the flat N * 2 R^2 array.
template <class T>
inline std::vector<T> build_local_weights(const gbuffer_view<T>& gbuffer,
                                          const image_regions& regions, int count_per_region,
                                          std::uint32_t seed, const dprsm_view<T>& view, T dmin) {
  view.validate();
  const std::vector<std::vector<int>> subsets =
      local_gather_subsets(gbuffer, regions, count_per_region, seed);
  std::vector<T> w(std::size_t(regions.count()) * std::size_t(view.texel_count()), T(0));
  build_local_weights(gbuffer, regions, subsets, view, dmin, w.data(), w.size());
  return w;
}

}  // namespace vplkit
