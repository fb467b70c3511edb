// SPDX-License-Identifier: MIT
#include "render/gpu/gpu_cdf.hpp"

#include "render/gpu/dprsm_view_uniforms.hpp"

#include <vplkit/core/error.hpp>
#include <vplkit/core/float_bits.hpp>
#include <vplkit/distribution/cdf_build_params.h>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/distribution/mixture_split.hpp>

#include <algorithm>
#include <string>

#ifndef VPLRENDER_SHADER_DIR
#error "VPLRENDER_SHADER_DIR must name examples/vplrender/shaders (set by core.cmake)"
#endif

namespace vplrender {

namespace {

namespace gl = vplkit::gl;

constexpr std::size_t cdf_block = VPLKIT_CDF_BUILD_BLOCK;  // weights per block (the kernel's defaults)

}  // namespace

gpu_cdf_set build_cdf_set_gpu(const gl::buffer& weights, std::size_t dists, std::size_t n, std::size_t extra_words) {
  if (dists < 1 || n < 1) throw vplkit::invalid_input("build_cdf_set_gpu: no weights (" + std::to_string(dists) + " arrays of " + std::to_string(n) + ")");
  if (weights.size_bytes() < dists * n * sizeof(float))
    throw vplkit::invalid_input("build_cdf_set_gpu: the weight buffer holds fewer than " + std::to_string(dists) +
                                " x " + std::to_string(n) + " floats");
  const std::size_t m = vplkit::discrete_guide_size(n);
  // One buffer: all cdfs, then (at an offset the SSBO binding rules allow) all guides, then the
  // caller's words; cdf_build.comp writes the first two through range bindings, so nothing is copied.
  GLint align = 1;
  glGetIntegerv(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, &align);
  const std::size_t align_u = std::max<std::size_t>(1, static_cast<std::size_t>(std::max(align, 4)) / 4);
  const auto aligned = [&](std::size_t w) { return (w + align_u - 1) / align_u * align_u; };
  const std::size_t cdf_words = dists * (n + 1);
  const std::size_t guide_words = dists * (m + 1);
  const std::size_t blocks = (n + cdf_block - 1) / cdf_block;

  gpu_cdf_set out;
  out.n = n;
  out.m = m;
  out.guide_base = aligned(cdf_words);
  out.extra_base = aligned(out.guide_base + guide_words);
  out.data = gl::buffer::filled((out.extra_base + extra_words) * 4, 0);
  gl::buffer b_blocks =
      gl::buffer::filled(std::max<std::size_t>(1, dists * blocks) * sizeof(vplkit::gpu::cdf_build_block), 0);
  gl::buffer b_info = gl::buffer::filled(dists * sizeof(vplkit::gpu::cdf_build_info), 0);
  gl::buffer b_params = gl::buffer::filled(sizeof(vplkit::gpu::cdf_build_params), 0);
  weights.bind(VPLKIT_CDF_BUILD_BINDING_WEIGHTS);
  glBindBufferRange(GL_SHADER_STORAGE_BUFFER, VPLKIT_CDF_BUILD_BINDING_CDF, out.data.id(), 0,
                    static_cast<GLsizeiptr>(cdf_words * 4));
  glBindBufferRange(GL_SHADER_STORAGE_BUFFER, VPLKIT_CDF_BUILD_BINDING_GUIDE, out.data.id(),
                    static_cast<GLintptr>(out.guide_base * 4), static_cast<GLsizeiptr>(guide_words * 4));
  b_blocks.bind(VPLKIT_CDF_BUILD_BINDING_BLOCKS);
  b_info.bind(VPLKIT_CDF_BUILD_BINDING_INFO);
  glBindBufferBase(GL_UNIFORM_BUFFER, VPLKIT_CDF_BUILD_BINDING_PARAMS, b_params.id());
  gl::check_gl("cdf_build.comp bindings");
  // cdf_build.comp strides its blocks over gl_NumWorkGroups.x: any count up to the axis limit works.
  const std::size_t max_x = gl::max_work_group_count(0);
  const GLuint groups = static_cast<GLuint>(std::min<std::size_t>(std::max<std::size_t>(blocks, 1), max_x));
  const GLuint guide_groups = static_cast<GLuint>(std::min<std::size_t>((m + 1 + cdf_block - 1) / cdf_block, max_x));
  // One program per pass (VPLKIT_CDF_BUILD_PASS): the parameter block is written once, and each
  // program holds one pass's code only (fewer registers on a GPU). The passes
  // cdf_build_pass_needed names: 1, 3, 5 (5 writes the guide), and 2 and 4 only when the blocks
  // span several chunks (n > 2^20): three dependent dispatches for a 2 x 512^2 DPRSM.
  vplkit::gpu::cdf_build_params params{};
  params.n = static_cast<std::uint32_t>(n);
  b_params.write_bytes(&params, 0, sizeof params);
  for (std::uint32_t pass = 1; pass <= 6; ++pass) {
    if (!vplkit::gpu::cdf_build_pass_needed(pass, params.n)) continue;
    const gl::program& cp = gl::cached_kernel("vplkit/distribution/cdf_build.comp",
                                              "#define VPLKIT_CDF_BUILD_PASS " + std::to_string(pass) + "\n");
    gl::dispatch(cp, pass == 2 || pass == 4 ? 1 : pass == 6 ? guide_groups : groups, 1, static_cast<GLuint>(dists));
  }
  // The only read-back: the totals (16 bytes per distribution).
  std::vector<vplkit::gpu::cdf_build_info> info(dists);
  b_info.read_bytes(info.data(), 0, dists * sizeof(vplkit::gpu::cdf_build_info));
  for (const vplkit::gpu::cdf_build_info& i : info) {
    out.totals.push_back(i.total);
    out.zeroed.push_back(static_cast<long long>(i.zeroed));
  }
  return out;
}

gpu_mixtures build_mixtures_gpu(const gl::buffer& weights, int D, const gl::buffer& dprsm,
                                const vplkit::dprsm_view<float>& view, float eps, stage_timer& timer,
                                nlohmann::json& det) {
  auto running = stage_timer::running("cdf (gpu)");
  if (!(eps >= 0.0f && eps <= 1.0f))
    throw vplkit::invalid_input("build_mixtures_gpu: eps = " + std::to_string(eps) + " is outside [0, 1]");
  if (D < 1) throw vplkit::invalid_input("build_mixtures_gpu: no weight arrays");
  const std::size_t n = static_cast<std::size_t>(view.texel_count());
  const bool with_fallback = eps > 0.0f;
  const std::size_t dists = static_cast<std::size_t>(D) + (with_fallback ? 1u : 0u);
  if (weights.size_bytes() < (static_cast<std::size_t>(D) + 1) * n * sizeof(float))
    throw vplkit::invalid_input("build_mixtures_gpu: weight buffer holds fewer than (D + 1) 2 R^2 floats");

  gl::timer_query tq;
  tq.begin();
  if (with_fallback) {
    const gl::program& fp = gl::cached_kernel(std::string(VPLRENDER_SHADER_DIR) + "/vpl_fallback_weights.comp");
    set_dprsm_view_uniforms(fp, view.resolution, view.light);
    glUniform1ui(fp.uniform_location("u_offset"), static_cast<GLuint>(static_cast<std::size_t>(D) * n));
    gl::check_gl("vpl_fallback_weights.comp uniforms");
    dprsm.bind(0);
    weights.bind(1);
    gl::dispatch_linear(fp, gl::groups_for(n, 64));
  }
  gpu_cdf_set set = build_cdf_set_gpu(weights, dists, n, 0);
  const std::size_t m = set.m;
  gpu_mixtures out;
  out.count = D;
  out.n = n;
  out.m = m;
  out.data = std::move(set.data);
  const std::vector<float>& totals = set.totals;

  // Mixture d: slot 2d (learned d) and 2d + 1 (the shared fallback); every slot stores the uint
  // offsets of its cdf and guide in `data`.
  for (std::size_t k = 0; k < dists; ++k) {
    out.cdf_offset.push_back(k * (n + 1));
    out.guide_offset.push_back(set.guide_base + k * (m + 1));
    out.totals.push_back(totals[k]);
  }
  const vplkit::discrete_cdf<float> no_fallback;  // eps = 0: size 0 (make_vpl_distribution)
  const float fb_total = with_fallback ? totals[static_cast<std::size_t>(D)] : 0.0f;
  const std::uint32_t fb_size = with_fallback ? static_cast<std::uint32_t>(n) : 0u;
  const std::uint32_t fb_m = with_fallback ? static_cast<std::uint32_t>(m)
                                           : static_cast<std::uint32_t>(no_fallback.guide_size());
  std::vector<std::uint32_t> meta, slots;
  long long zeroed = 0;
  for (int d = 0; d < D; ++d) {
    const float total = totals[static_cast<std::size_t>(d)];
    zeroed += set.zeroed[static_cast<std::size_t>(d)];
    // The defensive_mixture constructor's split, on the totals (empty() is total == 0).
    const vplkit::mixture_split<float> split(eps, total == 0.0f, fb_total == 0.0f);
    const float e = split.effective_eps(), fs = split.fallback_scale(), ls = split.learned_scale();
    out.effective_eps.push_back(e);
    out.fallback_scale.push_back(fs);
    out.learned_scale.push_back(ls);
    const std::uint32_t rec[12] = {static_cast<std::uint32_t>(2 * d),
                                   static_cast<std::uint32_t>(n),
                                   static_cast<std::uint32_t>(m),
                                   vplkit::float_bits(total),
                                   static_cast<std::uint32_t>(2 * d + 1),
                                   fb_size,
                                   fb_m,
                                   vplkit::float_bits(fb_total),
                                   vplkit::float_bits(e),
                                   vplkit::float_bits(fs),
                                   vplkit::float_bits(ls),
                                   0u};
    meta.insert(meta.end(), rec, rec + 12);
    const std::size_t fb = with_fallback ? static_cast<std::size_t>(D) : 0u;  // eps = 0: never read
    slots.push_back(static_cast<std::uint32_t>(out.cdf_offset[static_cast<std::size_t>(d)]));
    slots.push_back(static_cast<std::uint32_t>(out.guide_offset[static_cast<std::size_t>(d)]));
    slots.push_back(static_cast<std::uint32_t>(out.cdf_offset[fb]));
    slots.push_back(static_cast<std::uint32_t>(out.guide_offset[fb]));
  }
  out.slot_base = static_cast<std::uint32_t>(meta.size());
  meta.insert(meta.end(), slots.begin(), slots.end());
  out.meta = gl::buffer::from_vector(meta);
  tq.end();
  timer.add("cdf (gpu)", tq.milliseconds(), "gpu");
  det["cdf"] = {{"backend", "gpu"},
                {"kernel", "vplkit/distribution/cdf_build.comp (double accumulation, one program per pass)"},
                {"distributions", dists},
                {"fallback", with_fallback ? "gpu (vpl_fallback_weights.comp + cdf_build.comp)" : "none (eps = 0)"},
                {"zeroed_weights", zeroed}};
  return out;
}

}  // namespace vplrender
