// SPDX-License-Identifier: MIT
// speed_vs_error's three references (the exhaustive VPL sum, converged gathering, the exact ground
// truth), each computed once and kept as an EXR in --cache-dir under a hash of everything it
// depends on, so later sweeps of the same frame read it instead of computing it again.
#pragma once

#include "cli/render_options.hpp"

#include <cstdint>
#include <string>

namespace speed_vs_error {

// The gathering reference's seed: fixed and far from the usual sweep seeds, so the reference's
// random streams are independent of the runs it judges.
constexpr std::uint32_t k_gather_reference_seed = 0x5EED0F1Eu;
// The exact reference's seed, for the same reason.
constexpr std::uint32_t k_exact_reference_seed = 0x5EED0E4Au;
// The seeds of the second, independent renders of the gathering and exact references, made only to
// measure their noise (metrics.hpp, estimate_noise; --ref-noise).
constexpr std::uint32_t k_gather_reference_noise_seed = 0x5EED2F1Eu;
constexpr std::uint32_t k_exact_reference_noise_seed = 0x5EED2E4Au;
// The patch VPL sum's seed (its jitter; --vpl-mode point draws nothing), for the same reason.
constexpr std::uint32_t k_vplsum_reference_seed = 0x5EED0A50u;

struct reference_image {
  vplrender::image_rgb img;
  std::string path;
  bool hit = false;
  double ms = 0.0;  // time to compute it (0 on a cache hit)
};

// Everything a reference image depends on (the scene as prepared: camera and light after framing).
// kind is "vplsum", "gather" or "exact"; dirs and seed count for gather and exact (seed also for a
// patch VPL sum).
std::string reference_key(const vplrender::options& o, const vplrender::prepared_scene& p, const std::string& kind,
                          int dirs, std::uint32_t seed);

// The reference from the cache when there (and of the frame's size), else computed on b and
// written there. Prints the hit or miss. output_error when cache_dir cannot be created.
reference_image get_reference(const vplrender::options& base, const vplrender::prepared_scene& p,
                              const vplrender::frame_buffers& b, const std::string& cache_dir, const std::string& kind,
                              int dirs, std::uint32_t seed);

}  // namespace speed_vs_error
