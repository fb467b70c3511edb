// SPDX-License-Identifier: MIT
#pragma once
// The junction band (docs/results/clamp_compensation.md): the pixels whose gather point lies within a
// given distance of another surface, where the VPL clamp and the patch VPLs' edge texels act. One
// mask per frame, the same for every method and reference, and reproducible: pixel p is in the band
// when one of the 32 x 32 midpoint directions of the cosine hemisphere around its geometric normal
// (sample_cosine_hemisphere of ((i + 0.5) / 32, (j + 0.5) / 32)) meets a triangle within `radius`
// of its gather point, traced with the frame's exact rays (Embree). A flat surface away from
// others has no such hit: its own plane lies below every direction.
#include "io/image.hpp"
#include "render/frame_buffers.hpp"

#include <cstdint>
#include <vector>

namespace speed_vs_error {

// 1 for the pixels in the band, 0 elsewhere (background pixels included); needs the frame's exact
// rays (frame_settings::exact_rays), else invalid_input.
std::vector<std::uint8_t> junction_band(const vplrender::frame_buffers& b, float radius);

// The mean over the band's pixels and the three channels; NaN for an empty band.
double band_mean(const vplrender::image_rgb& img, const std::vector<std::uint8_t>& band);

}  // namespace speed_vs_error
