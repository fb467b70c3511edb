// SPDX-License-Identifier: MIT
#pragma once
// A list of n items cut into chunks and worked on by all cores, chunks taken in turn: what the
// per-frame DPRSM mesh (raster/tessellate.hpp, raster/dprsm_mesh.hpp) runs on. Several chunks per
// thread, since the work per item is uneven (triangles near the light split the most).
#include <cstddef>
#include <functional>

namespace vplrender {

struct chunk_plan {
  std::size_t chunk = 1;    // items per chunk (the last one may hold fewer)
  std::size_t chunks = 0;   // ceil(n / chunk)
  std::size_t threads = 1;  // threads to run them on: min(hardware threads, chunks), at least 1
  std::size_t begin(std::size_t c, std::size_t n) const { return c * chunk < n ? c * chunk : n; }
  std::size_t end(std::size_t c, std::size_t n) const { return (c + 1) * chunk < n ? (c + 1) * chunk : n; }
};

// Four chunks per hardware thread; a list of few items (cornell's 36 triangles) gets one item per chunk.
chunk_plan plan_chunks(std::size_t n);

// work(c) for every chunk c of the plan, on plan.threads threads (this one among them). Rethrows the
// first exception a chunk threw, after every thread has stopped.
void run_chunks(const chunk_plan& plan, const std::function<void(std::size_t)>& work);

}  // namespace vplrender
