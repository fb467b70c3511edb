// SPDX-License-Identifier: MIT
#pragma once
// A float render target of the raster passes: 1-4 GL_RGBA32F colour textures (one level, nearest:
// shaders/surfels_from_targets.comp reads them with texelFetch) and a 32-bit float depth buffer in
// one framebuffer, read back per attachment. Kept from one frame to the next while the size stays;
// its bytes are counted with vplkit::gl::track_gpu_bytes. Needs the context current at creation.
#include <epoxy/gl.h>

#include <vector>

namespace vplrender {

class gl_target {
public:
  gl_target() = default;
  ~gl_target();
  gl_target(const gl_target&) = delete;
  gl_target& operator=(const gl_target&) = delete;

  // A target of width x height with `attachments` colour textures: this one when it has exactly
  // that size and count already, else a new one. Throws vplkit::gl::gl_error when the framebuffer
  // is incomplete or `attachments` is outside 1-4.
  void ensure(int width, int height, int attachments);
  // Binds the framebuffer with a viewport over the whole target; colours 0, depth 1.
  void clear();
  // Attachment i as width * height RGBA floats, GL row order (bottom row first).
  std::vector<float> read(int i) const;

  int width() const { return w_; }
  int height() const { return h_; }
  int attachments() const { return attachments_; }
  GLuint color(int i) const { return color_[i]; }
  // The RGBA32F textures and the 32-bit depth buffer.
  long long bytes() const { return static_cast<long long>(w_) * h_ * (attachments_ * 16 + 4); }

private:
  void release();
  GLuint fbo_ = 0, depth_ = 0;
  GLuint color_[4] = {0, 0, 0, 0};
  int attachments_ = 0;
  int w_ = 0, h_ = 0;
};

}  // namespace vplrender
