// SPDX-License-Identifier: MIT
#include "raster/gl_target.hpp"

#include <headless_gl/compute.hpp>

#include <cstddef>
#include <string>

namespace vplrender {

using vplkit::gl::check_gl;
using vplkit::gl::gl_error;

gl_target::~gl_target() { release(); }

void gl_target::ensure(int width, int height, int attachments) {
  if (fbo_ != 0 && w_ == width && h_ == height && attachments_ == attachments) return;
  if (attachments < 1 || attachments > 4)
    throw gl_error("vplrender: a render target has 1 to 4 colour attachments, not " + std::to_string(attachments));
  release();
  w_ = width;
  h_ = height;
  attachments_ = attachments;
  glGenFramebuffers(1, &fbo_);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glGenTextures(attachments_, color_);
  for (int i = 0; i < attachments_; ++i) {
    glBindTexture(GL_TEXTURE_2D, color_[i]);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, w_, h_);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i), GL_TEXTURE_2D, color_[i], 0);
  }
  glGenRenderbuffers(1, &depth_);
  glBindRenderbuffer(GL_RENDERBUFFER, depth_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, w_, h_);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
  vplkit::gl::track_gpu_bytes(bytes());
  const GLenum bufs[4] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2, GL_COLOR_ATTACHMENT3};
  glDrawBuffers(attachments_, bufs);
  const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    throw gl_error("vplrender: float render target " + std::to_string(w_) + "x" + std::to_string(h_) +
                   " is incomplete (status 0x" + std::to_string(status) + ")");
  check_gl("vplrender: render target");
}

void gl_target::clear() {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glViewport(0, 0, w_, h_);
  const float zero[4] = {0, 0, 0, 0};
  for (int i = 0; i < attachments_; ++i) glClearBufferfv(GL_COLOR, i, zero);
  const float one = 1.0f;
  glClearBufferfv(GL_DEPTH, 0, &one);
}

std::vector<float> gl_target::read(int i) const {
  std::vector<float> px(static_cast<std::size_t>(w_) * static_cast<std::size_t>(h_) * 4u);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
  glReadBuffer(GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i));
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, w_, h_, GL_RGBA, GL_FLOAT, px.data());
  check_gl("vplrender: read-back");
  return px;
}

void gl_target::release() {
  if (fbo_) vplkit::gl::track_gpu_bytes(-bytes());
  if (depth_) glDeleteRenderbuffers(1, &depth_);
  if (color_[0]) glDeleteTextures(attachments_, color_);
  if (fbo_) glDeleteFramebuffers(1, &fbo_);
  fbo_ = depth_ = 0;
  color_[0] = color_[1] = color_[2] = color_[3] = 0;
}

}  // namespace vplrender
