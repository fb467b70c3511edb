// SPDX-License-Identifier: MIT
#pragma once
// Linear HDR output as OpenEXR: 32-bit float R, G, B (half would clip at 65504 and round at
// 1e-3 relative, too coarse for error measurements), ZIP compression (lossless).
#include "io/image.hpp"
#include "io/output_set.hpp"

#include <string>
#include <utility>
#include <vector>

namespace vplrender {

// Refuses non-finite pixels (output_error) before touching the disk; writes atomically.
// `attributes` become string attributes of the EXR header (parameters, for provenance).
void write_exr(const std::string& path, const image_rgb& img,
               const std::vector<std::pair<std::string, std::string>>& attributes = {});
// The same into `set`: on disk under `path` once the set is published.
void write_exr(output_set& set, const std::string& path, const image_rgb& img,
               const std::vector<std::pair<std::string, std::string>>& attributes = {});

// Reads R, G and B (half, float or uint channels, converted to float) from any scan-line or tiled
// EXR. Throws input_error if the file cannot be read or lacks one of the channels.
image_rgb read_exr(const std::string& path);

}  // namespace vplrender
