// SPDX-License-Identifier: MIT
#pragma once
// The buffers of cdf_build.comp (glsl/vplkit/distribution), bound at the kernel's bindings: the one
// layout the CDF-build parity tests and the GPU benchmark drive it with. Needs a current GL context.
#include <gl_kernels.hpp>

#include <vplkit/distribution/cdf_build_params.h>

namespace vplkit_test {

inline void bind_cdf_build(const vplkit::gl::buffer& weights, const vplkit::gl::buffer& cdf,
                           const vplkit::gl::buffer& guide, const vplkit::gl::buffer& blocks,
                           const vplkit::gl::buffer& info, const vplkit::gl::buffer& params) {
  bind({storage_at(VPLKIT_CDF_BUILD_BINDING_WEIGHTS, weights), storage_at(VPLKIT_CDF_BUILD_BINDING_CDF, cdf),
        storage_at(VPLKIT_CDF_BUILD_BINDING_GUIDE, guide), storage_at(VPLKIT_CDF_BUILD_BINDING_BLOCKS, blocks),
        storage_at(VPLKIT_CDF_BUILD_BINDING_INFO, info), uniform_at(VPLKIT_CDF_BUILD_BINDING_PARAMS, params)});
}

}  // namespace vplkit_test
