// SPDX-License-Identifier: MIT
#include "voxelize_gpu.hpp"

#include "compute.hpp"

#include <vplkit/core/error.hpp>
#include <vplkit/visibility/prefix_sum_params.h>
#include <vplkit/visibility/voxel_rank.hpp>
#include <vplkit/visibility/voxelize.hpp>
#include <vplkit/visibility/voxelize_params.h>
#include <vplkit/visibility/voxelize_triangles.hpp>

#include <glm/vec4.hpp>

#include <map>
#include <string>

namespace vplkit::gl {

namespace {

// The kernels, compiled once per process and variant.
const program& pack_program(const std::string& rel, const std::string& defines) {
  static std::map<std::string, program> cache;
  const std::string key = rel + "|" + defines;
  auto it = cache.find(key);
  if (it != cache.end()) return it->second;
  program p = program::compute_with_includes("#version 430\n#include \"" + rel + "\"\n", rel, {}, defines);
  return cache.emplace(key, std::move(p)).first->second;
}

// A parameter block: a buffer bound to the uniform target.
buffer uniform_block(const void* data, std::size_t bytes, GLuint binding) {
  buffer b = buffer::from_bytes(data, bytes);
  glBindBufferBase(GL_UNIFORM_BUFFER, binding, b.id());
  check_gl("glBindBufferBase(GL_UNIFORM_BUFFER)");
  return b;
}

// The pieces every mode shares: the mesh, the parameter block, the dispatch shape.
struct voxelize_job {
  buffer positions, indices;
  gpu::voxelize_params params{};
  GLuint gx = 1, gy = 1;
  std::size_t words = 0;
};

voxelize_job make_job(const gpu_voxelize_input& in) {
  if (in.positions == nullptr || in.indices == nullptr) throw invalid_input("voxelize_on_gpu: null mesh");
  // What vplkit::voxelize validates (it throws naming the first bad triangle), checked up front.
  validate_triangle_mesh(in.positions->data(), in.positions->size(), in.indices->data(), in.indices->size(),
                         "voxelize_on_gpu");
  voxel_grid<float> shape(in.bounds_min, in.bounds_max, in.resolution);  // validates bounds, resolution
  if (!(in.margin_voxels >= 0.0f) || !(in.margin_voxels < 0.5f))
    throw invalid_input("voxelize_on_gpu: margin_voxels must be in [0, 0.5)");
  voxelize_job j;
  std::vector<glm::vec4> pos;
  pos.reserve(in.positions->size() + 1);
  for (const glm::vec3& p : *in.positions) pos.emplace_back(p, 1.0f);
  if (pos.empty()) pos.emplace_back(0.0f);
  std::vector<std::uint32_t> idx = *in.indices;
  if (idx.empty()) idx.push_back(0u);
  j.positions = buffer::from_vector(pos);
  j.indices = buffer::from_vector(idx);
  j.params.bounds_min = glm::vec4(in.bounds_min, 0.0f);
  j.params.bounds_max = glm::vec4(in.bounds_max, 0.0f);
  j.params.resolution = glm::ivec4(in.resolution, 0);
  const std::uint32_t tris = std::uint32_t(in.indices->size() / 3);
  j.params.triangle_count = tris;
  j.params.margin_voxels = in.margin_voxels;
  // One work group per triangle (voxelize.comp's dispatch rule), spread over y past 65535.
  const GLuint groups = tris > 0 ? tris : 1u;
  j.gx = groups > 65535u ? 65535u : groups;
  j.gy = (groups + j.gx - 1) / j.gx;
  j.words = shape.word_count();
  return j;
}

void run_voxelize(const voxelize_job& j, int mode) {
  const program& p = pack_program("vplkit/visibility/voxelize.comp",
                                  "#define VPLKIT_VOXELIZE_MODE " + std::to_string(mode) + "\n");
  const buffer ub = uniform_block(&j.params, sizeof j.params, VPLKIT_VOXELIZE_BINDING_PARAMS);
  j.positions.bind(VPLKIT_VOXELIZE_BINDING_POSITIONS);
  j.indices.bind(VPLKIT_VOXELIZE_BINDING_INDICES);
  dispatch(p, j.gx, j.gy);
}

// Exclusive prefix sum of `count` uints of `in` into `out` (with out[count] = total when
// write_total); returns the total.
std::uint32_t run_prefix_sum(const buffer& in, const buffer& out, std::size_t count, bool bit_count, bool write_total) {
  const program& p = pack_program("vplkit/visibility/prefix_sum.comp", "");
  const std::size_t chunk = std::size_t(VPLKIT_PREFIX_SUM_LOCAL_SIZE) * VPLKIT_PREFIX_SUM_PER_INVOCATION;
  buffer carry = buffer::filled(4, 0);
  in.bind(VPLKIT_PREFIX_SUM_BINDING_INPUT);
  out.bind(VPLKIT_PREFIX_SUM_BINDING_OUTPUT);
  carry.bind(VPLKIT_PREFIX_SUM_BINDING_CARRY);
  for (std::size_t begin = 0; begin == 0 || begin < count; begin += chunk) {
    const gpu::prefix_sum_params params{std::uint32_t(count), std::uint32_t(begin), bit_count ? 1u : 0u,
                                   write_total ? 1u : 0u};
    const buffer ub = uniform_block(&params, sizeof params, VPLKIT_PREFIX_SUM_BINDING_PARAMS);
    dispatch(p, 1);
  }
  return carry.read<std::uint32_t>(1)[0];
}

}  // namespace

std::vector<std::uint32_t> prefix_sum_on_gpu(const std::vector<std::uint32_t>& in, std::size_t count, bool bit_count,
                                             bool write_total) {
  if (count > in.size()) throw invalid_input("prefix_sum_on_gpu: count exceeds the input");
  std::uint64_t total = 0;
  for (std::size_t i = 0; i < count; ++i) total += bit_count ? std::uint64_t(voxel_bit_count(in[i])) : in[i];
  if (total > 0xFFFFFFFFull) throw invalid_input("prefix_sum_on_gpu: the total exceeds 32 bits");
  std::vector<std::uint32_t> padded = in;
  if (padded.empty()) padded.push_back(0u);
  const buffer b_in = buffer::from_vector(padded);
  const buffer b_out = buffer::filled((count + 1) * 4, 0xFF);
  run_prefix_sum(b_in, b_out, count, bit_count, write_total);
  return b_out.read<std::uint32_t>(count + (write_total ? 1 : 0));
}

// Compiled before the timers start, so that they time the dispatches only.
void compile_voxelize_programs(bool lists) {
  for (int mode = 0; mode <= (lists ? 2 : 0); ++mode)
    pack_program("vplkit/visibility/voxelize.comp", "#define VPLKIT_VOXELIZE_MODE " + std::to_string(mode) + "\n");
  if (lists) pack_program("vplkit/visibility/prefix_sum.comp", "");
}

voxel_grid<float> voxelize_on_gpu(const gpu_voxelize_input& in, double* ms) {
  voxelize_job j = make_job(in);
  compile_voxelize_programs(false);
  buffer words = buffer::filled(j.words * 4, 0);
  words.bind(VPLKIT_VOXELIZE_BINDING_WORDS);
  timer_query tq;
  tq.begin();
  run_voxelize(j, 0);
  tq.end();
  if (ms) *ms = tq.milliseconds();
  return voxel_grid<float>(in.bounds_min, in.bounds_max, in.resolution, words.read<std::uint32_t>(j.words));
}

triangle_voxel_grid<float> voxelize_triangles_on_gpu(const gpu_voxelize_input& in, double* ms) {
  voxelize_job j = make_job(in);
  compile_voxelize_programs(true);
  buffer words = buffer::filled(j.words * 4, 0);
  buffer rank = buffer::filled(j.words * 4, 0);
  timer_query tq;
  tq.begin();
  words.bind(VPLKIT_VOXELIZE_BINDING_WORDS);
  run_voxelize(j, 0);
  const std::uint32_t occupied = run_prefix_sum(words, rank, j.words, true, false);
  // counts (occupied) -> offsets (occupied + 1); the same buffer then serves as the cursors.
  buffer counts = buffer::filled((std::size_t(occupied) + 1) * 4, 0);
  buffer offsets = buffer::filled((std::size_t(occupied) + 1) * 4, 0);
  words.bind(VPLKIT_VOXELIZE_BINDING_WORDS);
  rank.bind(VPLKIT_VOXELIZE_BINDING_RANK);
  counts.bind(VPLKIT_VOXELIZE_BINDING_COUNTS);
  run_voxelize(j, 1);
  const std::uint32_t entries_total = run_prefix_sum(counts, offsets, occupied, false, true);
  buffer zero_cursors = buffer::filled((std::size_t(occupied) + 1) * 4, 0);
  buffer entries = buffer::filled((std::size_t(entries_total) + 1) * 4, 0xFF);
  words.bind(VPLKIT_VOXELIZE_BINDING_WORDS);
  rank.bind(VPLKIT_VOXELIZE_BINDING_RANK);
  zero_cursors.bind(VPLKIT_VOXELIZE_BINDING_COUNTS);
  offsets.bind(VPLKIT_VOXELIZE_BINDING_OFFSETS);
  entries.bind(VPLKIT_VOXELIZE_BINDING_ENTRIES);
  run_voxelize(j, 2);
  tq.end();
  if (ms) *ms = tq.milliseconds();
  voxel_grid<float> occ(in.bounds_min, in.bounds_max, in.resolution, words.read<std::uint32_t>(j.words));
  return triangle_voxel_grid<float>(
      std::move(occ), rank.read<std::uint32_t>(j.words), offsets.read<std::uint32_t>(std::size_t(occupied) + 1),
      entries.read<std::uint32_t>(entries_total),
      make_voxel_triangles(in.positions->data(), in.positions->size(), in.indices->data(), in.indices->size()));
}

}  // namespace vplkit::gl
